#define _GNU_SOURCE
#include "config.h"
#include "aalab_version.h"
#include "install_paths.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void set_path(char *dst, size_t cap, const char *a, const char *b)
{
    snprintf(dst, cap, "%s%s", a, b);
}

void config_defaults(aalab_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    bool root = geteuid() == 0;
    const char *rt = getenv("RUNTIME_DIRECTORY"); /* systemd RuntimeDirectory= */
    const char *xdg_rt = getenv("XDG_RUNTIME_DIR");
    if (rt && *rt && !strchr(rt, ':'))
        set_path(cfg->socket_path, sizeof cfg->socket_path, rt, "/aalabd.sock");
    else if (root)
        set_path(cfg->socket_path, sizeof cfg->socket_path, "/run/aalab", "/aalabd.sock");
    else if (xdg_rt && *xdg_rt)
        set_path(cfg->socket_path, sizeof cfg->socket_path, xdg_rt, "/aalab/aalabd.sock");
    else
        snprintf(cfg->socket_path, sizeof cfg->socket_path, "/tmp/aalab-%u/aalabd.sock",
                 (unsigned)geteuid());

    const char *st = getenv("STATE_DIRECTORY");
    const char *xdg_st = getenv("XDG_STATE_HOME");
    const char *home = getenv("HOME");
    if (st && *st && !strchr(st, ':'))
        set_path(cfg->state_dir, sizeof cfg->state_dir, st, "");
    else if (root)
        set_path(cfg->state_dir, sizeof cfg->state_dir, "/var/lib/aalab", "");
    else if (xdg_st && *xdg_st)
        set_path(cfg->state_dir, sizeof cfg->state_dir, xdg_st, "/aalab");
    else if (home && *home)
        set_path(cfg->state_dir, sizeof cfg->state_dir, home, "/.local/state/aalab");
    else
        snprintf(cfg->state_dir, sizeof cfg->state_dir, "/tmp/aalab-%u/state", (unsigned)geteuid());

    snprintf(cfg->web_dir, sizeof cfg->web_dir, "%s", install_default_web_dir());
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    cfg->workers = cores > 0 ? (int)(cores > 64 ? 64 : cores) : 2;
    cfg->http_threads = cfg->workers < 2 ? 2 : cfg->workers > 8 ? 8 : cfg->workers;
    cfg->queue_size = 64;
    cfg->user_quota = 16;
    cfg->max_body = 8u << 20;
    cfg->connection_limit = 256;
    cfg->connection_timeout = 30;
    cfg->request_timeout = 10;
    cfg->connection_memory = 64u << 10;
    cfg->eval_cache = 1024;
    cfg->tile_bytes = 256u << 20;
    cfg->render_max_pixels = 512 * 512;
    cfg->render_seconds = 20.0;
    cfg->user_workers = 0; /* auto: config_finish */
    cfg->job_slice = 60.0;
    cfg->max_job_seconds = 86400.0;
    cfg->test_kinds = false;
    cfg->compute_threads = cfg->workers * 2 < 4 ? 4 : cfg->workers * 2 > 32 ? 32 : cfg->workers * 2;
    cfg->user_evaluates = 2;
    cfg->inline_work = 2048;
    cfg->user_renders = 1;
    cfg->user_connections = 32;
    cfg->token_connections = 32;
    cfg->user_tokens = 32;
    cfg->user_body_bytes = 32u << 20;
    cfg->answer_timeout = 60;
    cfg->user_store_bytes = 256u << 20;
    cfg->keep_days = 90.0;
    cfg->max_spec_bytes = 2u << 20;
    cfg->slurm.max_tasks = CLUSTER_DEFAULT_MAX_TASKS;
    cfg->slurm.time_limit_minutes = CLUSTER_DEFAULT_TIME_LIMIT;
    cfg->slurm.poll_seconds = CLUSTER_DEFAULT_POLL;
    /* worker: "" until config_finish puts aalab-worker beside this executable. */
}

/* Defaults that follow from other flags. */
static void config_finish(aalab_config *cfg)
{
    if (cfg->user_workers <= 0)
        cfg->user_workers = cfg->workers / 2 > 1 ? cfg->workers / 2 : 1;
    if (!cfg->slurm.worker[0]) {
        /* aalab-worker is built and installed beside aalabd. */
        char exe[AALAB_PATH_MAX];
        ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
        char *slash = n > 0 ? (exe[n] = 0, strrchr(exe, '/')) : NULL;
        if (slash) {
            *slash = 0;
            snprintf(cfg->slurm.worker, sizeof cfg->slurm.worker, "%.4000s/aalab-worker", exe);
        } else {
            snprintf(cfg->slurm.worker, sizeof cfg->slurm.worker, "aalab-worker");
        }
    }
}

void config_usage(FILE *out)
{
    fprintf(out,
            "usage: aalabd [options]\n"
            "  --socket PATH        Unix socket (default $XDG_RUNTIME_DIR/aalab/aalabd.sock)\n"
            "  --tcp HOST:PORT      also listen on TCP (loopback only; e.g. 127.0.0.1:8765;\n"
            "                       every API request there needs a token: aalab token)\n"
            "  --state-dir DIR      jobs database, tokens, tiles (default ~/.local/state/aalab)\n"
            "  --workers N          job worker threads (default: cores)\n"
            "  --http-threads N     HTTP threads per listener (default: cores, 2..8)\n"
            "  --web-dir DIR        dashboard files served on the TCP listener\n"
            "  --queue-size N       queued jobs before 429 (default 64)\n"
            "  --user-quota N       queued+running jobs per user (default 16)\n"
            "  --socket-group NAME  group owning the socket (mode 0660)\n"
            "  --max-body BYTES     request body limit (default 8388608)\n"
            "  --connection-limit N  open connections per listener (default 256)\n"
            "  --connection-timeout S  idle connection timeout (default 30)\n"
            "  --request-timeout S  time to deliver one whole request, against slow clients\n"
            "                       (default 10)\n"
            "  --eval-cache N       cached evaluate answers, 0 = off (default 1024)\n"
            "  --tile-bytes B       tile store budget (default 268435456)\n"
            "  --render-max-pixels N  largest POST /v1/render tile (default 262144; larger\n"
            "                       renders go to a compare job)\n"
            "  --render-seconds S   reference time budget of POST /v1/render (default 20)\n"
            "sharing between users:\n"
            "  --user-workers N     workers one user holds while others wait (default: half\n"
            "                       the workers, at least 1)\n"
            "  --job-slice S        a running job yields its worker to a waiting user after S\n"
            "                       seconds (default 60)\n"
            "  --max-job-seconds S  ceiling on a job's max_seconds and running time\n"
            "                       (default 86400)\n"
            "  --compute-threads N  threads running evaluate and render requests (default:\n"
            "                       2 x cores, 4..32)\n"
            "  --user-evaluates N   running evaluates per user, 429 beyond (default 2)\n"
            "  --inline-work N      evaluates of at most N kernel samples x angles run on the\n"
            "                       HTTP thread, larger ones on the compute pool (default\n"
            "                       2048; 0: every evaluate on the pool)\n"
            "  --user-renders N     running renders per user, 429 beyond (default 1)\n"
            "  --user-connections N open connections per peer uid on each listener (default 32)\n"
            "  --token-connections N open connections per bearer token on TCP (default 32)\n"
            "  --user-tokens N      live bearer tokens per user, 403 beyond (default 32)\n"
            "  --user-body-bytes B  request bodies one user may have in flight, 429 beyond\n"
            "                       (default 33554432)\n"
            "  --answer-timeout S   an answer not read to its end within S seconds is cut off\n"
            "                       (default 60)\n"
            "  --user-store-bytes B stored job data per user (default 268435456)\n"
            "  --keep-days D        finished, unpinned jobs are deleted after D days (default 90)\n"
            "  --max-spec-bytes B   largest job spec, 413 beyond (default 2097152)\n"
            "Slurm executor (jobs with \"executor\": \"slurm\"; docs/cluster.md):\n"
            "  --slurm-shared-dir DIR  directory every node sees, for task files and outputs\n"
            "                       (default: unset = Slurm not configured)\n"
            "  --slurm-partition NAME  partition of the arrays (default: the cluster's default)\n"
            "  --slurm-max-tasks N  most shards (array elements) per stage (default 64)\n"
            "  --slurm-time-limit MIN  time limit per task, sbatch --time (default 60)\n"
            "  --slurm-sbatch-args \"ARGS\"  extra sbatch arguments, split on blanks, no shell\n"
            "                       (default: none)\n"
            "  --slurm-worker PATH  aalab-worker on the nodes (default: aalab-worker beside\n"
            "                       the aalabd executable)\n"
            "  --slurm-poll S       seconds between squeue polls (default 2)\n"
            "  --enable-test-kinds  offer the 'sleep' job kind (for tests; off by default)\n"
            "  --help, --version\n");
}

static int parse_long(const char *s, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

static int parse_seconds(const char *s, double lo, double hi, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end || !(v >= lo && v <= hi))
        return -1;
    *out = v;
    return 0;
}

static int parse_tcp(aalab_config *cfg, const char *arg)
{
    const char *colon = strrchr(arg, ':');
    long port;
    if (!colon || colon == arg || (size_t)(colon - arg) >= sizeof cfg->tcp_host ||
        parse_long(colon + 1, 1, 65535, &port))
        return -1;
    memcpy(cfg->tcp_host, arg, (size_t)(colon - arg));
    cfg->tcp_host[colon - arg] = 0;
    cfg->tcp_port = (int)port;
    return 0;
}

int config_parse_args(aalab_config *cfg, int argc, char **argv, FILE *out, FILE *err)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            config_usage(out);
            return 1;
        }
        if (!strcmp(a, "--version")) {
            fprintf(out, "aalabd %s\n", aalab_version_full);
            return 1;
        }
        if (!strcmp(a, "--enable-test-kinds")) {
            cfg->test_kinds = true;
            continue;
        }
        const char *v = NULL;
        const char *eq = strchr(a, '=');
        char name[40];
        if (!strncmp(a, "--", 2) && eq && (size_t)(eq - a) < sizeof name) {
            memcpy(name, a, (size_t)(eq - a));
            name[eq - a] = 0;
            v = eq + 1;
            a = name;
        } else if (i + 1 < argc) {
            v = argv[i + 1];
        }
        static const char *const known[] = {"--socket",
                                            "--tcp",
                                            "--state-dir",
                                            "--web-dir",
                                            "--socket-group",
                                            "--workers",
                                            "--http-threads",
                                            "--queue-size",
                                            "--user-quota",
                                            "--max-body",
                                            "--connection-limit",
                                            "--connection-timeout",
                                            "--request-timeout",
                                            "--eval-cache",
                                            "--tile-bytes",
                                            "--render-max-pixels",
                                            "--render-seconds",
                                            "--user-workers",
                                            "--job-slice",
                                            "--max-job-seconds",
                                            "--compute-threads",
                                            "--user-evaluates",
                                            "--inline-work",
                                            "--user-renders",
                                            "--user-connections",
                                            "--token-connections",
                                            "--user-tokens",
                                            "--user-body-bytes",
                                            "--answer-timeout",
                                            "--user-store-bytes",
                                            "--keep-days",
                                            "--max-spec-bytes",
                                            "--slurm-shared-dir",
                                            "--slurm-partition",
                                            "--slurm-max-tasks",
                                            "--slurm-time-limit",
                                            "--slurm-sbatch-args",
                                            "--slurm-worker",
                                            "--slurm-poll",
                                            NULL};
        bool is_known = false;
        for (size_t k = 0; known[k] && !is_known; k++)
            is_known = !strcmp(a, known[k]);
        if (!is_known) {
            fprintf(err, "aalabd: unknown option %s (see --help)\n", a);
            return -1;
        }
        long n;
        int bad = 0;
        bool consumed = !eq;
        if (!v) {
            fprintf(err, "aalabd: %s needs a value (see --help)\n", a);
            return -1;
        }
        if (!strcmp(a, "--socket"))
            bad = snprintf(cfg->socket_path, sizeof cfg->socket_path, "%s", v) >=
                  (int)sizeof cfg->socket_path;
        else if (!strcmp(a, "--tcp"))
            bad = parse_tcp(cfg, v);
        else if (!strcmp(a, "--state-dir"))
            bad = snprintf(cfg->state_dir, sizeof cfg->state_dir, "%s", v) >=
                  (int)sizeof cfg->state_dir;
        else if (!strcmp(a, "--web-dir"))
            bad = snprintf(cfg->web_dir, sizeof cfg->web_dir, "%s", v) >= (int)sizeof cfg->web_dir;
        else if (!strcmp(a, "--socket-group"))
            bad = snprintf(cfg->socket_group, sizeof cfg->socket_group, "%s", v) >=
                  (int)sizeof cfg->socket_group;
        else if (!strcmp(a, "--workers") && !(bad = parse_long(v, 1, 256, &n)))
            cfg->workers = (int)n;
        else if (!strcmp(a, "--http-threads") && !(bad = parse_long(v, 1, 64, &n)))
            cfg->http_threads = (int)n;
        else if (!strcmp(a, "--queue-size") && !(bad = parse_long(v, 1, 1000000, &n)))
            cfg->queue_size = (int)n;
        else if (!strcmp(a, "--user-quota") && !(bad = parse_long(v, 1, 1000000, &n)))
            cfg->user_quota = (int)n;
        else if (!strcmp(a, "--max-body") && !(bad = parse_long(v, 1024, 1L << 30, &n)))
            cfg->max_body = (size_t)n;
        else if (!strcmp(a, "--connection-limit") && !(bad = parse_long(v, 1, 100000, &n)))
            cfg->connection_limit = (int)n;
        else if (!strcmp(a, "--connection-timeout") && !(bad = parse_long(v, 1, 86400, &n)))
            cfg->connection_timeout = (int)n;
        else if (!strcmp(a, "--request-timeout") && !(bad = parse_long(v, 1, 86400, &n)))
            cfg->request_timeout = (int)n;
        else if (!strcmp(a, "--eval-cache") && !(bad = parse_long(v, 0, 1000000, &n)))
            cfg->eval_cache = (size_t)n;
        else if (!strcmp(a, "--tile-bytes") && !(bad = parse_long(v, 1, 1L << 40, &n)))
            cfg->tile_bytes = (size_t)n;
        else if (!strcmp(a, "--render-max-pixels") && !(bad = parse_long(v, 1, 1L << 24, &n)))
            cfg->render_max_pixels = n;
        else if (!strcmp(a, "--render-seconds"))
            bad = parse_seconds(v, 0.001, 86400.0, &cfg->render_seconds);
        else if (!strcmp(a, "--user-workers") && !(bad = parse_long(v, 1, 256, &n)))
            cfg->user_workers = (int)n;
        else if (!strcmp(a, "--job-slice"))
            bad = parse_seconds(v, 0.01, 86400.0, &cfg->job_slice);
        else if (!strcmp(a, "--max-job-seconds"))
            bad = parse_seconds(v, 1.0, 31.0 * 86400.0, &cfg->max_job_seconds);
        else if (!strcmp(a, "--compute-threads") && !(bad = parse_long(v, 1, 256, &n)))
            cfg->compute_threads = (int)n;
        else if (!strcmp(a, "--user-evaluates") && !(bad = parse_long(v, 1, 1024, &n)))
            cfg->user_evaluates = (int)n;
        else if (!strcmp(a, "--inline-work") && !(bad = parse_long(v, 0, 1L << 23, &n)))
            cfg->inline_work = (size_t)n;
        else if (!strcmp(a, "--user-renders") && !(bad = parse_long(v, 1, 1024, &n)))
            cfg->user_renders = (int)n;
        else if (!strcmp(a, "--user-connections") && !(bad = parse_long(v, 1, 100000, &n)))
            cfg->user_connections = (int)n;
        else if (!strcmp(a, "--token-connections") && !(bad = parse_long(v, 1, 100000, &n)))
            cfg->token_connections = (int)n;
        else if (!strcmp(a, "--user-tokens") && !(bad = parse_long(v, 1, 100000, &n)))
            cfg->user_tokens = (int)n;
        else if (!strcmp(a, "--user-body-bytes") && !(bad = parse_long(v, 4096, 1L << 40, &n)))
            cfg->user_body_bytes = (size_t)n;
        else if (!strcmp(a, "--answer-timeout") && !(bad = parse_long(v, 1, 86400, &n)))
            cfg->answer_timeout = (int)n;
        else if (!strcmp(a, "--user-store-bytes") && !(bad = parse_long(v, 4096, 1L << 50, &n)))
            cfg->user_store_bytes = (size_t)n;
        else if (!strcmp(a, "--keep-days"))
            bad = parse_seconds(v, 0.0001, 36500.0, &cfg->keep_days);
        else if (!strcmp(a, "--max-spec-bytes") && !(bad = parse_long(v, 1024, 1L << 30, &n)))
            cfg->max_spec_bytes = (size_t)n;
        else if (!strcmp(a, "--slurm-shared-dir"))
            bad = v[0] != '/' || snprintf(cfg->slurm.shared_dir, sizeof cfg->slurm.shared_dir, "%s",
                                          v) >= (int)sizeof cfg->slurm.shared_dir;
        else if (!strcmp(a, "--slurm-partition"))
            bad = snprintf(cfg->slurm.partition, sizeof cfg->slurm.partition, "%s", v) >=
                  (int)sizeof cfg->slurm.partition;
        else if (!strcmp(a, "--slurm-max-tasks") && !(bad = parse_long(v, 1, 100000, &n)))
            cfg->slurm.max_tasks = (int)n;
        else if (!strcmp(a, "--slurm-time-limit") && !(bad = parse_long(v, 1, 525600, &n)))
            cfg->slurm.time_limit_minutes = (int)n;
        else if (!strcmp(a, "--slurm-sbatch-args"))
            bad = snprintf(cfg->slurm.sbatch_args, sizeof cfg->slurm.sbatch_args, "%s", v) >=
                  (int)sizeof cfg->slurm.sbatch_args;
        else if (!strcmp(a, "--slurm-worker"))
            bad = !v[0] || snprintf(cfg->slurm.worker, sizeof cfg->slurm.worker, "%s", v) >=
                               (int)sizeof cfg->slurm.worker;
        else if (!strcmp(a, "--slurm-poll"))
            bad = parse_seconds(v, 0.05, 3600.0, &cfg->slurm.poll_seconds);
        else if (!bad) {
            fprintf(err, "aalabd: unknown option %s (see --help)\n", a);
            return -1;
        }
        if (bad) {
            fprintf(err, "aalabd: bad value '%s' for %s\n", v, a);
            return -1;
        }
        if (consumed)
            i++;
    }
    config_finish(cfg);
    return 0;
}
