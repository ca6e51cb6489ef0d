/* What running evaluates on the compute pool costs over the Unix socket: the same daemon state
 * served in-process twice, with evaluates answered on the HTTP thread (pool off: the behaviour
 * before the pool) and on the compute pool (suspend, pool thread, resume), by keep-alive clients
 * sending an uncached 4-sample evaluate back to back; GET /v1/health (never pooled) as a
 * control. Prints req/s and p50/p99 per case and the pooled/inline ratios.
 *   bench_http_pool [--seconds S per case (default 2)] [--connections N (default 2)] */
#define _GNU_SOURCE
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include "aa_core.h"
#include "api_context.h"
#include "compute_pool.h"
#include "mhd_adapter.h"

#define MAX_LAT 2000000

static const char EVAL_BODY[] =
    "{\"pattern\":{\"kernels\":[[[-0.125,-0.375,0.25],[0.375,-0.125,0.25],[0.125,0.375,0.25],"
    "[-0.375,0.125,0.25]]]}}";

typedef struct client {
    const char *path;
    const char *request;
    double seconds;
    double *lat; /* microseconds */
    long n, errors;
} client;

/* One answer: headers, then Content-Length bytes. 0 on a 2xx. */
static int read_answer(int fd, char *buf, size_t cap)
{
    size_t have = 0;
    char *end = NULL;
    while (!end) {
        ssize_t r = recv(fd, buf + have, cap - 1 - have, 0);
        if (r <= 0)
            return -1;
        have += (size_t)r;
        buf[have] = 0;
        end = strstr(buf, "\r\n\r\n");
    }
    const char *cl = strcasestr(buf, "Content-Length:");
    size_t body = cl ? strtoul(cl + 15, NULL, 10) : 0, got = have - (size_t)(end + 4 - buf);
    while (got < body) {
        ssize_t r = recv(fd, buf, cap - 1, 0);
        if (r <= 0)
            return -1;
        got += (size_t)r;
    }
    return strncmp(buf, "HTTP/1.1 2", 10) ? -1 : 0;
}

static void *client_main(void *arg)
{
    client *c = arg;
    int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    struct sockaddr_un a = {.sun_family = AF_UNIX};
    snprintf(a.sun_path, sizeof a.sun_path, "%s", c->path);
    if (fd < 0 || connect(fd, (struct sockaddr *)&a, sizeof a)) {
        c->errors++;
        return NULL;
    }
    static _Thread_local char buf[65536];
    size_t len = strlen(c->request);
    double end = aa_monotonic_seconds() + c->seconds;
    while (c->n < MAX_LAT) {
        double t0 = aa_monotonic_seconds();
        if (t0 > end)
            break;
        if (send(fd, c->request, len, MSG_NOSIGNAL) != (ssize_t)len ||
            read_answer(fd, buf, sizeof buf)) {
            c->errors++;
            break;
        }
        c->lat[c->n++] = (aa_monotonic_seconds() - t0) * 1e6;
    }
    close(fd);
    return NULL;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef struct result {
    double rps, p50, p99;
    long errors;
} result;

static result run_case(api_context *ctx, const aalab_config *cfg, compute_pool *pool,
                       const char *sock, const char *request, double seconds, int conns)
{
    result res = {0};
    char msg[256];
    int fd = http_unix_socket_open(sock, "", msg, sizeof msg);
    http_listener *l =
        fd >= 0 ? http_listener_start(ctx, cfg, fd, true, pool, NULL, msg, sizeof msg) : NULL;
    if (!l) {
        fprintf(stderr, "bench_http_pool: %s\n", msg);
        exit(1);
    }
    client c[16];
    pthread_t t[16];
    double t0 = aa_monotonic_seconds();
    for (int i = 0; i < conns; i++) {
        c[i] = (client){.path = sock, .request = request, .seconds = seconds};
        c[i].lat = malloc(MAX_LAT * sizeof(double));
        pthread_create(&t[i], NULL, client_main, &c[i]);
    }
    long total = 0;
    for (int i = 0; i < conns; i++) {
        pthread_join(t[i], NULL);
        total += c[i].n;
        res.errors += c[i].errors;
    }
    double elapsed = aa_monotonic_seconds() - t0;
    double *all = malloc((size_t)(total ? total : 1) * sizeof(double));
    long k = 0;
    for (int i = 0; i < conns; i++) {
        memcpy(all + k, c[i].lat, (size_t)c[i].n * sizeof(double));
        k += c[i].n;
        free(c[i].lat);
    }
    qsort(all, (size_t)total, sizeof(double), cmp_double);
    res.rps = total / elapsed;
    res.p50 = total ? all[total / 2] : 0;
    res.p99 = total ? all[(long)(total * 0.99)] : 0;
    free(all);
    http_listener_quiesce(l);
    http_listener_stop(l);
    unlink(sock);
    return res;
}

int main(int argc, char **argv)
{
    double seconds = 2;
    int conns = 2;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--seconds"))
            seconds = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--connections"))
            conns = atoi(argv[i + 1]);
    }
    if (conns < 1 || conns > 16)
        conns = 2;
    char dir[] = "/tmp/bench-http-pool-XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    aalab_config cfg;
    config_defaults(&cfg);
    snprintf(cfg.state_dir, sizeof cfg.state_dir, "%s/state", dir);
    cfg.eval_cache = 0; /* every evaluate computes */
    aa_error err = {0};
    api_context *ctx = api_context_create(&cfg, &err);
    compute_pool *pool = compute_pool_create(cfg.compute_threads, 1000, 1000, 1024);
    if (!ctx || !pool) {
        fprintf(stderr, "bench_http_pool: %s\n", ctx ? "no pool" : err.message);
        return 1;
    }
    char sock[200], eval[512];
    snprintf(sock, sizeof sock, "%s/s.sock", dir);
    snprintf(eval, sizeof eval,
             "POST /v1/evaluate HTTP/1.1\r\nHost: localhost\r\nContent-Type: application/json\r\n"
             "Content-Length: %zu\r\n\r\n%s",
             strlen(EVAL_BODY), EVAL_BODY);
    const char *health = "GET /v1/health HTTP/1.1\r\nHost: localhost\r\n\r\n";
    printf("bench_http_pool: %d keep-alive connections, %.1f s per case, %d compute threads\n",
           conns, seconds, cfg.compute_threads);
    /* Inline and pooled alternate (twice) so drifting machine load hits both alike. */
    result r[2][2][2]; /* [round][evaluate/health][inline/pool] */
    for (int round = 0; round < 2; round++)
        for (int w = 0; w < 2; w++)
            for (int p = 0; p < 2; p++)
                r[round][w][p] =
                    run_case(ctx, &cfg, p ? pool : NULL, sock, w ? health : eval, seconds, conns);
    const char *what[2] = {"evaluate (uncached, 4 samples x 36 angles)", "GET /v1/health"};
    long errors = 0;
    for (int w = 0; w < 2; w++) {
        for (int p = 0; p < 2; p++) {
            result a = r[0][w][p], b = r[1][w][p];
            errors += a.errors + b.errors;
            printf("%-44s %-7s %9.0f req/s  p50 %7.1f us  p99 %7.1f us  (second round: %.0f "
                   "req/s, p50 %.1f us)\n",
                   what[w], p ? "pooled" : "inline", a.rps, a.p50, a.p99, b.rps, b.p50);
        }
        double ratio = (r[0][w][1].rps + r[1][w][1].rps) / (r[0][w][0].rps + r[1][w][0].rps);
        double lat = (r[0][w][1].p50 + r[1][w][1].p50) / (r[0][w][0].p50 + r[1][w][0].p50);
        printf("%-44s pooled/inline: %.2fx throughput, %.2fx p50 latency\n", what[w], ratio, lat);
    }
    compute_pool_destroy(pool);
    api_context_destroy(ctx);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "bench_http_pool: could not remove %s\n", dir);
    return errors ? 1 : 0;
}
