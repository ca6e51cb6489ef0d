/* aalab_load: HTTP/1.1 keep-alive load over aalabd's Unix socket (or TCP loopback).
 * N connections, each a thread sending one request at a time and reading the full answer;
 * stops after a request count or a time bound. Prints req/s and p50/p99 latency.
 *
 *   aalab_load --socket PATH [--tcp HOST:PORT] [--connections 2] [--requests 200000]
 *              [--seconds 10] [--method POST] [--path /v1/evaluate] [--body JSON]
 *              [--vary]   (appends a distinct "lp" per request: defeats the cache)
 *              [--token T]
 */
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include "load.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int connect_to(const load_config *c)
{
    int fd;
    if (c->tcp_port) {
        fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons((uint16_t)c->tcp_port)};
        inet_pton(AF_INET, c->tcp_host, &a.sin_addr);
        int one = 1;
        setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        if (connect(fd, (struct sockaddr *)&a, sizeof a)) {
            close(fd);
            return -1;
        }
    } else {
        fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        struct sockaddr_un a = {.sun_family = AF_UNIX};
        snprintf(a.sun_path, sizeof a.sun_path, "%.107s", c->socket_path);
        if (connect(fd, (struct sockaddr *)&a, sizeof a)) {
            close(fd);
            return -1;
        }
    }
    return fd;
}

/* Reads one response (headers + Content-Length body); returns the status or -1. The buffer
 * may hold the start of nothing else: one request in flight per connection. */
static int read_response(int fd, char *buf, size_t cap)
{
    size_t len = 0;
    char *end = NULL;
    while (!end) {
        ssize_t n = read(fd, buf + len, cap - len - 1);
        if (n <= 0)
            return -1;
        len += (size_t)n;
        buf[len] = 0;
        end = strstr(buf, "\r\n\r\n");
        if (!end && len >= cap - 1)
            return -1;
    }
    int status = atoi(buf + 9);
    size_t head = (size_t)(end + 4 - buf);
    size_t body = 0;
    for (char *p = buf; p < end; p++) {
        if ((p == buf || p[-1] == '\n') && !strncasecmp(p, "content-length:", 15)) {
            body = strtoul(p + 15, NULL, 10);
            break;
        }
    }
    size_t have = len - head;
    while (have < body) {
        ssize_t n = read(fd, buf, cap - 1 < body - have ? cap - 1 : body - have);
        if (n <= 0)
            return -1;
        have += (size_t)n;
    }
    return status;
}

typedef struct worker {
    const load_config *cfg;
    int index;
    double *lat;
    long done, errors;
    long limit;
    double deadline;
} worker;

static void *run_worker(void *arg)
{
    worker *w = arg;
    const load_config *c = w->cfg;
    int fd = connect_to(c);
    if (fd < 0) {
        w->errors++;
        return NULL;
    }
    size_t cap = 1 << 20;
    char *buf = malloc(cap);
    char *req = malloc(strlen(c->body) + 1024);
    char *body = malloc(strlen(c->body) + 128);
    for (long i = 0; i < w->limit; i++) {
        if ((i & 63) == 0 && now_s() > w->deadline)
            break;
        const char *b = c->body;
        if (c->vary) {
            /* A distinct body per request, same work (all default angles) plus an Lp norm:
             * {"pattern":...,"lp":2.000...k} misses the cache every time. */
            size_t bl = strlen(c->body);
            snprintf(body, bl + 128, "%.*s,\"lp\":%.12g}", (int)(bl - 1), c->body,
                     2 + (double)(i * c->connections + w->index) * 1e-7);
            b = body;
        }
        size_t blen = c->has_body ? strlen(b) : 0;
        int n = snprintf(req, strlen(c->body) + 1024,
                         "%s %s HTTP/1.1\r\nHost: localhost\r\n%s%s%s"
                         "Content-Type: application/json\r\nContent-Length: %zu\r\n\r\n",
                         c->method, c->path, c->token[0] ? "Authorization: Bearer " : "", c->token,
                         c->token[0] ? "\r\n" : "", blen);
        double t0 = now_s();
        if (write(fd, req, (size_t)n) != n || (blen && write(fd, b, blen) != (ssize_t)blen)) {
            w->errors++;
            break;
        }
        int status = read_response(fd, buf, cap);
        double t1 = now_s();
        if (status != 200) {
            w->errors++;
            if (status < 0)
                break;
            continue;
        }
        w->lat[w->done++] = t1 - t0;
    }
    close(fd);
    free(buf);
    free(req);
    free(body);
    return NULL;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int load_run(const load_config *c, load_result *out)
{
    memset(out, 0, sizeof *out);
    int n = c->connections;
    worker *w = calloc((size_t)n, sizeof *w);
    pthread_t *t = calloc((size_t)n, sizeof *t);
    long per = c->requests / n;
    double t0 = now_s();
    for (int i = 0; i < n; i++) {
        w[i] = (worker){.cfg = c, .index = i, .limit = per, .deadline = t0 + c->seconds};
        w[i].lat = malloc((size_t)per * sizeof(double));
        pthread_create(&t[i], NULL, run_worker, &w[i]);
    }
    long total = 0;
    for (int i = 0; i < n; i++) {
        pthread_join(t[i], NULL);
        total += w[i].done;
        out->errors += w[i].errors;
    }
    double elapsed = now_s() - t0;
    double *all = malloc((size_t)(total ? total : 1) * sizeof *all);
    long k = 0;
    for (int i = 0; i < n; i++) {
        memcpy(all + k, w[i].lat, (size_t)w[i].done * sizeof(double));
        k += w[i].done;
        free(w[i].lat);
    }
    qsort(all, (size_t)total, sizeof *all, cmp_double);
    out->requests = total;
    out->seconds = elapsed;
    out->rps = total / elapsed;
    out->p50_us = total ? all[total / 2] * 1e6 : 0;
    out->p99_us = total ? all[(long)(total * 0.99)] * 1e6 : 0;
    free(all);
    free(w);
    free(t);
    return total > 0 ? 0 : -1;
}
