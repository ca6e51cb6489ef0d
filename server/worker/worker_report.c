/* The trace file of a shard run by aalab-worker (worker_report.h). */
#define _POSIX_C_SOURCE 200809L
#include "worker_report.h"

#include <math.h>
#include <string.h>
#include <time.h>

#include "aa_core.h"
#include "cluster_layout.h"
#include "lock_held.h"

#define TRACE_WRITE_INTERVAL 2.0 /* seconds between rewrites of the trace file */
#define POINT_MIN_INTERVAL 0.1   /* as the daemon's job trace: at most 10 points a second */

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

void worker_report_init(worker_report *r, const char *trace_path, volatile sig_atomic_t *stop)
{
    memset(r, 0, sizeof *r);
    r->trace_path = trace_path;
    r->started_unix = wall_seconds();
    r->started_mono = aa_monotonic_seconds();
    r->stop = stop;
    r->points = json_array();
    r->last_append = -1;
    r->last_write = r->started_mono;
    pthread_mutex_init(&r->lock, NULL);
}

void worker_report_free(worker_report *r)
{
    json_decref(r->points);
    pthread_mutex_destroy(&r->lock);
}

static json_t *real_or_null(double v)
{
    return isfinite(v) ? json_real(v) : json_null();
}

/* Under lock. */
static int write_locked(worker_report *r, aa_error *err)
{
    ASSERT_LOCK_HELD(&r->lock);
    json_t *j = json_pack("{s:s,s:o,s:o,s:O}", "format", "aalab-shard-trace/1", "started_unix",
                          json_real(r->started_unix), "progress", json_real(r->progress), "points",
                          r->points ? r->points : json_array());
    if (!j)
        return aa_error_set(err, AA_ENOMEM, "trace", "out of memory");
    int rc = cluster_write_json(r->trace_path, j, err);
    json_decref(j);
    r->last_write = aa_monotonic_seconds();
    return rc;
}

int worker_report_write(worker_report *r, aa_error *err)
{
    pthread_mutex_lock(&r->lock);
    int rc = write_locked(r, err);
    pthread_mutex_unlock(&r->lock);
    return rc;
}

/* Rewrites the trace when its interval has passed; a failure stops the shard. */
static void maybe_write_locked(worker_report *r)
{
    ASSERT_LOCK_HELD(&r->lock);
    if (r->write_failed || aa_monotonic_seconds() - r->last_write < TRACE_WRITE_INTERVAL)
        return;
    if (write_locked(r, &r->err))
        r->write_failed = 1;
}

static bool report_progress(void *user, double fraction, json_t *best_so_far)
{
    (void)best_so_far; /* the output carries the shard's best; the daemon reads that */
    worker_report *r = user;
    pthread_mutex_lock(&r->lock);
    if (fraction > r->progress)
        r->progress = fmin(fraction, 1);
    maybe_write_locked(r);
    bool stop = r->write_failed || *r->stop;
    pthread_mutex_unlock(&r->lock);
    return stop;
}

static void report_trace(void *user, const job_trace_point *p)
{
    worker_report *r = user;
    pthread_mutex_lock(&r->lock);
    json_t *pt = json_pack("{s:o,s:I,s:I,s:o}", "seconds", json_real(p->seconds), "iterations",
                           (json_int_t)p->iterations, "evaluations", (json_int_t)p->evaluations,
                           "best_e2", real_or_null(p->best_e2));
    size_t n = json_array_size(r->points);
    if (pt && n && p->seconds - r->last_append < POINT_MIN_INTERVAL) {
        json_array_set_new(r->points, n - 1, pt); /* newer and at least as good */
    } else if (pt) {
        json_array_append_new(r->points, pt);
        r->last_append = p->seconds;
    }
    maybe_write_locked(r);
    pthread_mutex_unlock(&r->lock);
}

static double report_clock(void *user)
{
    (void)user;
    return aa_monotonic_seconds();
}

shard_ctx worker_report_ctx(worker_report *r, int workers)
{
    return (shard_ctx){report_progress, report_trace, r, {report_clock, NULL}, workers};
}
