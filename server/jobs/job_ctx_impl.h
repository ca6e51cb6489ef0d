/* The job_ctx behind job_kind.h: made by job_ctx_of (job_ctx.c) for the manager's job threads
 * (job_schedule.c, job_slurm.c) and read through the job_ctx_* functions of job_ctx.c. */
#ifndef AALAB_JOB_CTX_IMPL_H
#define AALAB_JOB_CTX_IMPL_H

#include <pthread.h>
#include <stdbool.h>

#include <jansson.h>

#include "job_kind.h"
#include "job_store.h"

/* Progress, best-so-far and trace of one job; guarded by the manager's lock. */
typedef struct job_live {
    double progress;
    json_t *best;  /* NULL until the kind reports one */
    json_t *trace; /* array of trace points */
    double last_point_seconds;
    double last_append; /* job time of the last append (the rate limit's clock) */
    double last_point_best;
    bool have_pending;
    job_trace_point pending; /* an improvement held back by the 10 points/s limit */
    double last_flush;       /* wall time of the last store write */
    /* What the last store write held, so an unchanged best or trace is not written again. */
    json_t *flushed_best;
    size_t flushed_trace_len;
    double flushed_progress;
} job_live;

int job_live_init(job_live *l);
void job_live_clear(job_live *l);
/* Appends the held-back improvement, if any (at the end of a run). */
void job_live_flush_pending(job_live *l);

struct job_manager;
struct job;

struct job_ctx {
    struct job_manager *jm;
    struct job *job;
    pthread_mutex_t *lock; /* the manager's */
    job_live *live;
    job_store *store;
    long long id;
    tile_store *tiles;
    int workers;
    int *busy;
    double started;      /* wall clock (Unix seconds) */
    double started_mono; /* aa_monotonic_seconds (clock.h) */
};

double jm_now(void); /* Unix seconds, CLOCK_REALTIME: stored timestamps; durations and budgets
                      * use the monotonic aa_monotonic_seconds (clock.h) */

/* Called by job_ctx_progress with the lock held: enforces --max-job-seconds and, when the job's
 * slice is over and another user waits with fewer workers, checkpoints the live state, gives the
 * worker back and waits (lock released) until the scheduler hands one back or the job must
 * stop. */
void jm_yield_point_locked(job_ctx *ctx);
/* Lock held: cancelled, over --max-job-seconds, or the daemon is stopping. */
bool jm_job_stop_locked(const job_ctx *ctx);
/* The job's clock (job_ctx_clock): monotonic seconds less the time spent paused. */
double jm_job_clock(void *ctx);
/* Writes progress, best and trace to the store now (lock held; released during the write). */
void job_ctx_flush_locked(job_ctx *ctx);

#endif
