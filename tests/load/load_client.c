/* A small closed-loop HTTP/1.1 load generator for aalabd over a Unix socket or TCP loopback:
 * N keep-alive connections, one thread each, each sending the same request back to back and
 * timing every answer. Prints requests/s and latency percentiles; any non-2xx answer or broken
 * connection counts as an error (and makes the exit status 1).
 *
 *   aalab_load (--unix PATH | --tcp 127.0.0.1:PORT) [--connections N] [--requests N | --seconds S]
 *              [--path /v1/evaluate] [--body JSON] [--method POST]
 */
#define _POSIX_C_SOURCE 200809L
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

typedef struct load_config {
    const char *unix_path;
    char tcp_host[64];
    int tcp_port;
    int connections;
    long requests;  /* total, 0 = use seconds */
    double seconds; /* duration when requests == 0 */
    char *request;  /* the whole request, sent verbatim */
    size_t request_len;
} load_config;

typedef struct worker {
    const load_config *cfg;
    long quota; /* requests for this connection (0: until the deadline) */
    double deadline;
    float *latency_us;
    long capacity;
    long done;
    long errors;
    long reconnects;
    pthread_t thread;
} worker;

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int connect_to(const load_config *cfg)
{
    int fd;
    if (cfg->unix_path) {
        struct sockaddr_un a;
        memset(&a, 0, sizeof a);
        a.sun_family = AF_UNIX;
        snprintf(a.sun_path, sizeof a.sun_path, "%s", cfg->unix_path);
        fd = socket(AF_UNIX, SOCK_STREAM, 0);
        if (fd < 0 || connect(fd, (struct sockaddr *)&a, sizeof a) < 0)
            goto fail;
    } else {
        struct sockaddr_in a;
        memset(&a, 0, sizeof a);
        a.sin_family = AF_INET;
        a.sin_port = htons((uint16_t)cfg->tcp_port);
        if (inet_pton(AF_INET, cfg->tcp_host, &a.sin_addr) != 1)
            return -1;
        fd = socket(AF_INET, SOCK_STREAM, 0);
        if (fd < 0 || connect(fd, (struct sockaddr *)&a, sizeof a) < 0)
            goto fail;
        int one = 1;
        setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    }
    struct timeval tv = {10, 0}; /* never hang: a stuck answer is an error */
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    return fd;
fail:
    if (fd >= 0)
        close(fd);
    return -1;
}

static int send_all(int fd, const char *p, size_t n)
{
    while (n > 0) {
        ssize_t w = send(fd, p, n, MSG_NOSIGNAL);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

/* Reads one response (Content-Length framed) into buf; returns the status or -1. Leftover bytes
 * of a following response cannot occur: one request is outstanding at a time. */
static int read_response(int fd, char *buf, size_t cap, int *keep_alive)
{
    size_t have = 0;
    char *end = NULL;
    while (!end) {
        if (have == cap - 1)
            return -1;
        ssize_t r = recv(fd, buf + have, cap - 1 - have, 0);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            return -1;
        have += (size_t)r;
        buf[have] = '\0';
        end = strstr(buf, "\r\n\r\n");
    }
    int status = 0;
    if (sscanf(buf, "HTTP/1.%*d %d", &status) != 1)
        return -1;
    *keep_alive = strstr(buf, "onnection: close") == NULL;
    const char *cl = strstr(buf, "ontent-Length:");
    if (!cl)
        cl = strstr(buf, "ontent-length:");
    if (!cl)
        return -1;
    size_t body = strtoul(cl + 14, NULL, 10);
    size_t header_len = (size_t)(end + 4 - buf);
    size_t got = have - header_len;
    while (got < body) {
        char sink[16384];
        size_t want = body - got < sizeof sink ? body - got : sizeof sink;
        ssize_t r = recv(fd, sink, want, 0);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            return -1;
        got += (size_t)r;
    }
    return status;
}

static void *worker_main(void *arg)
{
    worker *w = arg;
    char *buf = malloc(65536);
    int fd = -1;
    while (w->quota ? w->done < w->quota : now_seconds() < w->deadline) {
        if (fd < 0) {
            fd = connect_to(w->cfg);
            if (fd < 0) {
                w->errors++;
                nanosleep(&(struct timespec){0, 1000000}, NULL);
                continue;
            }
            w->reconnects++;
        }
        double t0 = now_seconds();
        int keep = 0;
        int status = -1;
        if (send_all(fd, w->cfg->request, w->cfg->request_len) == 0)
            status = read_response(fd, buf, 65536, &keep);
        double t1 = now_seconds();
        if (status < 200 || status > 299)
            w->errors++;
        if (status < 0 || !keep) {
            close(fd);
            fd = -1;
        }
        if (status < 0)
            continue;
        if (w->done == w->capacity) {
            w->capacity = w->capacity ? 2 * w->capacity : 65536;
            w->latency_us = realloc(w->latency_us, (size_t)w->capacity * sizeof(float));
        }
        w->latency_us[w->done++] = (float)((t1 - t0) * 1e6);
    }
    if (fd >= 0)
        close(fd);
    free(buf);
    return NULL;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static void usage(void)
{
    fprintf(stderr, "usage: aalab_load (--unix PATH | --tcp HOST:PORT) [--connections N] "
                    "[--requests N | --seconds S] [--method M] [--path P] [--body JSON]\n");
    exit(2);
}

int main(int argc, char **argv)
{
    load_config cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.connections = 2;
    cfg.seconds = 5;
    const char *path = "/v1/evaluate", *method = "POST";
    const char *body = "{\"pattern\":{\"kernels\":[[[-0.125,-0.375,0.25],[0.375,-0.125,0.25],"
                       "[0.125,0.375,0.25],[-0.375,0.125,0.25]]]}}";
    for (int i = 1; i < argc; i += 2) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v)
            usage();
        if (!strcmp(a, "--unix"))
            cfg.unix_path = v;
        else if (!strcmp(a, "--tcp")) {
            const char *colon = strrchr(v, ':');
            if (!colon || (size_t)(colon - v) >= sizeof cfg.tcp_host)
                usage();
            memcpy(cfg.tcp_host, v, (size_t)(colon - v));
            cfg.tcp_port = atoi(colon + 1);
        } else if (!strcmp(a, "--connections"))
            cfg.connections = atoi(v);
        else if (!strcmp(a, "--requests"))
            cfg.requests = atol(v);
        else if (!strcmp(a, "--seconds"))
            cfg.seconds = atof(v);
        else if (!strcmp(a, "--path"))
            path = v;
        else if (!strcmp(a, "--method"))
            method = v;
        else if (!strcmp(a, "--body"))
            body = v;
        else
            usage();
    }
    if ((!cfg.unix_path && !cfg.tcp_host[0]) || cfg.connections < 1 || cfg.connections > 1024)
        usage();
    int has_body = strcmp(method, "GET") != 0;
    size_t cap = strlen(body) + strlen(path) + 256;
    cfg.request = malloc(cap);
    int n = snprintf(cfg.request, cap, "%s %s HTTP/1.1\r\nHost: %s\r\n", method, path,
                     cfg.unix_path ? "localhost" : cfg.tcp_host);
    if (has_body)
        n += snprintf(cfg.request + n, cap - (size_t)n,
                      "Content-Type: application/json\r\nContent-Length: %zu\r\n\r\n%s",
                      strlen(body), body);
    else
        n += snprintf(cfg.request + n, cap - (size_t)n, "\r\n");
    cfg.request_len = (size_t)n;

    worker *ws = calloc((size_t)cfg.connections, sizeof *ws);
    double t0 = now_seconds();
    for (int i = 0; i < cfg.connections; i++) {
        ws[i].cfg = &cfg;
        ws[i].quota = cfg.requests ? cfg.requests / cfg.connections +
                                         (i < cfg.requests % cfg.connections ? 1 : 0)
                                   : 0;
        ws[i].deadline = t0 + cfg.seconds;
        pthread_create(&ws[i].thread, NULL, worker_main, &ws[i]);
    }
    long total = 0, errors = 0, reconnects = 0;
    for (int i = 0; i < cfg.connections; i++) {
        pthread_join(ws[i].thread, NULL);
        total += ws[i].done;
        errors += ws[i].errors;
        reconnects += ws[i].reconnects;
    }
    double elapsed = now_seconds() - t0;
    float *all = malloc((size_t)(total ? total : 1) * sizeof(float));
    long k = 0;
    for (int i = 0; i < cfg.connections; i++) {
        memcpy(all + k, ws[i].latency_us, (size_t)ws[i].done * sizeof(float));
        k += ws[i].done;
        free(ws[i].latency_us);
    }
    qsort(all, (size_t)total, sizeof(float), cmp_float);
    double p50 = total ? all[(long)(0.50 * (double)(total - 1))] : 0;
    double p99 = total ? all[(long)(0.99 * (double)(total - 1))] : 0;
    double pmax = total ? all[total - 1] : 0;
    printf("{\"transport\":\"%s\",\"connections\":%d,\"requests\":%ld,\"errors\":%ld,"
           "\"connects\":%ld,\"seconds\":%.3f,\"req_per_s\":%.0f,\"p50_us\":%.1f,"
           "\"p99_us\":%.1f,\"max_us\":%.1f}\n",
           cfg.unix_path ? "unix" : "tcp", cfg.connections, total, errors, reconnects, elapsed,
           total / elapsed, p50, p99, pmax);
    free(all);
    free(ws);
    free(cfg.request);
    return errors ? 1 : 0;
}
