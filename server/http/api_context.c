#define _GNU_SOURCE
#include "api_context.h"
#include "body_budget.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "eval_cache.h"
#include "group_membership.h"
#include "job_manager.h"
#include "kind_schemas.h"
#include "token_store.h"
#include "job_retention.h"
#include "tile_store.h"

struct api_context {
    aalab_config cfg;
    job_manager *jobs;
    job_retention *retention;
    eval_cache *cache;
    body_budget *bodies; /* request bodies in flight per user (--user-body-bytes) */
    struct tile_store *tiles;
    token_store *tokens;
    group_membership *group;  /* NULL: tokens are not tied to a group */
    bool socket_access_known; /* the socket file's owner and mode below were read at start */
    uid_t socket_owner;
    mode_t socket_mode;
    char *kinds_body; /* GET /v1/kinds, encoded once: the schemas are embedded */
    double started;   /* aa_monotonic_seconds */
    int lock_fd;      /* flock on <state-dir>/lock: one daemon per state directory */
};

/* mkdir -p with mode for the last component. */
static int make_dirs(const char *path, mode_t mode)
{
    char tmp[PATH_MAX];
    if (snprintf(tmp, sizeof tmp, "%s", path) >= (int)sizeof tmp)
        return -1;
    for (char *p = tmp + 1; *p; p++) {
        if (*p == '/') {
            *p = 0;
            if (mkdir(tmp, 0755) && errno != EEXIST)
                return -1;
            *p = '/';
        }
    }
    if (mkdir(tmp, mode) && errno != EEXIST)
        return -1;
    return 0;
}

api_context *api_context_create(const aalab_config *cfg, aa_error *err)
{
    api_context *ctx = calloc(1, sizeof *ctx);
    if (!ctx) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    ctx->cfg = *cfg;
    ctx->lock_fd = -1;
    ctx->started = aa_monotonic_seconds();
    /* GET /v1/kinds serves every kind's schemas: a build without them must not start. */
    if (kind_schemas_check(err))
        goto fail;
    if (make_dirs(cfg->state_dir, 0700)) {
        aa_error_set(err, AA_EINVAL, "state_dir", "cannot create %s: %s", cfg->state_dir,
                     strerror(errno));
        goto fail;
    }
    char lock_path[AALAB_PATH_MAX + 8];
    snprintf(lock_path, sizeof lock_path, "%s/lock", cfg->state_dir);
    ctx->lock_fd = open(lock_path, O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0600);
    if (ctx->lock_fd < 0 || flock(ctx->lock_fd, LOCK_EX | LOCK_NB)) {
        aa_error_set(err, AA_EINVAL, "state_dir", "state directory %s is in use by another aalabd",
                     cfg->state_dir);
        goto fail;
    }
    /* <state-dir>/token, a daemon-wide token of older daemons, admits nothing: its secret is
     * not left lying around. */
    char old_token[AALAB_PATH_MAX + 8];
    snprintf(old_token, sizeof old_token, "%s/token", cfg->state_dir);
    unlink(old_token);
    ctx->tokens = token_store_open(cfg->state_dir, err);
    if (!ctx->tokens)
        goto fail;
    ctx->cache = eval_cache_create(cfg->eval_cache);
    ctx->bodies = body_budget_create(cfg->user_body_bytes);
    if (!ctx->bodies) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        goto fail;
    }
    ctx->tiles = tile_store_create(cfg->state_dir, cfg->tile_bytes, err);
    if (!ctx->tiles)
        goto fail;
    job_manager_config jc = {.workers = cfg->workers,
                             .queue_size = cfg->queue_size,
                             .user_quota = cfg->user_quota,
                             .tiles = ctx->tiles,
                             .test_kinds = cfg->test_kinds,
                             .user_workers = cfg->user_workers,
                             .slice_seconds = cfg->job_slice,
                             .max_job_seconds = cfg->max_job_seconds,
                             .user_store_bytes = (long long)cfg->user_store_bytes,
                             .cluster = cfg->slurm};
    ctx->jobs = job_manager_create(cfg->state_dir, &jc, err);
    if (!ctx->jobs)
        goto fail;
    ctx->kinds_body = kind_schemas_document(ctx->jobs);
    if (!ctx->kinds_body) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        goto fail;
    }
    ctx->retention = job_retention_start(job_manager_store(ctx->jobs), cfg->keep_days, err);
    if (!ctx->retention)
        goto fail;
    return ctx;
fail:
    api_context_destroy(ctx);
    return NULL;
}

void api_context_shutdown(api_context *ctx)
{
    if (ctx && ctx->jobs)
        job_manager_shutdown(ctx->jobs);
}

void api_context_destroy(api_context *ctx)
{
    if (!ctx)
        return;
    job_retention_stop(ctx->retention);
    job_manager_destroy(ctx->jobs);
    tile_store_destroy(ctx->tiles);
    eval_cache_destroy(ctx->cache);
    body_budget_destroy(ctx->bodies);
    token_store_close(ctx->tokens);
    group_membership_destroy(ctx->group);
    free(ctx->kinds_body);
    if (ctx->lock_fd >= 0)
        close(ctx->lock_fd);
    free(ctx);
}

const aalab_config *api_context_config(const api_context *ctx)
{
    return &ctx->cfg;
}

const char *api_context_kinds_body(const api_context *ctx)
{
    return ctx->kinds_body;
}

struct tile_store *api_context_tiles(api_context *ctx)
{
    return ctx->tiles;
}

struct job_manager *api_context_jobs(api_context *ctx)
{
    return ctx->jobs;
}

struct eval_cache *api_context_eval_cache(api_context *ctx)
{
    return ctx->cache;
}

struct body_budget *api_context_body_budget(api_context *ctx)
{
    return ctx->bodies;
}

struct token_store *api_context_tokens(api_context *ctx)
{
    return ctx->tokens;
}

int api_context_tie_tokens_to_group(api_context *ctx, gid_t gid)
{
    group_membership_destroy(ctx->group);
    ctx->group = group_membership_create(gid);
    return ctx->group ? AA_OK : AA_ENOMEM;
}

bool api_context_token_owner_ok(api_context *ctx, long long uid)
{
    return !ctx->group || group_membership_check(ctx->group, uid);
}

void api_context_tie_socket_access(api_context *ctx, uid_t owner, mode_t mode)
{
    ctx->socket_owner = owner;
    ctx->socket_mode = mode;
    ctx->socket_access_known = true;
}

bool api_context_socket_peer_ok(api_context *ctx, long long uid)
{
    if (!ctx->socket_access_known || !ctx->group || (ctx->socket_mode & S_IWOTH))
        return true;
    return uid == 0 || uid == (long long)ctx->socket_owner ||
           group_membership_check(ctx->group, uid);
}

double api_context_uptime(const api_context *ctx)
{
    return aa_monotonic_seconds() - ctx->started;
}
