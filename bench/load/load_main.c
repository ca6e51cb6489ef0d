/* aalab_load CLI: evaluate load beside a GET /v1/health baseline (ratio), see aalab_load.c. */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "load.h"

static void print(const char *what, const load_result *r)
{
    printf("%-34s %9.0f req/s  p50 %7.1f us  p99 %7.1f us  (%ld requests in %.2f s, %ld errors)\n",
           what, r->rps, r->p50_us, r->p99_us, r->requests, r->seconds, r->errors);
}

int main(int argc, char **argv)
{
    load_config c = {.connections = 2, .requests = 200000, .seconds = 10};
    snprintf(c.method, sizeof c.method, "POST");
    snprintf(c.path, sizeof c.path, "/v1/evaluate");
    /* RGSS, the 4-sample rotated grid, sent as explicit samples. */
    c.body = "{\"pattern\":{\"kernels\":[[[-0.375,0.125,0.25],[0.125,0.375,0.25],"
             "[0.375,-0.125,0.25],[-0.125,-0.375,0.25]]]}}";
    c.has_body = true;
    bool only = false;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : "";
        if (!strcmp(a, "--socket"))
            snprintf(c.socket_path, sizeof c.socket_path, "%s", v), i++;
        else if (!strcmp(a, "--tcp")) {
            const char *colon = strrchr(v, ':');
            if (!colon)
                return 2;
            snprintf(c.tcp_host, sizeof c.tcp_host, "%.*s", (int)(colon - v), v);
            c.tcp_port = atoi(colon + 1);
            i++;
        } else if (!strcmp(a, "--connections"))
            c.connections = atoi(v), i++;
        else if (!strcmp(a, "--requests"))
            c.requests = atol(v), i++;
        else if (!strcmp(a, "--seconds"))
            c.seconds = atof(v), i++;
        else if (!strcmp(a, "--body"))
            c.body = v, i++;
        else if (!strcmp(a, "--token"))
            snprintf(c.token, sizeof c.token, "%s", v), i++;
        else if (!strcmp(a, "--vary"))
            c.vary = true;
        else if (!strcmp(a, "--only-evaluate"))
            only = true;
        else {
            fprintf(stderr, "usage: aalab_load --socket PATH | --tcp HOST:PORT [--connections N] "
                            "[--requests N] [--seconds S] [--body JSON] [--vary] [--token T] "
                            "[--only-evaluate]\n");
            return 2;
        }
    }
    if (!c.socket_path[0] && !c.tcp_port) {
        fprintf(stderr, "aalab_load: --socket or --tcp is required\n");
        return 2;
    }
    if (c.connections < 1 || c.requests < c.connections)
        return 2;
    load_result ev, base;
    if (load_run(&c, &ev)) {
        fprintf(stderr, "aalab_load: no successful request (is aalabd running?)\n");
        return 1;
    }
    char label[96];
    snprintf(label, sizeof label, "POST /v1/evaluate%s (%d conn)", c.vary ? " varied" : "",
             c.connections);
    print(label, &ev);
    if (only)
        return ev.errors ? 1 : 0;
    load_config h = c;
    snprintf(h.method, sizeof h.method, "GET");
    snprintf(h.path, sizeof h.path, "/v1/health");
    h.has_body = false;
    h.vary = false;
    if (load_run(&h, &base))
        return 1;
    snprintf(label, sizeof label, "GET /v1/health baseline (%d conn)", c.connections);
    print(label, &base);
    printf("evaluate / health throughput ratio: %.2f\n", ev.rps / base.rps);
    return ev.errors || base.errors ? 1 : 0;
}
