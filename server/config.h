/* Daemon configuration: embedded defaults (so `aalabd` alone starts) overridden by flags. */
#ifndef AALAB_CONFIG_H
#define AALAB_CONFIG_H

#define AALAB_PATH_MAX 4096
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "cluster_config.h"

typedef struct aalab_config {
    char socket_path[AALAB_PATH_MAX];
    char tcp_host[64]; /* "" = no TCP listener */
    int tcp_port;
    char state_dir[AALAB_PATH_MAX];
    char web_dir[AALAB_PATH_MAX];
    char socket_group[64]; /* "" = keep the primary group */
    int workers;           /* job worker threads */
    int http_threads;      /* libmicrohttpd thread pool per listener */
    int queue_size;        /* queued jobs beyond which POST /v1/jobs answers 429 */
    int user_quota;        /* queued + running jobs per user */
    size_t max_body;       /* request body limit in bytes (413 beyond) */
    int connection_limit;
    int connection_timeout;   /* seconds of inactivity */
    int request_timeout;      /* seconds to deliver one whole request (slowloris bound) */
    size_t connection_memory; /* per-connection memory (headers and buffers) */
    size_t eval_cache;        /* entries of the evaluate cache, 0 = off */
    size_t tile_bytes;        /* tile store budget */
    long render_max_pixels;   /* largest tile POST /v1/render draws (larger: a compare job) */
    double render_seconds;    /* wall-time budget of one POST /v1/render reference */

    /* Sharing one daemon between users (README, "Access and fair share"). */
    int user_workers;        /* workers one user may hold while others wait; 0 = auto
                              * (half the workers, at least 1; resolved by config_finish) */
    double job_slice;        /* seconds a job runs before it yields to a waiting user */
    double max_job_seconds;  /* ceiling on a job's max_seconds and on its running time */
    bool test_kinds;         /* the "sleep" test kind is available (tests only) */
    int compute_threads;     /* threads of the evaluate/render pool */
    int user_evaluates;      /* running evaluates per user (429 beyond) */
    size_t inline_work;      /* evaluates up to this work run on the HTTP thread; 0 = never */
    int user_renders;        /* running renders per user (429 beyond) */
    int user_connections;    /* open connections per peer uid, each listener */
    int token_connections;   /* open connections per bearer token on TCP */
    int user_tokens;         /* live bearer tokens per user (403 beyond) */
    size_t user_body_bytes;  /* request bodies one user may have in flight (429 beyond) */
    int answer_timeout;      /* seconds to deliver one answer, however slowly read */
    size_t user_store_bytes; /* stored job bytes per user */
    double keep_days;        /* finished, unpinned jobs older than this are deleted */
    size_t max_spec_bytes;   /* a job spec above this is refused with 413 */
    cluster_config slurm;    /* the Slurm executor (--slurm-*); shared_dir "" = not configured */
} aalab_config;

/* Embedded defaults: socket under $RUNTIME_DIRECTORY / $XDG_RUNTIME_DIR (or /run/aalab as root),
 * state under $STATE_DIRECTORY / $XDG_STATE_HOME / ~/.local/state (or /var/lib/aalab as root),
 * workers = online cores. */
void config_defaults(aalab_config *cfg);
/* Parses flags; returns 0, 1 when --help/--version was printed, -1 on error (message on err).
 * Values that depend on others (user_workers = auto) are resolved before it returns 0. */
int config_parse_args(aalab_config *cfg, int argc, char **argv, FILE *out, FILE *err);
void config_usage(FILE *out);

#endif
