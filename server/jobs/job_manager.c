#define _POSIX_C_SOURCE 200809L
#include "job_manager.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cluster_driver.h"
#include "cluster_sweep.h"
#include "fair_share.h"
#include "job_ctx_impl.h"
#include "job_envelope.h"
#include "wire_error.h"

#define COUNTS_MAX_AGE 0.25    /* seconds */
#define JOB_MAX_CRASHES 3      /* abnormal daemon exits while running one job before giving up */
#define YIELD_CHECK_EVERY 0.25 /* seconds between fair-share checks once a slice is over */
/* A job's final write is retried with doubling pauses from FINAL_RETRY_FIRST for about
 * FINAL_RETRY_SECONDS; then its outcome is dropped and a small failed (unavailable) record is
 * retried every FINAL_RETRY_SLOW seconds until the store takes it. */
#define FINAL_RETRY_FIRST 0.05
#define FINAL_RETRY_SECONDS 6.0
#define FINAL_RETRY_SLOW 1.0

typedef struct job {
    struct job_manager *jm;
    long long id;
    const job_kind *kind;
    void *params;
    json_t *spec;
    long long owner;
    int priority;
    bool private_job; /* visibility "private": what it makes (tiles) is private too */
    job_state state;
    double created, started;
    bool cancel_requested;
    bool over_time;    /* stopped by --max-job-seconds */
    bool holds_worker; /* running on one of the workers (a paused job does not) */
    bool unstored;     /* ended, but its end is not in the store yet (disk full): finish_job
                        * retries; it is no longer scheduled */
    bool cancelling;   /* a queued job being written as cancelled: not scheduled meanwhile */
    double finished;   /* when an unstored job ended (Unix seconds) */
    bool paused;       /* gave its worker back; waits on resume */
    double slice_start, served, paused_since, next_yield_check; /* monotonic seconds */
    atomic_llong paused_ns; /* total pause so far: the job's clock stands still meanwhile */
    pthread_cond_t resume;
    char reason[160];
    bool slurm;            /* executor "slurm": its thread drives Slurm arrays, holds no worker */
    json_t *cluster_state; /* the stored Slurm state to re-attach to (restart), or NULL */
    job_live live;         /* progress, best, trace: guarded by jm->lock */
    struct job *next;      /* active list */
} job;

/* Documents a _locked function's precondition: jm->lock is held (by some thread; a default
 * mutex cannot tell by whom). Debug and sanitizer builds only (NDEBUG compiles it out). */
#define JM_ASSERT_LOCKED(jm) assert(pthread_mutex_trylock(&(jm)->lock) == EBUSY)

struct job_manager {
    job_manager_config cfg;
    job_store *store;
    pthread_mutex_t lock;
    pthread_cond_t idle; /* signalled when the last job thread ends */
    job **queue;         /* queued jobs (never ran), in submission order */
    size_t q_len, q_cap;
    job *active;      /* every queued, running or paused job */
    int running;      /* jobs in state running, paused ones included */
    int busy;         /* workers held (running and not paused) */
    int threads;      /* job threads alive */
    size_t admitting; /* submissions between admission and their store insert */
    fs_job *snapshot; /* fair-share scratch, guarded by lock */
    size_t snapshot_cap;
    pthread_mutex_t counts_lock;
    /* Jobs by state as a few recent viewers see them, each cached for COUNTS_MAX_AGE. */
    struct {
        long long viewer;
        double at;
        long long counts[JOB_STATE_COUNT];
    } counts[8];
    bool stopping;
    cluster_probe *probe; /* whether Slurm answers (health, submit) */
    int slurm_jobs;       /* Slurm jobs with a thread */
};

double jm_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static job *job_new(void)
{
    job *j = calloc(1, sizeof *j);
    if (!j)
        return NULL;
    if (job_live_init(&j->live) != AA_OK || pthread_cond_init(&j->resume, NULL)) {
        job_live_clear(&j->live);
        free(j);
        return NULL;
    }
    atomic_init(&j->paused_ns, 0);
    return j;
}

static void job_free(job *j)
{
    if (!j)
        return;
    if (j->params && j->kind && j->kind->free_params)
        j->kind->free_params(j->params);
    json_decref(j->spec);
    json_decref(j->cluster_state);
    job_live_clear(&j->live);
    pthread_cond_destroy(&j->resume);
    free(j);
}

static int queue_push(job_manager *jm, job *j)
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

static void queue_remove(job_manager *jm, job *j)
{
    for (size_t i = 0; i < jm->q_len; i++) {
        if (jm->queue[i] == j) {
            memmove(jm->queue + i, jm->queue + i + 1, (jm->q_len - i - 1) * sizeof *jm->queue);
            jm->q_len--;
            return;
        }
    }
}

static void active_remove(job_manager *jm, job *j)
{
    for (job **p = &jm->active; *p; p = &(*p)->next) {
        if (*p == j) {
            *p = j->next;
            return;
        }
    }
}

static job *active_find(job_manager *jm, long long id)
{
    for (job *j = jm->active; j; j = j->next)
        if (j->id == id)
            return j;
    return NULL;
}

static int owner_load(job_manager *jm, long long owner)
{
    int n = 0;
    for (job *j = jm->active; j; j = j->next)
        n += j->owner == owner;
    return n;
}

/* --- scheduling ----------------------------------------------------------------------------- */

/* The fair-share view of the active jobs (fair_share.h); NULL when out of memory. */
static fs_job *snapshot_locked(job_manager *jm, size_t *n, job ***order)
{
    JM_ASSERT_LOCKED(jm);
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

static void *job_thread(void *arg);

/* Hands free workers to waiting jobs, by fair share: a paused job is woken, a queued one gets
 * a thread of its own. Called with the lock held after anything that frees a worker or adds a
 * waiting job. */
static void schedule_locked(job_manager *jm)
{
    JM_ASSERT_LOCKED(jm);
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
        queue_remove(jm, j);
        assert(j->state == JOB_QUEUED && !j->slurm); /* edge queued -> running (a worker) */
        j->state = JOB_RUNNING;
        j->started = jm_now();
        jm->running++;
        pthread_attr_t attr;
        pthread_t t;
        int rc = pthread_attr_init(&attr);
        if (!rc) {
            pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
            rc = pthread_create(&t, &attr, job_thread, j);
            pthread_attr_destroy(&attr);
        }
        if (rc) {
            /* No thread now: back to the queue; the next finish or submit tries again. */
            j->holds_worker = false;
            assert(j->state == JOB_RUNNING); /* edge running -> queued: no thread started */
            j->state = JOB_QUEUED;
            jm->busy--;
            jm->running--;
            queue_push(jm, j);
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
    JM_ASSERT_LOCKED(jm);
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
    schedule_locked(jm);
    fprintf(stderr, "aalabd: job %lld (uid %lld) yields its worker after a %.1f s slice\n", j->id,
            j->owner, now - j->slice_start);
    while (j->paused && !jm->stopping && !j->cancel_requested)
        pthread_cond_wait(&j->resume, &jm->lock);
    if (j->paused) { /* woken to stop: end without a worker (finish_job knows) */
        j->paused = false;
        atomic_fetch_add(&j->paused_ns,
                         (long long)((aa_monotonic_seconds() - j->paused_since) * 1e9));
    }
}

bool jm_job_stop_locked(const job_ctx *ctx)
{
    const job *j = ctx->job;
    JM_ASSERT_LOCKED((job_manager *)ctx->jm);
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
    JM_ASSERT_LOCKED(jm);
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
static void finish_job(job_manager *jm, job *j, int rc, json_t *result, const aa_error *err,
                       const char *failure)
{
    pthread_mutex_lock(&jm->lock);
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
        schedule_locked(jm);
        store_unavailable_end_locked(jm, j);
    } else if (wrc) {
        fprintf(stderr,
                "aalabd: job %lld: its checkpoint could not be written; the next start "
                "runs it again\n",
                j->id);
    }
    active_remove(jm, j);
    schedule_locked(jm);
    pthread_mutex_unlock(&jm->lock);
    job_free(j);
}

/* The context a job's thread hands its kind (or the Slurm driver). */
static struct job_ctx job_ctx_of(job_manager *jm, job *j)
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
    finish_job(jm, j, rc, result, &err, NULL);
    pthread_mutex_lock(&jm->lock);
    if (--jm->threads == 0)
        pthread_cond_broadcast(&jm->idle);
    pthread_mutex_unlock(&jm->lock);
    return NULL;
}

/* --- Slurm jobs -------------------------------------------------------------------------- */

static cluster_stop slurm_check(void *user)
{
    job_ctx *ctx = user;
    pthread_mutex_lock(ctx->lock);
    jm_yield_point_locked(ctx); /* holds no worker: this only enforces --max-job-seconds */
    const job *j = ctx->job;
    cluster_stop s = j->cancel_requested || j->over_time ? CLUSTER_CANCEL
                     : ctx->jm->stopping                 ? CLUSTER_DETACH
                                                         : CLUSTER_GO;
    pthread_mutex_unlock(ctx->lock);
    return s;
}

static void slurm_report(void *user, double progress, const json_t *best, const json_t *trace)
{
    job_ctx *ctx = user;
    json_t *b = best ? json_deep_copy(best) : NULL;
    json_t *t = trace ? json_deep_copy(trace) : NULL;
    pthread_mutex_lock(ctx->lock);
    job_live *l = ctx->live;
    l->progress = progress < 0 ? 0 : progress > 1 ? 1 : progress;
    if (b) {
        json_decref(l->best);
        l->best = b;
    }
    if (t) {
        /* The merged trace is rebuilt from the shards' files each poll: replace it whole. */
        json_decref(l->trace);
        l->trace = t;
        l->have_pending = false;
        if (json_array_size(t) == l->flushed_trace_len)
            l->flushed_trace_len = (size_t)-1;
    }
    if (jm_now() - l->last_flush >= 5.0)
        job_ctx_flush_locked(ctx);
    pthread_mutex_unlock(ctx->lock);
}

static void slurm_save(void *user, const json_t *state)
{
    job_ctx *ctx = user;
    if (job_store_set_cluster(ctx->store, ctx->id, state))
        fprintf(stderr, "aalabd: job %lld: cannot store its Slurm array ids\n", ctx->id);
}

/* One thread per Slurm job: runs the driver until the job ends, is cancelled or the daemon
 * stops (then the arrays keep running). */
static void *slurm_thread(void *arg)
{
    job *j = arg;
    job_manager *jm = j->jm;
    job_store_set_state(jm->store, j->id, JOB_RUNNING, j->started, j->reason[0] ? j->reason : NULL);
    struct job_ctx ctx = job_ctx_of(jm, j);
    cluster_job cj = {.id = j->id,
                      .kind = j->kind,
                      .params = j->params,
                      .spec = j->spec,
                      .state = j->cluster_state};
    cluster_job_io io = {
        .check = slurm_check, .report = slurm_report, .save = slurm_save, .user = &ctx};
    void *typed = NULL;
    json_t *result = NULL;
    aa_error err = {0};
    char failure[1200];
    int rc = cluster_driver_run(&jm->cfg.cluster, &cj, &io, &typed, failure, sizeof failure, &err);
    if (rc == AA_OK && !(result = j->kind->encode_result(typed)))
        rc = aa_error_set(&err, AA_ENOMEM, "", "out of memory");
    if (typed)
        j->kind->free_result(typed);
    finish_job(jm, j, rc, result, &err, failure);
    pthread_mutex_lock(&jm->lock);
    jm->slurm_jobs--;
    if (--jm->threads == 0)
        pthread_cond_broadcast(&jm->idle);
    pthread_mutex_unlock(&jm->lock);
    return NULL;
}

/* Starts a Slurm job's thread (lock held). false when no thread could start. */
static bool slurm_start_locked(job_manager *jm, job *j)
{
    JM_ASSERT_LOCKED(jm);
    assert(j->slurm && j->state == JOB_QUEUED); /* edge queued -> running (a Slurm thread) */
    j->state = JOB_RUNNING;
    j->started = jm_now();
    pthread_attr_t attr;
    pthread_t t;
    int rc = pthread_attr_init(&attr);
    if (!rc) {
        pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
        rc = pthread_create(&t, &attr, slurm_thread, j);
        pthread_attr_destroy(&attr);
    }
    if (rc)
        return false;
    jm->running++;
    jm->threads++;
    jm->slurm_jobs++;
    return true;
}

/* --- restart recovery --------------------------------------------------------------------- */

static void recover_one(void *user, long long id, const char *kind_name, json_t *spec,
                        long long owner, int priority, bool private_job, job_state state,
                        double created)
{
    job_manager *jm = user;
    const job_kind *kind = kind_name ? job_manager_kind(jm, kind_name) : NULL;
    char reason[400];
    if (!kind) {
        snprintf(reason, sizeof reason, "job kind '%.40s' is not available after restart",
                 kind_name ? kind_name : "?");
        job_store_finish(jm->store, id, JOB_INTERRUPTED, 0, NULL, NULL, NULL, NULL, reason,
                         jm_now());
        return;
    }
    /* A Slurm job (its array ids are in the cluster column) re-attaches to its arrays. */
    json_t *cluster_state = job_store_get_cluster(jm->store, id);
    if (cluster_state && !jm->cfg.cluster.shared_dir[0]) {
        json_decref(cluster_state);
        job_store_finish(jm->store, id, JOB_INTERRUPTED, 0, NULL, NULL, NULL, NULL,
                         "a Slurm job, but the daemon restarted without --slurm-shared-dir; its "
                         "arrays were left alone",
                         jm_now());
        return;
    }
    /* A job that keeps taking the daemon down with it must not do so forever (a Slurm job runs
     * elsewhere: its thread only polls). */
    if (state == JOB_RUNNING && !cluster_state) {
        int crashes = job_store_bump_crashes(jm->store, id);
        if (crashes >= JOB_MAX_CRASHES) {
            snprintf(reason, sizeof reason,
                     "the daemon stopped abnormally %d times while running this job; not "
                     "re-queued again",
                     crashes);
            job_store_finish(jm->store, id, JOB_INTERRUPTED, 0, NULL, NULL, NULL, NULL, reason,
                             jm_now());
            return;
        }
    }
    void *params = NULL;
    aa_error err = {0};
    /* The stored spec is the kind's (the envelope lives in its own columns); a spec stored
     * before that split still carries it, so it is taken out here too. */
    job_envelope env;
    json_t *kind_spec = NULL;
    int prc = job_envelope_take(spec, &env, &kind_spec, &err);
    if (!prc)
        prc = kind->decode(kind_spec, &params, &err);
    json_decref(kind_spec);
    if (prc != AA_OK) {
        json_decref(cluster_state);
        snprintf(reason, sizeof reason, "spec no longer valid after restart: %s (%s)", err.message,
                 err.field);
        job_store_finish(jm->store, id, JOB_INTERRUPTED, 0, NULL, NULL, NULL, NULL, reason,
                         jm_now());
        return;
    }
    job *j = job_new();
    if (!j) {
        json_decref(cluster_state);
        kind->free_params(params);
        job_store_finish(jm->store, id, JOB_INTERRUPTED, 0, NULL, NULL, NULL, NULL,
                         "out of memory at restart", jm_now());
        return;
    }
    j->jm = jm;
    j->id = id;
    j->kind = kind;
    j->params = params;
    j->spec = json_incref(spec);
    j->owner = owner;
    j->priority = priority;
    j->private_job = private_job || env.private_job;
    j->state = JOB_QUEUED;
    j->created = created;
    if (cluster_state) {
        /* Started by job_manager_create once recovery is over. */
        j->slurm = true;
        j->cluster_state = cluster_state;
        snprintf(j->reason, sizeof j->reason, "re-attached to its Slurm arrays at restart");
        j->next = jm->active;
        jm->active = j;
        return;
    }
    if (state == JOB_RUNNING)
        snprintf(j->reason, sizeof j->reason,
                 "was running when the daemon stopped; re-queued at restart");
    queue_push(jm, j);
    j->next = jm->active;
    jm->active = j;
    /* A job that was running restarts from scratch: clear its stale live state. */
    job_store_finish(jm->store, id, JOB_QUEUED, 0, json_null(), NULL, NULL, NULL,
                     j->reason[0] ? j->reason : NULL, 0);
}

static bool job_known(void *user, long long id)
{
    job_manager *jm = user;
    return job_store_owner(jm->store, id, NULL, NULL, NULL);
}

/* The probe thread's housekeeping: the shared files of jobs that retention deleted. */
static void sweep_shared_dir(void *user)
{
    job_manager *jm = user;
    size_t removed = 0;
    aa_error err = {0};
    if (cluster_sweep_orphans(jm->cfg.cluster.shared_dir, job_known, jm, &removed, &err))
        fprintf(stderr, "aalabd: sweeping --slurm-shared-dir: %s\n", err.message);
    if (removed)
        fprintf(stderr, "aalabd: removed the shared files of %zu deleted job(s)\n", removed);
}

job_manager *job_manager_create(const char *state_dir, const job_manager_config *cfg, aa_error *err)
{
    job_manager *jm = calloc(1, sizeof *jm);
    if (!jm) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    jm->cfg = *cfg;
    if (jm->cfg.workers < 1)
        jm->cfg.workers = 1;
    pthread_mutex_init(&jm->lock, NULL);
    pthread_mutex_init(&jm->counts_lock, NULL);
    for (size_t i = 0; i < sizeof jm->counts / sizeof jm->counts[0]; i++)
        jm->counts[i].at = -1e300;
    pthread_cond_init(&jm->idle, NULL);
    jm->store = job_store_open(state_dir, err);
    if (!jm->store) {
        job_manager_destroy(jm);
        return NULL;
    }
    if (jm->cfg.user_workers < 1)
        jm->cfg.user_workers = jm->cfg.workers / 2 > 1 ? jm->cfg.workers / 2 : 1;
    if (!(jm->cfg.slice_seconds > 0))
        jm->cfg.slice_seconds = 60;
    if (!(jm->cfg.max_job_seconds > 0))
        jm->cfg.max_job_seconds = 86400;
    job_store_set_user_quota(jm->store, jm->cfg.user_store_bytes);
    jm->probe = cluster_probe_start(jm->cfg.cluster.shared_dir[0] != 0, sweep_shared_dir, jm, err);
    if (!jm->probe) {
        job_manager_destroy(jm);
        return NULL;
    }
    job_store_unfinished(jm->store, recover_one, jm);
    pthread_mutex_lock(&jm->lock);
    for (job *j = jm->active; j; j = j->next) {
        if (j->slurm && j->state == JOB_QUEUED && !slurm_start_locked(jm, j))
            fprintf(stderr, "aalabd: cannot start a thread for Slurm job %lld\n", j->id);
    }
    schedule_locked(jm);
    pthread_mutex_unlock(&jm->lock);
    return jm;
}

void job_manager_shutdown(job_manager *jm)
{
    pthread_mutex_lock(&jm->lock);
    jm->stopping = true;
    for (job *j = jm->active; j; j = j->next)
        if (j->paused || j->unstored)
            pthread_cond_signal(&j->resume);
    while (jm->threads > 0)
        pthread_cond_wait(&jm->idle, &jm->lock);
    pthread_mutex_unlock(&jm->lock);
}

void job_manager_destroy(job_manager *jm)
{
    if (!jm)
        return;
    job_manager_shutdown(jm);
    /* Jobs still queued stay queued in the store; only memory is released. */
    while (jm->active) {
        job *j = jm->active;
        jm->active = j->next;
        job_free(j);
    }
    free(jm->queue);
    free(jm->snapshot);
    job_store_close(jm->store);
    cluster_probe_stop(jm->probe);
    pthread_cond_destroy(&jm->idle);
    pthread_mutex_destroy(&jm->counts_lock);
    pthread_mutex_destroy(&jm->lock);
    free(jm);
}

/* --- API ---------------------------------------------------------------------------------- */

const job_kind *job_manager_kind(const job_manager *jm, const char *name)
{
    const job_kind *k = job_kind_find(name);
    return k && (!k->test_only || jm->cfg.test_kinds) ? k : NULL;
}

void job_manager_kind_names(const job_manager *jm, char *buf, size_t cap)
{
    size_t n = 0;
    buf[0] = 0;
    size_t count;
    const job_kind *table = job_kinds_table(&count);
    for (size_t k = 0; k < count && n < cap; k++) {
        if (table[k].test_only && !jm->cfg.test_kinds)
            continue;
        int w = snprintf(buf + n, cap - n, "%s%s", n ? ", " : "", table[k].name);
        if (w < 0)
            break;
        n += (size_t)w;
    }
}

/* Why a job with executor "slurm" cannot be taken now (AA_EINVAL for a kind without a split,
 * JM_ESLURM), or AA_OK. Reads the probe's last answer: never waits for Slurm. */
static int slurm_refusal(job_manager *jm, const job_kind *kind, aa_error *err)
{
    if (!kind->split)
        return aa_error_set(
            err, AA_EINVAL, "executor",
            "kind %s cannot run on Slurm (optimize, family-sweep, random-stats and table3 "
            "can)",
            kind->name);
    cluster_status st;
    cluster_probe_status(jm->probe, &st);
    if (!st.configured)
        return aa_error_set(err, JM_ESLURM, "executor",
                            "Slurm is not configured: this daemon runs without --slurm-shared-dir");
    if (st.answering != 1)
        return aa_error_set(err, JM_ESLURM, "executor", "%s", st.message);
    return AA_OK;
}

int job_manager_submit(job_manager *jm, const json_t *spec, long long owner, long long *id,
                       aa_error *err)
{
    const json_t *kind_j = json_object_get(spec, "kind");
    if (!kind_j)
        return aa_error_set(err, AA_EINVAL, "kind", "a job needs a kind");
    if (!json_is_string(kind_j))
        return aa_error_set(err, AA_EINVAL, "kind", "kind must be a string");
    const char *kind_name = json_string_value(kind_j);
    const job_kind *kind = job_manager_kind(jm, kind_name);
    if (!kind || strlen(kind_name) != json_string_length(kind_j)) {
        char names[256];
        job_manager_kind_names(jm, names, sizeof names);
        return aa_error_set(err, AA_EINVAL, "kind", "unknown job kind \"%.40s\"; known kinds: %s",
                            kind_name, names);
    }
    job_envelope env;
    json_t *kind_spec = NULL;
    int rc = job_envelope_take(spec, &env, &kind_spec, err);
    if (rc)
        return rc;
    if (env.slurm) {
        rc = slurm_refusal(jm, kind, err);
        if (rc) {
            json_decref(kind_spec);
            return rc;
        }
    }
    void *params = NULL;
    rc = kind->decode(kind_spec, &params, err);
    double whole = !rc && kind->max_seconds ? kind->max_seconds(params) : 0;
    if (whole > jm->cfg.max_job_seconds) {
        kind->free_params(params);
        const json_t *asked = json_object_get(kind_spec, "max_seconds");
        double per = json_is_number(asked) ? json_number_value(asked) : whole;
        /* Kinds that spend max_seconds per seed or stage (table3) say what it adds up to, so
         * that a 0.5 refused under a ceiling of 3 makes sense. */
        if (per < whole)
            rc = aa_error_set(err, AA_ERANGE, "max_seconds",
                              "max_seconds %g makes this %s job's whole budget %g s (it is spent "
                              "per seed and stage), over this daemon's --max-job-seconds %.0f",
                              per, kind->name, whole, jm->cfg.max_job_seconds);
        else
            rc = aa_error_set(err, AA_ERANGE, "max_seconds",
                              "must be at most %.0f (this daemon's --max-job-seconds)",
                              jm->cfg.max_job_seconds);
    }
    /* Stored as submitted, less the envelope (which has columns of its own). */
    json_t *stored = rc ? NULL : json_pack("{s:s}", "kind", kind->name);
    if (stored && json_object_update(stored, kind_spec)) {
        json_decref(stored);
        stored = NULL;
    }
    json_decref(kind_spec);
    if (rc)
        return rc < 0 ? rc : AA_EINVAL;
    job *j = stored ? job_new() : NULL;
    if (!j) {
        kind->free_params(params);
        json_decref(stored);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    j->jm = jm;
    j->kind = kind;
    j->params = params;
    j->spec = stored;
    j->owner = owner;
    j->priority = env.priority;
    j->private_job = env.private_job;
    j->state = JOB_QUEUED;
    j->created = jm_now();
    j->slurm = env.slurm;

    /* Admission under the lock; the store insert (an fsync) outside it, so workers reporting
     * progress never wait for a disk. The job joins the active list first (id 0, invisible
     * to lookups) so it counts against the quota and the queue bound meanwhile. */
    pthread_mutex_lock(&jm->lock);
    if (jm->stopping) {
        rc = aa_error_set(err, JM_EQUEUE_FULL, "", "the daemon is shutting down");
    } else if (j->slurm && jm->slurm_jobs >= JM_SLURM_JOBS_MAX) {
        rc = aa_error_set(err, JM_EQUEUE_FULL, "", "%d Slurm jobs are running (the limit)",
                          JM_SLURM_JOBS_MAX);
    } else if (!j->slurm && (int)(jm->q_len + jm->admitting) >= jm->cfg.queue_size) {
        rc = aa_error_set(err, JM_EQUEUE_FULL, "", "the job queue is full (%d queued)",
                          (int)jm->q_len);
    } else if (owner >= 0 && owner_load(jm, owner) >= jm->cfg.user_quota) {
        rc = aa_error_set(err, JM_EQUOTA, "",
                          "uid %lld already has %d queued or running jobs (the limit)", owner,
                          jm->cfg.user_quota);
    } else {
        j->next = jm->active;
        jm->active = j;
        jm->admitting++;
    }
    pthread_mutex_unlock(&jm->lock);
    if (rc) {
        job_free(j);
        return rc;
    }
    long long new_id = 0;
    job_store_new rec = {.kind = kind->name,
                         .spec = j->spec,
                         .owner = owner,
                         .created = j->created,
                         .visibility = job_envelope_visibility(&env),
                         .pinned = env.pinned,
                         .priority = env.priority,
                         .label = env.label,
                         .family = kind->spec_family ? kind->spec_family(params) : NULL};
    rc = job_store_insert(jm->store, &rec, &new_id, err);
    if (rc)
        rc = rc == JOB_STORE_EQUOTA ? JM_ESTORE_QUOTA : JM_ESTORE;
    /* A restart must know a Slurm job as one even before its first array is submitted. */
    json_t *marker = j->slurm ? json_pack("{s:s,s:[]}", "executor", "slurm", "stages") : NULL;
    if (!rc && j->slurm && (!marker || job_store_set_cluster(jm->store, new_id, marker)))
        rc = aa_error_set(err, JM_ESTORE, "", "cannot store the job's executor");
    json_decref(marker);
    pthread_mutex_lock(&jm->lock);
    jm->admitting--;
    if (!rc && j->slurm) {
        j->id = new_id;
        if (!slurm_start_locked(jm, j))
            rc = aa_error_set(err, AA_ENOMEM, "", "cannot start a thread for the Slurm job");
    } else if (!rc && queue_push(jm, j) != AA_OK) {
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    if (rc) {
        active_remove(jm, j);
    } else {
        j->id = new_id;
        *id = new_id;
        schedule_locked(jm);
    }
    pthread_mutex_unlock(&jm->lock);
    if (new_id > 0 && (rc == AA_ENOMEM || rc == JM_ESTORE))
        job_store_finish(jm->store, new_id, JOB_FAILED, 0, NULL, NULL, NULL, NULL, "out of memory",
                         jm_now());
    if (!rc)
        j = NULL;
    job_free(j);
    return rc;
}

/* Overlays the live state of an active job on its stored record. Caller holds the lock. */
static void overlay_live(json_t *o, const job *j)
{
    json_object_set_new(o, "state", json_string(job_state_name(j->state)));
    json_object_set_new(o, "progress", json_real(j->live.progress));
    /* Copies, never shared references: jansson's reference counts are not meant to be
     * touched from two threads (the worker keeps updating live.best). */
    if (j->live.best) {
        json_object_set_new(o, "best", json_deep_copy(j->live.best));
        json_t *e2 = json_is_object(j->live.best) ? json_object_get(j->live.best, "e2") : NULL;
        if (json_is_number(e2))
            json_object_set_new(o, "best_e2", json_real(json_number_value(e2)));
    }
    if (json_object_get(o, "trace"))
        json_object_set_new(o, "trace", json_deep_copy(j->live.trace));
    if (j->cancel_requested)
        json_object_set_new(o, "cancel_requested", json_true());
    if (j->unstored) { /* its end as the store will have it once it can be written */
        json_object_set_new(o, "finished", json_real(j->finished));
        json_object_set_new(o, "reason", json_string(j->reason));
        json_object_set_new(o, "error",
                            json_pack("{s:s,s:s,s:s}", "code",
                                      proto_wire_row_of(WIRE_STORE_UNAVAILABLE)->code, "message",
                                      j->reason, "field", ""));
    }
    if (j->paused) /* gave its worker to another user's job; resumes where it stopped */
        json_object_set_new(o, "paused", json_true());
    if (j->state == JOB_RUNNING) {
        json_object_set_new(o, "started", json_real(j->started));
        /* Why a job runs longer than its budget: the turns it gave to other users so far. */
        double paused = (double)atomic_load(&j->paused_ns) * 1e-9 +
                        (j->paused ? aa_monotonic_seconds() - j->paused_since : 0);
        json_object_set_new(o, "paused_seconds", json_real(paused));
    }
}

json_t *job_manager_get(job_manager *jm, long long id)
{
    json_t *o = job_store_get(jm->store, id, true);
    if (!o)
        return NULL;
    json_t *cluster = job_store_get_cluster(jm->store, id);
    json_object_set_new(o, "executor", json_string(cluster ? "slurm" : "local"));
    json_decref(cluster);
    pthread_mutex_lock(&jm->lock);
    job *j = active_find(jm, id);
    if (j)
        overlay_live(o, j);
    pthread_mutex_unlock(&jm->lock);
    return o;
}

json_t *job_manager_list(job_manager *jm, const job_store_filter *filter)
{
    json_t *a = job_store_list(jm->store, filter);
    pthread_mutex_lock(&jm->lock);
    size_t i;
    json_t *o;
    json_array_foreach(a, i, o)
    {
        job *j = active_find(jm, json_integer_value(json_object_get(o, "id")));
        if (j)
            overlay_live(o, j);
    }
    pthread_mutex_unlock(&jm->lock);
    return a;
}

int job_manager_cancel(job_manager *jm, long long id, long long caller, const char **state_out)
{
    pthread_mutex_lock(&jm->lock);
    job *j = active_find(jm, id);
    if (!j) {
        pthread_mutex_unlock(&jm->lock);
        json_t *o = job_store_get(jm->store, id, false);
        int rc = o ? JM_EFINISHED : JM_ENOENT;
        json_decref(o);
        return rc;
    }
    if (caller != 0 && !(j->owner < 0 || (caller >= 0 && caller == j->owner))) {
        pthread_mutex_unlock(&jm->lock);
        return JM_EFORBIDDEN;
    }
    if (j->unstored || j->cancelling) {
        pthread_mutex_unlock(&jm->lock);
        return JM_EFINISHED;
    }
    if (j->state == JOB_QUEUED) {
        /* Out of the queue while the store is written outside the lock; back in it if the
         * store cannot be written (503), so it is never lost from both. */
        queue_remove(jm, j);
        j->cancelling = true;
        pthread_mutex_unlock(&jm->lock);
        int rc = job_store_finish(jm->store, id, JOB_CANCELLED, 0, NULL, NULL, NULL, NULL,
                                  "cancelled by request before it ran", jm_now());
        pthread_mutex_lock(&jm->lock);
        j->cancelling = false;
        if (rc != AA_OK) {
            rc = queue_push(jm, j);
            if (rc == AA_OK)
                schedule_locked(jm);
            else
                active_remove(jm, j); /* out of memory: the next start runs it */
            pthread_mutex_unlock(&jm->lock);
            if (rc != AA_OK)
                job_free(j);
            return JM_ESTORE;
        }
        active_remove(jm, j);
        pthread_mutex_unlock(&jm->lock);
        job_free(j);
        *state_out = "cancelled";
        return JM_OK;
    }
    j->cancel_requested = true;
    if (j->paused)
        pthread_cond_signal(&j->resume);
    pthread_mutex_unlock(&jm->lock);
    *state_out = "running";
    return JM_OK;
}

json_t *job_manager_best_pattern(job_manager *jm, long long id, const char **why)
{
    json_t *o = job_manager_get(jm, id);
    if (!o) {
        *why = "no such job";
        return NULL;
    }
    /* A job's best is {"pattern", "e2"} (job_kind.h); a finished job's result knows its best
     * through its kind's row. */
    const json_t *p = json_object_get(json_object_get(o, "best"), "pattern");
    const job_kind *kind = job_kind_find(json_string_value(json_object_get(o, "kind")));
    json_t *result = json_object_get(o, "result");
    double e2;
    /* Only an encoded pattern (it has a form): animation's best names its pattern's family and
     * cost only. */
    json_t *out = json_is_object(p) && json_object_get(p, "form") ? json_deep_copy(p) : NULL;
    if (!out && kind && kind->best_of && json_is_object(result))
        out = kind->best_of(result, &e2);
    json_decref(o);
    if (!out)
        *why = "the job has no pattern (yet)";
    return out;
}

void job_manager_stats_get(job_manager *jm, long long viewer, job_manager_stats *out)
{
    memset(out, 0, sizeof *out);
    /* Counting by state scans the table: refresh at most every COUNTS_MAX_AGE seconds per
     * viewer so health probes stay cheap with a long job history. */
    double now = jm_now();
    size_t n = sizeof jm->counts / sizeof jm->counts[0], slot = n, oldest = 0;
    pthread_mutex_lock(&jm->counts_lock);
    for (size_t i = 0; i < n; i++) {
        if (jm->counts[i].viewer == viewer && jm->counts[i].at > -1e299)
            slot = i;
        if (jm->counts[i].at < jm->counts[oldest].at)
            oldest = i;
    }
    if (slot == n) {
        slot = oldest;
        jm->counts[slot].viewer = viewer;
        jm->counts[slot].at = -1e300;
    }
    if (now - jm->counts[slot].at > COUNTS_MAX_AGE || now < jm->counts[slot].at) {
        job_store_counts_visible(jm->store, viewer, jm->counts[slot].counts);
        jm->counts[slot].at = now;
    }
    memcpy(out->by_state, jm->counts[slot].counts, sizeof out->by_state);
    pthread_mutex_unlock(&jm->counts_lock);
    pthread_mutex_lock(&jm->lock);
    out->workers = jm->cfg.workers;
    out->busy = jm->busy;
    /* Queue and running counts as the viewer sees them: another user's private job is not
     * there for them (issue 35, point 9). */
    out->queued = viewer == JOB_VIEWER_ALL ? (int)jm->q_len : (int)out->by_state[JOB_QUEUED];
    out->running = viewer == JOB_VIEWER_ALL ? jm->running : (int)out->by_state[JOB_RUNNING];
    for (job *j = jm->active; j; j = j->next)
        out->paused += j->paused;
    out->queue_size = jm->cfg.queue_size;
    pthread_mutex_unlock(&jm->lock);
}

job_store *job_manager_store(job_manager *jm)
{
    return jm->store;
}

int job_manager_purge(job_manager *jm, long long id, long long caller)
{
    pthread_mutex_lock(&jm->lock);
    job *j = active_find(jm, id);
    long long owner = -1;
    job_state state = JOB_DONE;
    bool found = j != NULL, unstored = j && j->unstored;
    if (j) {
        owner = j->owner;
        state = j->state;
    }
    pthread_mutex_unlock(&jm->lock);
    if (!found && !job_store_owner(jm->store, id, &owner, &state, NULL))
        return JM_ENOENT;
    if (caller != 0 && !(owner < 0 || (caller >= 0 && caller == owner)))
        return JM_EFORBIDDEN;
    if (unstored) /* its end is not in the store yet: the store cannot be written */
        return JM_ESTORE;
    if (found) {
        const char *ignored;
        int rc = state == JOB_QUEUED ? job_manager_cancel(jm, id, caller, &ignored) : JM_EACTIVE;
        if (rc != JM_OK && rc != JM_EFINISHED)
            return rc == JM_ENOENT || rc == JM_ESTORE ? rc : JM_EACTIVE;
    }
    /* A queued job that started meanwhile is still "running" in the store: refused. */
    int rc = job_store_delete(jm->store, id);
    /* Its shared files (possibly many, on a network file system) go in the probe thread's sweep,
     * not in this HTTP handler. */
    if (rc == AA_OK)
        cluster_probe_housekeep_soon(jm->probe);
    return rc == AA_OK               ? JM_OK
           : rc == JOB_STORE_ENOENT  ? JM_ENOENT
           : rc == JOB_STORE_EACTIVE ? JM_EACTIVE
                                     : JM_ESTORE;
}

void job_manager_slurm_status(job_manager *jm, cluster_status *out)
{
    cluster_probe_status(jm->probe, out);
}
