/* Persistent job records in SQLite (WAL) under the state directory: spec, owner, state,
 * progress, best-so-far, trace, result, error and timestamps. One connection behind a mutex:
 * writes are small and rare (state changes, progress at most once a second per job). */
#ifndef AALAB_JOB_STORE_H
#define AALAB_JOB_STORE_H

#include <stdbool.h>
#include <sys/types.h>

#include <jansson.h>

#include "aa_error.h"

typedef struct job_store job_store;

typedef enum job_state {
    JOB_QUEUED,
    JOB_RUNNING,
    JOB_DONE,
    JOB_FAILED,
    JOB_CANCELLED,
    JOB_INTERRUPTED
} job_state;
#define JOB_STATE_COUNT 6

const char *job_state_name(job_state s);
bool job_state_final(job_state s);

/* Opens or creates dir/jobs.db; runs PRAGMA integrity_check (AA_EINVAL if it fails). */
job_store *job_store_open(const char *dir, aa_error *err);
void job_store_close(job_store *st);

/* A new queued job; owner < 0 = unknown. */
int job_store_insert(job_store *st, const char *kind, const json_t *spec, long long owner,
                     double created, long long *id, aa_error *err);
int job_store_set_state(job_store *st, long long id, job_state state, double when,
                        const char *reason);
/* A job found "running" at start-up: the daemon died while running it (a graceful stop writes
 * it back as queued). Returns the new count, or -1. */
int job_store_bump_crashes(job_store *st, long long id);
/* Live fields of a running job (NULL json leaves the column unchanged). */
int job_store_update_progress(job_store *st, long long id, double progress, const json_t *best,
                              const json_t *trace);
/* Final state with result/error (may be NULL). */
int job_store_finish(job_store *st, long long id, job_state state, double progress,
                     const json_t *best, const json_t *trace, const json_t *result,
                     const json_t *error, const char *reason, double finished);

/* The job as the API shows it; full adds spec, best, trace, result. NULL if absent. */
json_t *job_store_get(job_store *st, long long id, bool full);
/* Newest first, at most limit, summaries; state < 0 = every state. */
json_t *job_store_list(job_store *st, int limit, int state);
/* Jobs by state counts into counts[JOB_STATE_COUNT]. */
int job_store_counts(job_store *st, long long counts[JOB_STATE_COUNT]);

/* Calls fn for every queued or running job, oldest first (restart recovery). */
typedef void (*job_store_visit_fn)(void *user, long long id, const char *kind, json_t *spec,
                                   long long owner, job_state state, double created);
int job_store_unfinished(job_store *st, job_store_visit_fn fn, void *user);

/* PRAGMA integrity_check == "ok". */
bool job_store_integrity_ok(job_store *st);

#endif
