/* What the compute pool costs an uncached evaluate over the Unix socket, and what running small
 * evaluates on the HTTP thread (--inline-work) wins back. The same daemon state is served
 * in-process in three ways, one after another and alternated twice, by keep-alive clients sending
 * uncached evaluates back to back (each request its own "lp", so no cache could answer):
 *   direct   no compute pool: every evaluate on the HTTP thread (the daemon before the pool);
 *   pooled   every evaluate on the compute pool (suspend, pool thread, resume: --inline-work 0);
 *   adaptive this release: evaluates of at most --inline-work kernel samples x angles on the
 *            HTTP thread in the user's share, larger ones on the pool.
 * First RGSS (4 samples x 36 angles) and GET /v1/health (never pooled) as a control, with the
 * ratios to the direct path; then a size sweep (1 kernel of 16, 64, 256 samples) that shows
 * where the hand-off stops mattering, which is how the default threshold was chosen
 * (docs/http.md). Then the fairness half: a second user (uid 65534, a forked child; needs root)
 * floods with renders and with large evaluates while this process, the first user, sends small
 * evaluates on one connection; its p50/p99 with the pool (the direct path has no answer to a
 * flood: large evaluates and renders hold the HTTP threads). Target: p99 under 50 ms.
 *   bench_http_pool [--seconds S per case (default 2)] [--connections N (default 2)] */
#define _GNU_SOURCE
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include "aa_core.h"
#include "api_context.h"
#include "compute_pool.h"
#include "mhd_adapter.h"

#define MAX_LAT 2000000
#define FLOOD_UID 65534 /* nobody */

typedef enum { MODE_DIRECT, MODE_POOLED, MODE_ADAPTIVE, MODE_COUNT } serve_mode;
static const char *const mode_name[MODE_COUNT] = {"direct", "pooled", "adaptive"};

typedef struct client {
    const char *path;
    const char *body;    /* the evaluate's pattern body without its closing brace, or NULL */
    const char *request; /* a fixed request when body is NULL */
    double seconds;
    bool flood; /* keep going on non-2xx answers (pausing 50 ms on 429), record nothing */
    int seed;
    double *lat; /* microseconds */
    long n, errors;
} client;

/* One answer: headers, then Content-Length bytes. Returns the status, or -1. */
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
    int status = strncmp(buf, "HTTP/1.1 ", 9) ? -1 : atoi(buf + 9);
    const char *cl = strcasestr(buf, "Content-Length:");
    size_t body = cl ? strtoul(cl + 15, NULL, 10) : 0, got = have - (size_t)(end + 4 - buf);
    while (got < body) {
        ssize_t r = recv(fd, buf, cap - 1, 0);
        if (r <= 0)
            return -1;
        got += (size_t)r;
    }
    return status;
}

static int connect_unix(const char *path)
{
    int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    struct sockaddr_un a = {.sun_family = AF_UNIX};
    snprintf(a.sun_path, sizeof a.sun_path, "%s", path);
    if (fd >= 0 && connect(fd, (struct sockaddr *)&a, sizeof a)) {
        close(fd);
        return -1;
    }
    return fd;
}

static void *client_main(void *arg)
{
    client *c = arg;
    int fd = connect_unix(c->path);
    if (fd < 0) {
        c->errors++;
        return NULL;
    }
    static _Thread_local char buf[1 << 16], req[1 << 15];
    double end = aa_monotonic_seconds() + c->seconds;
    for (long i = 0; c->n < MAX_LAT; i++) {
        double t0 = aa_monotonic_seconds();
        if (t0 > end)
            break;
        size_t len;
        if (c->body) {
            /* A distinct lp per request (as aalab_load --vary): never a cache hit. */
            char body[1 << 14];
            int bl = snprintf(body, sizeof body, "%s,\"lp\":%.9f}", c->body,
                              2.0 + 1e-9 * (double)(i + 1) + 1e-3 * c->seed);
            len = (size_t)snprintf(req, sizeof req,
                                   "POST /v1/evaluate HTTP/1.1\r\nHost: localhost\r\n"
                                   "Content-Type: application/json\r\nContent-Length: %d\r\n\r\n%s",
                                   bl, body);
        } else {
            len = strlen(c->request);
            memcpy(req, c->request, len);
        }
        int status = -1;
        if (send(fd, req, len, MSG_NOSIGNAL) == (ssize_t)len)
            status = read_answer(fd, buf, sizeof buf);
        if (status < 0) {
            c->errors++;
            break;
        }
        if (c->flood) {
            if (status == 429)
                usleep(50000);
            continue;
        }
        if (status / 100 != 2) {
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

typedef struct bench {
    api_context *ctx;
    aalab_config cfg;
    compute_pool *pool;
    char sock[200];
} bench;

static http_listener *listen_in(bench *b, serve_mode mode)
{
    char msg[256];
    aalab_config cfg = b->cfg;
    cfg.inline_work = mode == MODE_ADAPTIVE ? b->cfg.inline_work : 0;
    int fd = http_unix_socket_open(b->sock, "", msg, sizeof msg);
    http_listener *l =
        fd >= 0 ? http_listener_start(b->ctx, &cfg, fd, true, mode == MODE_DIRECT ? NULL : b->pool,
                                      NULL, msg, sizeof msg)
                : NULL;
    if (!l) {
        fprintf(stderr, "bench_http_pool: %s\n", msg);
        exit(1);
    }
    chmod(b->sock, 0666); /* the flooding user connects too */
    return l;
}

static void unlisten(bench *b, http_listener *l)
{
    http_listener_quiesce(l);
    http_listener_stop(l);
    unlink(b->sock);
}

/* conns clients sending body (or request) for seconds; latencies pooled. */
static result measure(bench *b, const char *body, const char *request, double seconds, int conns)
{
    result res = {0};
    client c[16];
    pthread_t t[16];
    double t0 = aa_monotonic_seconds();
    for (int i = 0; i < conns; i++) {
        c[i] = (client){
            .path = b->sock, .body = body, .request = request, .seconds = seconds, .seed = i};
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
    return res;
}

static result run_case(bench *b, serve_mode mode, const char *body, const char *request,
                       double seconds, int conns)
{
    http_listener *l = listen_in(b, mode);
    result r = measure(b, body, request, seconds, conns);
    unlisten(b, l);
    return r;
}

/* An evaluate body of one kernel of n samples on a jittered grid, without the closing brace. */
static void kernel_body(char *out, size_t cap, int n)
{
    size_t len = (size_t)snprintf(out, cap, "{\"pattern\":{\"kernels\":[[");
    int side = 1;
    while (side * side < n)
        side++;
    for (int i = 0; i < n; i++) {
        double x = ((i % side) + 0.5 + 0.3 * ((i * 7) % 5 - 2) / 5.0) / side - 0.5;
        double y = ((i / side) + 0.5 + 0.3 * ((i * 3) % 5 - 2) / 5.0) / side - 0.5;
        len += (size_t)snprintf(out + len, cap - len, "%s[%.6f,%.6f,%.17g]", i ? "," : "", x, y,
                                1.0 / n);
    }
    snprintf(out + len, cap - len, "]]}");
}

/* The second user's flood, in a child that has become uid 65534: renders (512x512, 4096 spp
 * reference) on 3 connections and large evaluates (1 kernel of 256 samples x 2,048 angles, about
 * 30 ms each) on 3, each pausing 50 ms on a 429, for seconds. */
static pid_t start_flood(bench *b, double seconds)
{
    pid_t pid = fork();
    if (pid != 0)
        return pid;
    if (setgid(FLOOD_UID) || setuid(FLOOD_UID))
        _exit(2);
    static char big[1 << 14], render[1024];
    kernel_body(big, sizeof big - 64, 256);
    size_t bl = strlen(big);
    snprintf(big + bl, sizeof big - bl, ",\"angles\":2048");
    const char *rbody = "{\"pattern\":{\"preset\":\"rgss\"},\"scene\":{\"name\":\"siemens-star\","
                        "\"width\":512,\"height\":512,\"angle\":17},\"reference\":{\"spp\":4096}}";
    snprintf(render, sizeof render,
             "POST /v1/render HTTP/1.1\r\nHost: localhost\r\nContent-Type: application/json\r\n"
             "Content-Length: %zu\r\n\r\n%s",
             strlen(rbody), rbody);
    client c[6];
    pthread_t t[6];
    for (int i = 0; i < 6; i++) {
        c[i] = (client){.path = b->sock,
                        .body = i < 3 ? big : NULL,
                        .request = i < 3 ? NULL : render,
                        .seconds = seconds,
                        .flood = true,
                        .seed = 100 + i};
        pthread_create(&t[i], NULL, client_main, &c[i]);
    }
    for (int i = 0; i < 6; i++)
        pthread_join(t[i], NULL);
    _exit(0);
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
    if (!mkdtemp(dir) || chmod(dir, 0711)) {
        perror("mkdtemp");
        return 1;
    }
    bench b = {0};
    config_defaults(&b.cfg);
    snprintf(b.cfg.state_dir, sizeof b.cfg.state_dir, "%s/state", dir);
    b.cfg.eval_cache = 0; /* every evaluate computes */
    aa_error err = {0};
    b.ctx = api_context_create(&b.cfg, &err);
    b.pool =
        compute_pool_create(b.cfg.compute_threads, b.cfg.user_evaluates, b.cfg.user_renders, 1024);
    if (!b.ctx || !b.pool) {
        fprintf(stderr, "bench_http_pool: %s\n", b.ctx ? "no pool" : err.message);
        return 1;
    }
    snprintf(b.sock, sizeof b.sock, "%s/s.sock", dir);
    const char *rgss = "{\"pattern\":{\"kernels\":[[[-0.375,0.125,0.25],[0.125,0.375,0.25],"
                       "[0.375,-0.125,0.25],[-0.125,-0.375,0.25]]]}";
    const char *health = "GET /v1/health HTTP/1.1\r\nHost: localhost\r\n\r\n";
    printf("bench_http_pool: %d keep-alive connections, %.1f s per case, %d compute threads, "
           "--inline-work %zu, --user-evaluates %d\n",
           conns, seconds, b.cfg.compute_threads, b.cfg.inline_work, b.cfg.user_evaluates);
    /* The three modes alternate (twice) so drifting machine load hits them alike. */
    result r[2][2][MODE_COUNT]; /* [round][evaluate/health][mode] */
    for (int round = 0; round < 2; round++)
        for (int w = 0; w < 2; w++)
            for (int m = 0; m < MODE_COUNT; m++)
                r[round][w][m] =
                    run_case(&b, (serve_mode)m, w ? NULL : rgss, w ? health : NULL, seconds, conns);
    const char *what[2] = {"varied evaluate (RGSS, 4 x 36)", "GET /v1/health"};
    long errors = 0;
    for (int w = 0; w < 2; w++) {
        for (int m = 0; m < MODE_COUNT; m++) {
            result x = r[0][w][m], y = r[1][w][m];
            errors += x.errors + y.errors;
            printf("%-32s %-8s %8.0f / %8.0f req/s  p50 %6.1f / %6.1f us  p99 %7.1f / %7.1f us\n",
                   what[w], mode_name[m], x.rps, y.rps, x.p50, y.p50, x.p99, y.p99);
        }
        for (int m = MODE_POOLED; m < MODE_COUNT; m++) {
            double tput = (r[0][w][m].rps + r[1][w][m].rps) / (r[0][w][0].rps + r[1][w][0].rps);
            double p50 = (r[0][w][m].p50 + r[1][w][m].p50) / (r[0][w][0].p50 + r[1][w][0].p50);
            printf("%-32s %-8s / direct: %.2fx throughput, %.2fx p50%s\n", what[w], mode_name[m],
                   tput, p50,
                   w == 0 && m == MODE_ADAPTIVE
                       ? (tput >= 0.9 && p50 <= 1.2 ? "  (target >= 0.9x, <= 1.2x: met)"
                                                    : "  (target >= 0.9x, <= 1.2x: MISSED)")
                       : "");
        }
    }

    /* Size sweep: where the hand-off stops mattering. */
    static const int sizes[] = {16, 40, 64, 256};
    printf("\nsize sweep (1 kernel x 36 angles, varied; %.1f s per case):\n", seconds / 2);
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        char body[1 << 14];
        kernel_body(body, sizeof body, sizes[s]);
        result x[MODE_COUNT];
        for (int m = 0; m < MODE_COUNT; m++) {
            x[m] = run_case(&b, (serve_mode)m, body, NULL, seconds / 2, conns);
            errors += x[m].errors;
        }
        printf("  %3d samples (work %5d, %5zu B): p50 direct %7.1f us, pooled %7.1f us (+%.1f), "
               "adaptive %7.1f us (%s)\n",
               sizes[s], sizes[s] * 36, strlen(body), x[0].p50, x[1].p50, x[1].p50 - x[0].p50,
               x[2].p50,
               (size_t)sizes[s] * 36 <= b.cfg.inline_work && strlen(body) < 2000 ? "inline"
                                                                                 : "pool");
    }

    /* Fairness: a second user's floods. */
    printf("\nfloods from uid %d (3 render + 3 large-evaluate connections) against one "
           "connection of small evaluates from this uid (%.1f s each):\n",
           FLOOD_UID, 2 * seconds);
    if (geteuid() != 0) {
        printf("  SKIP: needs root to fork a second user\n");
    } else {
        /* Alternated twice, as above. */
        for (int k = 0; k < 4; k++) {
            serve_mode m = k % 2 ? MODE_ADAPTIVE : MODE_POOLED;
            http_listener *l = listen_in(&b, m);
            pid_t flood = start_flood(&b, 2 * seconds + 1.0);
            usleep(500000); /* the flood is running */
            result x = measure(&b, rgss, NULL, 2 * seconds, 1);
            int st = 0;
            waitpid(flood, &st, 0);
            /* The pool's last tasks resume connections of this listener: let them end first. */
            while (compute_pool_user_load(b.pool, COMPUTE_RENDER, FLOOD_UID) ||
                   compute_pool_user_load(b.pool, COMPUTE_EVALUATE, FLOOD_UID))
                usleep(10000);
            unlisten(&b, l);
            errors += x.errors;
            printf("  %-8s this user's evaluate: %7.0f req/s  p50 %8.1f us  p99 %9.1f us%s\n",
                   mode_name[m], x.rps, x.p50, x.p99,
                   x.p99 < 50000.0 ? "  (target < 50 ms: met)" : "  (target < 50 ms: MISSED)");
        }
    }
    compute_pool_destroy(b.pool);
    api_context_destroy(b.ctx);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "bench_http_pool: could not remove %s\n", dir);
    return errors ? 1 : 0;
}
