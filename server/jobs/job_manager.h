/* The job manager: `workers` worker slots shared by the users of one daemon, fed from a bounded
 * queue, in the manner of Redis' bio.c but with fair share. HTTP threads never run a job: they
 * validate the spec (the envelope in job_envelope.h, then the kind's parse), store the job,
 * append it to the queue under the mutex and call the scheduler. The scheduler hands each free
 * worker slot to the waiting job that fair_share.h picks (the user holding the fewest workers,
 * round robin between equals, --user-workers as a cap while others wait, priority inside a
 * user's own jobs); a queued job gets a thread of its own, which runs the kind with the mutex
 * released and writes the outcome to the SQLite store.
 *
 * Slices: at each progress report (job_ctx_progress) a job that has held its worker for
 * --job-slice seconds checks whether another user waits with fewer workers; if so it writes its
 * live state to the store (checkpoint), gives the slot back and waits on its own condition until
 * the scheduler hands it a slot again, then continues exactly where it stopped: the computation
 * is untouched and the job's clock (job_ctx_clock, the engine's time budget) stands still while
 * it waits, so results do not depend on pauses. A paused job keeps its thread and memory; a
 * daemon restart re-runs it from the start like any job that was running.
 *
 * A full queue is refused at submission (429 with Retry-After) rather than blocking a request
 * thread. Cancellation is cooperative: a flag the job polls through job_ctx_progress()/
 * job_ctx_cancelled(); a paused job is woken to stop. --max-job-seconds stops a job whose own
 * clock passes it (failed, code time_limit, best kept). At shutdown running jobs stop and are
 * written back as queued so the next start re-runs them.
 *
 * Live state (progress, best-so-far, trace) of queued and running jobs is kept in memory and
 * written to the store at most once every 5 s (job_ctx.c); finished jobs are read from the store.
 */
#ifndef AALAB_JOB_MANAGER_H
#define AALAB_JOB_MANAGER_H

#include <stdbool.h>
#include <sys/types.h>

#include <jansson.h>

#include "aa_core.h"
#include "service_error.h"
#include "cluster_config.h"
#include "cluster_probe.h"
#include "job_kind.h"
#include "job_store.h"

typedef struct job_manager job_manager;

typedef struct job_manager_config {
    int workers;
    int queue_size;    /* queued jobs beyond which submit answers JM_EQUEUE_FULL */
    int user_quota;    /* queued + running per owner */
    tile_store *tiles; /* where render kinds put their images (job_ctx_tiles); may be NULL */
    bool test_kinds;   /* offer kinds marked test_only (--enable-test-kinds) */
    /* Fair share (fair_share.h); 0 picks the default. */
    int user_workers;           /* workers one user holds while others wait (half, at least 1) */
    double slice_seconds;       /* a job yields to a waiting user after this (60) */
    double max_job_seconds;     /* ceiling on max_seconds and on running time (86400) */
    long long user_store_bytes; /* stored job bytes per owner, 0 = unlimited */
    /* The Slurm executor (cluster_driver.h); cluster.shared_dir "" = not configured. */
    cluster_config cluster;
} job_manager_config;

/* Slurm jobs running at once (each has a thread that polls Slurm; none holds a worker). */
#define JM_SLURM_JOBS_MAX 64

/* JM_ENOENT .. JM_ESLURM and their answers: proto/service_error.h */
enum { JM_OK = 0, PROTO_SERVICE_JM_ERRORS(PROTO_SERVICE_AS_ENUM) };

/* Opens the store in state_dir, re-queues unfinished jobs (or marks them interrupted with a
 * reason) and starts the workers. */
job_manager *job_manager_create(const char *state_dir, const job_manager_config *cfg,
                                aa_error *err);
/* Stops accepting, stops running jobs (written back as queued), joins the workers. */
void job_manager_shutdown(job_manager *jm);
void job_manager_destroy(job_manager *jm); /* shuts down first if needed */

/* Validates spec with the kind named spec.kind and queues the job. owner < 0 = unknown.
 * The envelope keys (job_envelope.h) are taken out of spec before the kind sees it.
 * AA_E* with err (field relative to the body) for bad specs, JM_EQUEUE_FULL, JM_EQUOTA,
 * JM_ESLURM (field "executor"), and the store's JOB_STORE_EQUOTA, _EUNAVAILABLE and _EWRITE as
 * it gives them: every code with its message in err, answered from its row
 * (proto/service_error.h).
 * A job with executor "slurm" is not queued: it starts at once on a thread of its own that
 * drives its Slurm arrays (cluster_driver.h) and holds no worker; at most JM_SLURM_JOBS_MAX
 * run at once (JM_EQUEUE_FULL beyond). At shutdown such a job is written back with its array
 * ids (the store's cluster column) and the arrays keep running; the next start re-attaches. */
int job_manager_submit(job_manager *jm, const json_t *spec, long long owner, long long *id,
                       aa_error *err);
/* The job object (full detail) or NULL. */
json_t *job_manager_get(job_manager *jm, long long id);
/* Newest first, filtered (job_store_filter). A running job listed under "queued" in the store
 * (it just started) shows its live state. */
json_t *job_manager_list(job_manager *jm, const job_store_filter *filter);
/* caller < 0 = unknown (refused unless the job has no owner). JM_ENOENT, JM_EFORBIDDEN,
 * JM_EFINISHED, JM_ESTORE (a queued job that the store cannot record as cancelled now stays
 * queued), each with its message in err (may be NULL). On success *state_out names the state
 * after the call ("cancelled" for a queued job, "running" with cancel requested for a running
 * one). */
int job_manager_cancel(job_manager *jm, long long id, long long caller, const char **state_out,
                       aa_error *err);
/* The best pattern JSON of a job (new reference), or NULL (*why: "no such job" /
 * "no pattern yet"). */
json_t *job_manager_best_pattern(job_manager *jm, long long id, const char **why);

/* The kind of that name if this daemon offers it (test-only kinds need test_kinds), else NULL. */
const job_kind *job_manager_kind(const job_manager *jm, const char *name);
/* Writes the names of the kinds this daemon offers, comma-separated, into buf. */
void job_manager_kind_names(const job_manager *jm, char *buf, size_t cap);

/* Deletes a job's record (DELETE /v1/jobs/{id}?purge=1): owner or root, as for cancel. A
 * queued job is cancelled and deleted; a running one is JM_EACTIVE (cancel it first); JM_ESTORE
 * for a job whose end is not stored yet; the store's codes of job_store_delete as it gives them.
 * Each refusal with its message in err (may be NULL).
 *
 * A job's end is written with retries; if the store still cannot take it after about 6 s, the
 * outcome is dropped and the job ends failed with error code "unavailable" as soon as the store
 * can be written (GET shows it so meanwhile), so it never stays "running" in the store. */
int job_manager_purge(job_manager *jm, long long id, long long caller, aa_error *err);

typedef struct job_manager_stats {
    int workers, busy;
    int queued, running, paused;
    int queue_size;
    long long by_state[JOB_STATE_COUNT];
} job_manager_stats;
/* by_state, queued and running count only the jobs viewer may see (job_store_filter.viewer:
 * JOB_VIEWER_ALL for root on the socket); workers, busy and paused are the shared machine's. */
void job_manager_stats_get(job_manager *jm, long long viewer, job_manager_stats *out);
/* Whether Slurm is configured and answering (the probe's last answer; never blocks). */
void job_manager_slurm_status(job_manager *jm, cluster_status *out);
job_store *job_manager_store(job_manager *jm);

#endif
