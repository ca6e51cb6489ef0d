/* job_ctx: what a running job kind sees (job_kind.h). Progress and best-so-far go to memory at
 * once and to the store at most once every STORE_FLUSH_INTERVAL seconds, and only what changed
 * (a best pattern can be megabytes; the store writes a row per flush); the trace keeps every
 * improvement of best_e2 but at most 10 points a second (an improvement inside the 0.1 s window is
 * held back and written when the window opens or the job ends, so the last best is never lost).
 * The job's own fields (owner, visibility, clock, stop flags) are read here too, so that the
 * manager's files call into job_ctx.c and never the other way round, except for the scheduler's
 * yield point (jm_yield_point_locked, job_schedule.c). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <time.h>

#include "job_manager_impl.h"

#define TRACE_MIN_INTERVAL 0.1
#define STORE_FLUSH_INTERVAL 5.0

int job_live_init(job_live *l)
{
    *l = (job_live){0};
    l->trace = json_array();
    l->last_point_seconds = -INFINITY;
    l->last_append = -INFINITY;
    l->last_point_best = INFINITY;
    return l->trace ? AA_OK : AA_ENOMEM;
}

void job_live_clear(job_live *l)
{
    json_decref(l->best);
    json_decref(l->trace);
    json_decref(l->flushed_best);
    l->best = l->trace = l->flushed_best = NULL;
}

static void append_point(job_live *l, const job_trace_point *p)
{
    json_array_append_new(
        l->trace, json_pack("{s:f,s:I,s:I,s:o}", "seconds", p->seconds, "iterations",
                            (json_int_t)p->iterations, "evaluations", (json_int_t)p->evaluations,
                            "best_e2", isfinite(p->best_e2) ? json_real(p->best_e2) : json_null()));
    l->last_point_seconds = p->seconds;
    l->last_point_best = p->best_e2;
}

void job_live_flush_pending(job_live *l)
{
    if (l->have_pending) {
        append_point(l, &l->pending);
        l->have_pending = false;
    }
}

void job_ctx_flush_locked(job_ctx *ctx)
{
    ASSERT_LOCK_HELD(&ctx->jm->lock);
    job_live *l = ctx->live;
    l->last_flush = jm_now();
    double progress = l->progress;
    /* live.best is replaced, never modified, so the same pointer means the same best; a
     * new object with equal content is not written again either. */
    json_t *best = NULL;
    if (l->best && l->best != l->flushed_best && !json_equal(l->best, l->flushed_best)) {
        best = json_incref(l->best);
        json_decref(l->flushed_best);
        l->flushed_best = json_incref(l->best);
    }
    /* The trace only grows. */
    json_t *trace = NULL;
    if (json_array_size(l->trace) != l->flushed_trace_len) {
        trace = json_deep_copy(l->trace);
        l->flushed_trace_len = json_array_size(l->trace);
    }
    if (!best && !trace && progress == l->flushed_progress)
        return;
    l->flushed_progress = progress;
    pthread_mutex_unlock(ctx->lock);
    job_store_update_progress(ctx->store, ctx->id, progress, best, trace);
    json_decref(best);
    json_decref(trace);
    pthread_mutex_lock(ctx->lock);
}

static void maybe_flush_to_store(job_ctx *ctx)
{
    if (jm_now() - ctx->live->last_flush >= STORE_FLUSH_INTERVAL)
        job_ctx_flush_locked(ctx);
}

bool job_ctx_progress(job_ctx *ctx, double fraction, json_t *best_so_far)
{
    json_t *copy = best_so_far ? json_deep_copy(best_so_far) : NULL;
    pthread_mutex_lock(ctx->lock);
    if (isfinite(fraction))
        ctx->live->progress = fraction < 0 ? 0 : fraction > 1 ? 1 : fraction;
    if (copy) {
        json_decref(ctx->live->best);
        ctx->live->best = copy;
    }
    maybe_flush_to_store(ctx);
    jm_yield_point_locked(ctx); /* may wait here while another user's job has the worker */
    bool stop = jm_job_stop_locked(ctx);
    pthread_mutex_unlock(ctx->lock);
    return stop;
}

void job_ctx_trace(job_ctx *ctx, const job_trace_point *point)
{
    pthread_mutex_lock(ctx->lock);
    job_live *l = ctx->live;
    double now = point->seconds;
    /* Rate limit on the time of appending: at most one append per 0.1 s of job time. */
    if (l->have_pending && now - l->last_append >= TRACE_MIN_INTERVAL) {
        job_live_flush_pending(l);
        l->last_append = now;
    }
    double best = l->have_pending ? l->pending.best_e2 : l->last_point_best;
    bool improves = json_array_size(l->trace) == 0 || point->best_e2 < best;
    if (improves) {
        if (!l->have_pending && now - l->last_append >= TRACE_MIN_INTERVAL) {
            append_point(l, point);
            l->last_append = now;
        } else {
            l->pending = *point; /* newer and better than any held point */
            l->have_pending = true;
        }
    }
    pthread_mutex_unlock(ctx->lock);
}

bool job_ctx_cancelled(const job_ctx *ctx)
{
    pthread_mutex_lock(ctx->lock);
    bool stop = jm_job_stop_locked(ctx);
    pthread_mutex_unlock(ctx->lock);
    return stop;
}

aa_clock job_ctx_clock(job_ctx *ctx)
{
    return (aa_clock){jm_job_clock, ctx};
}

int job_ctx_workers(const job_ctx *ctx)
{
    /* Idle workers may lend their core to this job's own threads. */
    pthread_mutex_lock(ctx->lock);
    int idle = ctx->workers - *ctx->busy;
    pthread_mutex_unlock(ctx->lock);
    return idle > 0 ? idle + 1 : 1;
}

tile_store *job_ctx_tiles(job_ctx *ctx)
{
    return ctx->tiles;
}

double jm_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

bool jm_job_stop_locked(const job_ctx *ctx)
{
    const job *j = ctx->job;
    ASSERT_LOCK_HELD(&((job_manager *)ctx->jm)->lock);
    return j->cancel_requested || j->over_time || ((job_manager *)ctx->jm)->stopping;
}

long long job_ctx_owner(const job_ctx *ctx)
{
    return ctx->job->owner;
}

bool job_ctx_private(const job_ctx *ctx)
{
    return ctx->job->private_job;
}

double jm_job_clock(void *ctx_)
{
    const job_ctx *ctx = ctx_;
    const job *j = ctx->job;
    return aa_monotonic_seconds() - (double)atomic_load(&j->paused_ns) * 1e-9;
}

/* The context a job's thread hands its kind (or the Slurm driver). */
struct job_ctx job_ctx_of(job_manager *jm, job *j)
{
    return (struct job_ctx){.jm = jm,
                            .job = j,
                            .lock = &jm->lock,
                            .live = &j->live,
                            .store = jm->store,
                            .id = j->id,
                            .tiles = jm->cfg.tiles,
                            .workers = jm->cfg.workers,
                            .busy = &jm->busy,
                            .started = j->started,
                            .started_mono = aa_monotonic_seconds()};
}
