/* The job manager's scheduler (job_manager_impl.h): the queue, the hand-out of workers by fair
 * share (fair_share.h), the slices after which a job yields its worker, one thread per started
 * job and the final write of its outcome, retried while the store cannot take it. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cluster_driver.h"
#include "job_manager_impl.h"
#include "wire_error.h"

#define YIELD_CHECK_EVERY 0.25 /* seconds between fair-share checks once a slice is over */
/* A job's final write is retried with doubling pauses from FINAL_RETRY_FIRST for about
 * FINAL_RETRY_SECONDS; then its outcome is dropped and a small failed (unavailable) record is
 * retried every FINAL_RETRY_SLOW seconds until the store takes it. */
#define FINAL_RETRY_FIRST 0.05
#define FINAL_RETRY_SECONDS 6.0
#define FINAL_RETRY_SLOW 1.0

static void *job_thread(void *arg);

int jm_start_detached(void *(*fn)(void *), void *arg)
{
    pthread_attr_t attr;
    pthread_t t;
    int rc = pthread_attr_init(&attr);
    if (!rc) {
        pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
        rc = pthread_create(&t, &attr, fn, arg);
        pthread_attr_destroy(&attr);
    }
    return rc;
}

int jm_queue_push(job_manager *jm, job *j)
{
    if (jm->q_len == jm->q_cap) {
        size_t cap = jm->q_cap ? jm->q_cap * 2 : 64;
        job **q = realloc(jm->queue, cap * sizeof *q);
        if (!q)
            return AA_ENOMEM;
        jm->queue = q;
        jm->q_cap = cap;
    }
    jm->queue[jm->q_len++] = j;
    return AA_OK;
}

void jm_queue_remove(job_manager *jm, job *j)
{
    ASSERT_LOCK_HELD(&jm->lock);
    for (size_t i = 0; i < jm->q_len; i++) {
        if (jm->queue[i] == j) {
            memmove(jm->queue + i, jm->queue + i + 1, (jm->q_len - i - 1) * sizeof *jm->queue);
            jm->q_len--;
            return;
        }
    }
}

void jm_active_remove(job_manager *jm, job *j)
{
    ASSERT_LOCK_HELD(&jm->lock);
    for (job **p = &jm->active; *p; p = &(*p)->next) {
        if (*p == j) {
            *p = j->next;
            return;
        }
    }
}

job *jm_active_find(job_manager *jm, long long id)
{
    ASSERT_LOCK_HELD(&jm->lock);
    for (job *j = jm->active; j; j = j->next)
        if (j->id == id)
            return j;
    return NULL;
}

/* The fair-share view of the active jobs (fair_share.h); NULL when out of memory. */
static fs_job *snapshot_locked(job_manager *jm, size_t *n, job ***order)
{
    ASSERT_LOCK_HELD(&jm->lock);
    size_t count = 0;
    /* Admitted jobs not yet in the store are not schedulable, nor are Slurm jobs (their
     * threads need no worker). */
    for (job *j = jm->active; j; j = j->next)
        count += j->id > 0 && !j->slurm && !j->unstored && !j->cancelling;
    if (count > jm->snapshot_cap || !jm->snapshot) {
        size_t cap = count < 8 ? 16 : count * 2;
        fs_job *s = realloc(jm->snapshot, cap * (sizeof *s + sizeof(job *)));
        if (!s)
            return NULL;
        jm->snapshot = s;
        jm->snapshot_cap = cap;
    }
    job **jobs = (job **)(void *)(jm->snapshot + jm->snapshot_cap);
    size_t i = 0;
    for (job *j = jm->active; j; j = j->next) {
        if (j->id <= 0 || j->slurm || j->unstored || j->cancelling)
            continue;
        jobs[i] = j;
        jm->snapshot[i] = (fs_job){.owner = j->owner,
                                   .priority = j->priority,
                                   .running = j->holds_worker,
                                   .paused = j->paused,
                                   .served = j->served,
                                   .id = j->id};
        i++;
    }
    *n = i;
    *order = jobs;
    return jm->snapshot;
}

/* Hands free workers to waiting jobs, by fair share: a paused job is woken, a queued one gets
 * a thread of its own. Called with the lock held after anything that frees a worker or adds a
 * waiting job. */
void jm_schedule_locked(job_manager *jm)
{
    ASSERT_LOCK_HELD(&jm->lock);
    while (!jm->stopping && jm->busy < jm->cfg.workers) {
        size_t n;
        job **jobs;
        fs_job *snap = snapshot_locked(jm, &n, &jobs);
        long k = snap ? fs_pick(snap, n, jm->cfg.user_workers) : -1;
        if (k < 0)
            return;
        job *j = jobs[k];
        double now = aa_monotonic_seconds();
        j->holds_worker = true;
        j->slice_start = j->served = now;
        j->next_yield_check = now + jm->cfg.slice_seconds;
        jm->busy++;
        if (j->paused) {
            j->paused = false;
            atomic_fetch_add(&j->paused_ns, (long long)((now - j->paused_since) * 1e9));
            pthread_cond_signal(&j->resume);
            continue;
        }
        jm_queue_remove(jm, j);
        assert(j->state == JOB_QUEUED && !j->slurm); /* edge queued -> running (a worker) */
        j->state = JOB_RUNNING;
        j->started = jm_now();
        jm->running++;
        int rc = jm_start_detached(job_thread, j);
        if (rc) {
            /* No thread now: back to the queue; the next finish or submit tries again. */
            j->holds_worker = false;
            assert(j->state == JOB_RUNNING); /* edge running -> queued: no thread started */
            j->state = JOB_QUEUED;
            jm->busy--;
            jm->running--;
            jm_queue_push(jm, j);
            fprintf(stderr, "aalabd: cannot start a thread for job %lld; it stays queued\n", j->id);
            return;
        }
        jm->threads++;
    }
}

void jm_yield_point_locked(job_ctx *ctx)
{
    job_manager *jm = ctx->jm;
    job *j = ctx->job;
    ASSERT_LOCK_HELD(&jm->lock);
    double now = aa_monotonic_seconds();
    double ran = now - ctx->started_mono - (double)atomic_load(&j->paused_ns) * 1e-9;
    if (!j->over_time && ran > jm->cfg.max_job_seconds) {
        j->over_time = true; /* the caller sees the stop flag through cancel_requested */
        return;
    }
    if (now < j->next_yield_check || jm->stopping || j->cancel_requested || !j->holds_worker)
        return;
    j->next_yield_check = now + YIELD_CHECK_EVERY;
    size_t n, r = 0;
    job **jobs;
    fs_job *snap = snapshot_locked(jm, &n, &jobs);
    if (!snap)
        return;
    while (r < n && jobs[r] != j)
        r++;
    if (r == n || !fs_should_yield(snap, n, r))
        return;
    /* Checkpoint: what the job has found so far is in the store before it waits. */
    job_ctx_flush_locked(ctx);
    j->holds_worker = false;
    j->paused = true;
    j->paused_since = j->served = aa_monotonic_seconds();
    jm->busy--;
    jm_schedule_locked(jm);
    fprintf(stderr, "aalabd: job %lld (uid %lld) yields its worker after a %.1f s slice\n", j->id,
            j->owner, now - j->slice_start);
    while (j->paused && !jm->stopping && !j->cancel_requested)
        pthread_cond_wait(&j->resume, &jm->lock);
    if (j->paused) { /* woken to stop: end without a worker (jm_finish_job knows) */
        j->paused = false;
        atomic_fetch_add(&j->paused_ns,
                         (long long)((aa_monotonic_seconds() - j->paused_since) * 1e9));
    }
}

static void sleep_seconds(double s)
{
    struct timespec ts = {.tv_sec = (time_t)s, .tv_nsec = (long)((s - (double)(time_t)s) * 1e9)};
    while (nanosleep(&ts, &ts) && errno == EINTR)
        ;
}

/* The job's final record, retried with doubling pauses for about FINAL_RETRY_SECONDS while the
 * store cannot be written (a full disk may be freed meanwhile). AA_OK or the last error. */
static int final_write(job_manager *jm, long long id, job_state st, double progress,
                       const json_t *best, const json_t *trace, const json_t *result,
                       const json_t *error, const char *reason, double now)
{
    double pause = FINAL_RETRY_FIRST, waited = 0;
    for (;;) {
        int rc =
            job_store_finish(jm->store, id, st, progress, best, trace, result, error, reason, now);
        if (rc == AA_OK || waited >= FINAL_RETRY_SECONDS)
            return rc;
        sleep_seconds(pause);
        waited += pause;
        pause *= 2;
    }
}

/* A job whose end could not be stored (j->unstored): a small failed record with error code
 * "unavailable" (its best so far stays as last stored) is retried every FINAL_RETRY_SLOW
 * seconds until the store takes it or the daemon stops (then the row is still "running" and the
 * next start runs the job again). Lock held; released while writing. */
static void store_unavailable_end_locked(job_manager *jm, job *j)
{
    ASSERT_LOCK_HELD(&jm->lock);
    char msg[sizeof j->reason];
    snprintf(msg, sizeof msg, "%s", j->reason);
    json_t *error =
        json_pack("{s:s,s:s,s:s}", "code", proto_wire_row_of(WIRE_STORE_UNAVAILABLE)->code,
                  "message", msg, "field", "");
    double progress = j->live.progress;
    while (!jm->stopping) {
        pthread_mutex_unlock(&jm->lock);
        int rc = job_store_finish(jm->store, j->id, JOB_FAILED, progress, NULL, NULL, NULL, error,
                                  msg, j->finished);
        pthread_mutex_lock(&jm->lock);
        if (rc == AA_OK) {
            fprintf(stderr, "aalabd: job %lld stored as failed (unavailable)\n", j->id);
            break;
        }
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_sec += (time_t)FINAL_RETRY_SLOW;
        pthread_cond_timedwait(&j->resume, &jm->lock, &until);
    }
    json_decref(error);
}

/* failure: a message longer than err's (a Slurm shard's log tail), or NULL/"". */
void jm_finish_job(job_manager *jm, job *j, int rc, json_t *result, const aa_error *err,
                   const char *failure)
{
    pthread_mutex_lock(&jm->lock);
    assert(j->state == JOB_RUNNING); /* only a started job's thread ends it */
    bool detached = rc == CLUSTER_EDETACHED;
    bool shutdown_stop =
        detached || (rc == AA_ECANCELED && jm->stopping && !j->cancel_requested && !j->over_time);
    bool over_time = j->over_time && rc != AA_OK;
    json_t *best = json_incref(j->live.best);
    job_live_flush_pending(&j->live);
    json_t *trace = json_deep_copy(j->live.trace);
    double progress = j->live.progress;
    pthread_mutex_unlock(&jm->lock);

    job_state st;
    json_t *error = NULL;
    const char *reason = NULL;
    char why[160];
    if (detached) {
        /* Its arrays keep running; the next start re-attaches through the cluster column. */
        st = JOB_QUEUED;
        reason = "daemon stopped; the job's Slurm arrays keep running and the next start "
                 "re-attaches to them";
    } else if (shutdown_stop) {
        /* Not resumable mid-run: the next start runs it again from the beginning. */
        st = JOB_QUEUED;
        reason = "daemon stopped while the job was running; re-queued";
        progress = 0;
    } else if (over_time) {
        st = JOB_FAILED;
        snprintf(why, sizeof why,
                 "the job ran longer than this daemon's --max-job-seconds (%.0f s); its best so "
                 "far is kept",
                 jm->cfg.max_job_seconds);
        reason = why;
        error = json_pack("{s:s,s:s,s:s}", "code", proto_wire_row_of(WIRE_TIME_LIMIT)->code,
                          "message", why, "field", "max_seconds");
    } else if (rc == AA_OK) {
        st = JOB_DONE;
        progress = 1;
    } else if (rc == AA_ECANCELED) {
        st = JOB_CANCELLED;
        reason = "cancelled by request";
    } else {
        st = JOB_FAILED;
        /* The wire code of the engine error, as an HTTP answer would carry it. */
        error = json_pack("{s:s,s:s,s:s}", "code",
                          proto_wire_row_of(proto_wire_error_of_aa(rc))->code, "message",
                          failure && failure[0]    ? failure
                          : err && err->message[0] ? err->message
                                                   : aa_strerror(rc),
                          "field", err ? err->field : "");
    }
    /* The live best is posted at most 10 times a second, so the last improvement may be
     * missing from it: a finished job's best is its result's. */
    double final_e2 = NAN;
    json_t *final_pattern =
        st == JOB_DONE && result && j->kind->best_of ? j->kind->best_of(result, &final_e2) : NULL;
    if (final_pattern && isfinite(final_e2)) {
        json_t *b = json_pack("{s:O,s:f}", "pattern", final_pattern, "e2", final_e2);
        if (b) {
            json_decref(best);
            best = b;
        }
    }
    json_decref(final_pattern);
    double now = jm_now();
    int wrc = final_write(jm, j->id, st, progress, best, trace, result, error, reason, now);
    /* One line per finished run for the journal. */
    fprintf(stderr, "aalabd: job %lld (%s, uid %lld) %s after %.2f s%s%s\n", j->id, j->kind->name,
            j->owner, shutdown_stop ? "checkpointed as queued" : job_state_name(st),
            now - j->started, st == JOB_FAILED && err && !over_time ? ": " : "",
            st == JOB_FAILED && err && !over_time ? err->message : "");
    json_decref(best);
    json_decref(trace);
    json_decref(error);
    json_decref(result);

    pthread_mutex_lock(&jm->lock);
    jm->running--;
    if (j->holds_worker)
        jm->busy--;
    j->holds_worker = false;
    if (wrc && st != JOB_QUEUED) {
        /* Still "running" in the store: without this, it would stay so until a restart ran it
         * again, and could be neither cancelled nor purged. */
        fprintf(stderr,
                "aalabd: job %lld: the job store cannot be written (%s); its outcome (%s) is "
                "dropped and it ends failed (unavailable) once the store can be written\n",
                j->id, wrc == JOB_STORE_EUNAVAILABLE ? "disk full or I/O error" : "write error",
                job_state_name(st));
        j->unstored = true;
        j->state = JOB_FAILED;
        j->finished = now;
        snprintf(j->reason, sizeof j->reason,
                 "the job ended (%s) but the job store could not be written (disk full?); its "
                 "outcome was dropped",
                 job_state_name(st));
        jm_schedule_locked(jm);
        store_unavailable_end_locked(jm, j);
    } else if (wrc) {
        fprintf(stderr,
                "aalabd: job %lld: its checkpoint could not be written; the next start "
                "runs it again\n",
                j->id);
    }
    jm_active_remove(jm, j);
    jm_schedule_locked(jm);
    pthread_mutex_unlock(&jm->lock);
    jm_job_free(j);
}

/* One thread per started job: paused jobs keep their thread (and memory) while they wait, so
 * the number of threads is the number of started jobs, bounded by the queue and user quota. */
static void *job_thread(void *arg)
{
    job *j = arg;
    job_manager *jm = j->jm;
    job_store_set_state(jm->store, j->id, JOB_RUNNING, j->started, NULL);
    struct job_ctx ctx = job_ctx_of(jm, j);
    void *typed = NULL;
    json_t *result = NULL;
    aa_error err = {0};
    int rc = j->kind->run(j->params, &ctx, &typed, &err);
    if (rc == AA_OK && !(result = j->kind->encode_result(typed)))
        rc = aa_error_set(&err, AA_ENOMEM, "", "out of memory");
    j->kind->free_result(typed);
    jm_finish_job(jm, j, rc, result, &err, NULL);
    pthread_mutex_lock(&jm->lock);
    if (--jm->threads == 0)
        pthread_cond_broadcast(&jm->idle);
    pthread_mutex_unlock(&jm->lock);
    return NULL;
}
