/* A job kind is what the worker pool can run; the kinds are the rows jobs/kind_list.h lists (GET
 * /v1/kinds lists them with their schemas). Each kind validates its spec when the job is submitted
 * (so a bad spec is a 400 naming the field, never a failed job) and runs on a worker thread, where
 * it reports progress and its error-against-run-time trace through job_ctx and stops promptly when
 * job_ctx_cancelled() becomes true. Kinds live in one file each (jobs/kind_<id>.c, which defines
 * the kind's row) and are listed in jobs/kind_list.h. */
#ifndef AALAB_JOB_KIND_H
#define AALAB_JOB_KIND_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_core.h"

typedef struct job_ctx job_ctx;

typedef struct job_trace_point {
    double seconds;   /* wall time since the job started running */
    long iterations;  /* optimizer steps so far (all seeds) */
    long evaluations; /* E2 evaluations so far */
    double best_e2;   /* best E2 so far */
} job_trace_point;

/* Progress 0..1 and, optionally, the best result so far (borrowed; NULL keeps the previous):
 * {"pattern": an encoded pattern, "e2": its E2} (either may be missing; the job list reads
 * best_e2 and family from them).
 * Returns true if the job has been cancelled, has run past --max-job-seconds, or the daemon is
 * shutting down: stop then. This is also where a job yields its worker to a waiting user when
 * its slice is over (fair share): the call then returns only when the job has a worker again,
 * so a kind that reports progress regularly needs nothing else to share the machine. */
bool job_ctx_progress(job_ctx *ctx, double fraction, json_t *best_so_far);
/* Appends a trace point; the context keeps every improvement but at most 10 points a second. */
void job_ctx_trace(job_ctx *ctx, const job_trace_point *point);
bool job_ctx_cancelled(const job_ctx *ctx);
/* Who the job belongs to (uid, -1 unknown) and whether it is private: what the job makes for
 * others to fetch (tiles) gets the same owner and visibility. */
long long job_ctx_owner(const job_ctx *ctx);
bool job_ctx_private(const job_ctx *ctx);
/* The job's own clock for time budgets (engine aa_clock): it stands still while the job is
 * paused for another user, so a pause costs the job none of its budget. */
aa_clock job_ctx_clock(job_ctx *ctx);
int job_ctx_workers(const job_ctx *ctx); /* threads a job may use for its own parallel work */
/* Maps an engine progress callback's fraction 0..1 onto [base, base + span] of the job's
 * progress; pass job_progress_span_report as the callback and the span as its user pointer.
 * Returns nonzero when the job is cancelled, as engine callbacks expect. */
typedef struct job_progress_span {
    job_ctx *ctx;
    double base, span;
} job_progress_span;
int job_progress_span_report(void *user, double fraction);
/* The daemon's tile store, where render kinds put the images they make; NULL when the daemon
 * runs without one (the kinds then return no tile references). */
typedef struct tile_store tile_store;
tile_store *job_ctx_tiles(job_ctx *ctx);

/* One row of the table of kinds (job_kind_<id> in kind_<id>.c). The envelope (kind, label,
 * priority, visibility, pinned) is the job manager's: a kind's decode never sees those keys. */
typedef struct job_kind {
    const char *name;
    const char *summary; /* one sentence, served by GET /v1/kinds */
    /* Offered only when the daemon runs with --enable-test-kinds (the harmless "sleep" kind
     * that the tests drive; a release daemon does not run it). */
    bool test_only;
    /* spec: the POST /v1/jobs body without the envelope. On error fill err (field relative to
     * the body, e.g. "seeds") and return a negative AA_E* code. */
    int (*decode)(const json_t *spec, void **params, aa_error *err);
    void (*free_params)(void *params);
    /* The family the spec names (the job list's "family" until a best pattern replaces it), or
     * NULL; may itself be NULL. */
    const char *(*spec_family)(const void *params);
    /* The time budget the spec asks for (the daemon refuses one above --max-job-seconds);
     * NULL for kinds without one. */
    double (*max_seconds)(const void *params);
    /* Runs on a worker. On success *result is the kind's typed result (its proto result
     * struct, owned by the caller: free it with free_result). Return AA_OK, AA_ECANCELED when
     * cancelled, or another negative code with err filled (and *result left NULL). */
    int (*run)(void *params, job_ctx *ctx, void **result, aa_error *err);
    /* The wire form of a typed result run made (the kind's proto encoder); NULL when out of
     * memory. */
    json_t *(*encode_result)(const void *result);
    void (*free_result)(void *result);
    /* The best pattern (encoded, new reference; NULL: none) and its E2 (NaN when the kind
     * gives none) of a result this kind made, read through the kind's result decoder; NULL for
     * kinds whose results hold no best pattern. */
    json_t *(*best_of)(const json_t *result, double *e2);
    /* How the kind splits into shards (job_split.h), or NULL: only kinds with a split run with
     * "executor": "slurm". */
    const struct job_split *split;
} job_kind;

const job_kind *job_kind_find(const char *name);
/* The table (the rows in kind_list.h's order), and its length. */
const job_kind *const *job_kinds_table(size_t *count);

#endif
