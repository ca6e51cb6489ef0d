/* The job manager's private state, shared by its parts (job_manager.h is the public API):
 *   job_manager.c  create and destroy, submit, get, list, cancel, purge, stats
 *   job_schedule.c the queue, fair-share scheduling, job threads and their final write
 *   job_slurm.c    jobs with executor "slurm": the thread that drives cluster_driver.h
 *   job_recovery.c unfinished jobs at start-up, the shared-directory sweep
 *   job_ctx.c      what a running kind sees of its job (job_ctx_impl.h)
 * One mutex (job_manager.lock) guards every field below unless a comment says otherwise; a
 * function named *_locked is called with it held and says so with ASSERT_LOCK_HELD(&jm->lock)
 * (lock_held.h). */
#ifndef AALAB_JOB_MANAGER_IMPL_H
#define AALAB_JOB_MANAGER_IMPL_H

#include <assert.h>
#include <errno.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>

#include <jansson.h>

#include "fair_share.h"
#include "job_ctx_impl.h"
#include "job_manager.h"
#include "lock_held.h"

#define COUNTS_MAX_AGE 0.25 /* seconds */

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
    bool unstored;     /* ended, but its end is not in the store yet (disk full): jm_finish_job
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

/* job_manager.c: a job's memory (NULL when out of memory) and its release. */
job *jm_job_new(void);
void jm_job_free(job *j);

/* job_schedule.c. The queue and the active list (lock held, except while job_manager_create
 * recovers jobs on its own thread). */
int jm_queue_push(job_manager *jm, job *j);
void jm_queue_remove(job_manager *jm, job *j);
void jm_active_remove(job_manager *jm, job *j);
job *jm_active_find(job_manager *jm, long long id);
/* Starts fn(arg) on a detached thread: 0, or pthread_create's error. */
int jm_start_detached(void *(*fn)(void *), void *arg);
/* Hands free workers to waiting jobs, by fair share (lock held). */
void jm_schedule_locked(job_manager *jm);
/* Ends job j's run (rc, its result and error): writes its final record, frees its worker and j.
 * failure: a message longer than err's (a Slurm shard's log tail), or NULL/"". */
void jm_finish_job(job_manager *jm, job *j, int rc, json_t *result, const aa_error *err,
                   const char *failure);

/* job_slurm.c. Starts a Slurm job's thread (lock held); false when no thread could start. */
bool jm_slurm_start_locked(job_manager *jm, job *j);
/* Why a job with executor "slurm" cannot be taken now (AA_EINVAL for a kind without a split,
 * JM_ESLURM), or AA_OK. Reads the probe's last answer: never waits for Slurm. */
int jm_slurm_refusal(job_manager *jm, const job_kind *kind, aa_error *err);

/* job_recovery.c. Re-queues the store's unfinished jobs (or ends them interrupted with a
 * reason), starts the Slurm ones and schedules; once, at start-up. */
void jm_recover_jobs(job_manager *jm);
/* The probe thread's housekeeping (cluster_probe_start): removes the shared files of deleted
 * jobs. */
void jm_sweep_shared_dir(void *jm);

/* job_ctx.c. The context a job's thread hands its kind (or the Slurm driver). */
struct job_ctx job_ctx_of(job_manager *jm, job *j);

#endif
