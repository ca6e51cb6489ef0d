/* Persistent job records in SQLite (WAL) under the state directory: spec, owner, state,
 * progress, best-so-far, trace, result, error and timestamps, plus the columns the job list
 * reads (best_e2, family, visibility, pinned) and the bytes each job occupies.
 *
 * One write connection behind the store mutex; reads go through a small pool of read
 * connections (WAL readers never block the writer), so a long listing never delays a progress
 * write or a single-job lookup. No JSON is parsed under the store mutex.
 *
 * Bounds: each owner's jobs may occupy at most the user quota (job_store_set_user_quota):
 * an insert that would take the owner over it fails with JOB_STORE_EQUOTA, a progress write
 * that would is dropped (best and trace stay as they were), and a finishing job whose result
 * would is stored as failed with error "quota_exceeded" and without best/trace/result.
 * Derived pattern keys (kernels_expanded) are not stored; job_store_get re-derives them. */
#ifndef AALAB_JOB_STORE_H
#define AALAB_JOB_STORE_H

#include <stdbool.h>
#include <sys/types.h>

#include <jansson.h>

#include "aa_core.h"
#include "service_error.h"

typedef struct job_store job_store;

/* Messages of a refused change of job %lld, the same whether the store or the job manager
 * refuses (the code's row in proto/service_error.h gives the status and the field). */
#define JOB_MSG_NOT_FOUND "no job %lld"
#define JOB_MSG_UNWRITABLE                                                                         \
    "the job store cannot be written now (disk full or I/O error); job %lld is unchanged: try "    \
    "again later"
#define JOB_MSG_RUNNING                                                                            \
    "job %lld is running: cancel it (DELETE without purge) and purge it when it has ended"

typedef enum job_state {
    JOB_QUEUED,
    JOB_RUNNING,
    JOB_DONE,
    JOB_FAILED,
    JOB_CANCELLED,
    JOB_INTERRUPTED
} job_state;
#define JOB_STATE_COUNT 6

/* JOB_STORE_EQUOTA, _ENOENT, _EACTIVE and _EUNAVAILABLE (proto/service_error.h). EUNAVAILABLE:
 * the database cannot be written now (disk full, I/O error, locked): worth a retry, and an
 * HTTP 503, never a 404. Any write below may return it. */
enum { PROTO_SERVICE_JOB_STORE_ERRORS(PROTO_SERVICE_AS_ENUM) };

/* Bytes reserved at insert for what a job will store besides its spec: about twice the spec
 * (best and result usually carry the spec's pattern) plus this much for trace and result. */
#define JOB_STORE_RESERVE_EXTRA (256 * 1024)

const char *job_state_name(job_state s);
bool job_state_final(job_state s);
/* The state machine's edges, as the store writes them: a job leaves only queued or running.
 * queued -> running when it starts; queued or running -> done, failed, cancelled or interrupted
 * when it ends; queued or running -> queued when a restart re-queues it, running -> running
 * when a restart re-attaches it to its Slurm arrays. A final state never changes. */
bool job_state_edge_legal(job_state from, job_state to);

/* Opens or creates dir/jobs.db (migrating a database of an older schema); runs PRAGMA
 * integrity_check (AA_EINVAL if it fails). */
job_store *job_store_open(const char *dir, aa_error *err);
void job_store_close(job_store *st);
/* Bytes of stored jobs per owner; 0 = unlimited (the default). Set before use. */
void job_store_set_user_quota(job_store *st, long long bytes);

/* What a new job is stored with. visibility: "team" (NULL) or "private". */
typedef struct job_store_new {
    const char *kind;
    const json_t *spec;
    long long owner; /* < 0 = unknown (counts against no quota) */
    double created;
    const char *visibility;
    bool pinned;
    int priority;
    const char *label;  /* NULL or "": none */
    const char *family; /* the spec's family, NULL: none (the best pattern's replaces it) */
} job_store_new;

/* A new queued job. JOB_STORE_EQUOTA (err names usage and limit), JOB_STORE_EUNAVAILABLE or
 * JOB_STORE_EWRITE (err says why). A failed write of any function below is one of these two. */
int job_store_insert(job_store *st, const job_store_new *job, long long *id, aa_error *err);
int job_store_set_state(job_store *st, long long id, job_state state, double when,
                        const char *reason);
/* A job found "running" at start-up: the daemon died while running it (a graceful stop writes
 * it back as queued). Returns the new count, or -1. */
int job_store_bump_crashes(job_store *st, long long id);
/* Live fields of a running job (NULL json leaves the column unchanged). A write of best/trace
 * that would take the owner over the quota is dropped (progress is still written): returns
 * JOB_STORE_EQUOTA then. Written with synchronous=NORMAL (a lost progress write is harmless). */
int job_store_update_progress(job_store *st, long long id, double progress, const json_t *best,
                              const json_t *trace);
/* Final state with result/error (may be NULL). See the quota rule above. */
int job_store_finish(job_store *st, long long id, job_state state, double progress,
                     const json_t *best, const json_t *trace, const json_t *result,
                     const json_t *error, const char *reason, double finished);
/* Deletes a finished job's row: JOB_STORE_ENOENT, JOB_STORE_EACTIVE (queued or running), a
 * failed write; err (may be NULL) gets the JOB_MSG_* message. */
int job_store_delete(job_store *st, long long id, aa_error *err);
/* JOB_STORE_ENOENT or a failed write, with the JOB_MSG_* message in err (may be NULL). */
int job_store_set_pinned(job_store *st, long long id, bool pinned, aa_error *err);
/* Deletes finished, unpinned jobs that finished before `before` (Unix seconds). */
int job_store_sweep(job_store *st, double before, long long *deleted);

/* The job as the API shows it; full adds spec, best, trace, result (with derived pattern keys
 * re-derived). NULL if absent. */
json_t *job_store_get(job_store *st, long long id, bool full);
/* Owner (-1 = unknown), state and visibility of a job from its indexed columns; false if
 * absent. Any out pointer may be NULL. */
bool job_store_owner(job_store *st, long long id, long long *owner, job_state *state,
                     bool *private_job);

#define JOB_VIEWER_ALL (-1LL) /* sees private jobs of every owner */
typedef struct job_store_filter {
    int limit;
    int state;        /* < 0 = every state */
    const char *kind; /* NULL = every kind */
    long long viewer; /* JOB_VIEWER_ALL, a uid (private jobs of others hidden) or another
                       * negative value (only team jobs) */
} job_store_filter;
/* Newest first, summaries from indexed columns only (no JSON parsing of best/spec). */
json_t *job_store_list(job_store *st, const job_store_filter *f);
/* Jobs by state counts into counts[JOB_STATE_COUNT]. */
int job_store_counts(job_store *st, long long counts[JOB_STATE_COUNT]);
/* The same over the jobs viewer may see (job_store_filter.viewer: JOB_VIEWER_ALL, a uid, or
 * another negative value for team jobs only). */
int job_store_counts_visible(job_store *st, long long viewer, long long counts[JOB_STATE_COUNT]);

typedef struct job_store_usage {
    long long bytes; /* stored bytes plus the reserve of unfinished jobs */
    long long jobs;
    long long limit; /* the user quota, 0 = unlimited */
} job_store_usage;
int job_store_usage_of(job_store *st, long long owner, job_store_usage *out);
/* [{"owner_uid","bytes","jobs"},...] for every owner, largest first. */
json_t *job_store_usage_all(job_store *st);

/* Calls fn for every queued or running job, oldest first (restart recovery). */
/* An unfinished job as stored: its envelope (priority, visibility) beside the kind's spec. */
typedef void (*job_store_visit_fn)(void *user, long long id, const char *kind, json_t *spec,
                                   long long owner, int priority, bool private_job, job_state state,
                                   double created);
int job_store_unfinished(job_store *st, job_store_visit_fn fn, void *user);

/* The Slurm executor state of a job (cluster column, JSON; job_slurm.c, job_recovery.c and
 * cluster_driver.h): set replaces it (NULL or JSON null clears it; AA_OK, JOB_STORE_ENOENT); get
 * returns a new reference or NULL (a local job, or no such job). */
int job_store_set_cluster(job_store *st, long long id, const json_t *cluster);
json_t *job_store_get_cluster(job_store *st, long long id);

/* PRAGMA integrity_check == "ok". */
bool job_store_integrity_ok(job_store *st);

#endif
