/* The Slurm executor of one job: for each stage of the kind's split (job_split.h) it plans at
 * most --slurm-max-tasks shards, writes their TASK.json files and array.sh under the shared
 * directory (cluster_layout.h) and submits one `sbatch --array`; then it polls (squeue first,
 * then the output files) every --slurm-poll seconds. A shard that left the queue without an
 * output (for 3 polls in a row: shared filesystems may show a node's file late) failed: it is
 * resubmitted once (`sbatch --array=<i>`), and a second failure fails the job, naming the shard,
 * Slurm's state for it and the tail of its log. When every shard of a stage has its output the
 * outputs merge in shard order; after the last stage split->finish makes the kind's result.
 *
 * Everything needed to re-attach is the state JSON the driver hands to io->save whenever it
 * changes (array ids per stage, which shard runs in which array, which were retried, when the
 * job was submitted); running the driver again with that state re-attaches: nothing with an
 * output is resubmitted, and arrays still running are polled as before.
 *
 * Runs on a thread of its own (it blocks on Slurm commands and sleeps between polls). */
#ifndef AALAB_CLUSTER_DRIVER_H
#define AALAB_CLUSTER_DRIVER_H

#include <stddef.h>

#include <jansson.h>

#include "aa_core.h"
#include "cluster_config.h"
#include "service_error.h"
#include "job_kind.h"

/* CLUSTER_EDETACHED, _ESHARD, _ESLURM (proto/service_error.h) */
enum { PROTO_SERVICE_CLUSTER_ERRORS(PROTO_SERVICE_AS_ENUM) };

typedef enum cluster_stop {
    CLUSTER_GO,     /* keep going */
    CLUSTER_CANCEL, /* scancel every array of the job and end cancelled */
    CLUSTER_DETACH  /* leave the arrays running and return (daemon shutdown) */
} cluster_stop;

/* How the driver reports to its owner (the job manager, or a test). */
typedef struct cluster_job_io {
    cluster_stop (*check)(void *user);
    /* progress 0..1, best so far ({"pattern","e2"} or NULL) and the merged trace (array),
     * borrowed for the call. */
    void (*report)(void *user, double progress, const json_t *best, const json_t *trace);
    /* The re-attach state changed (borrowed): persist it. */
    void (*save)(void *user, const json_t *state);
    void *user;
} cluster_job_io;

typedef struct cluster_job {
    long long id;
    const job_kind *kind; /* kind->split must be set */
    const void *params;   /* kind->decode's */
    const json_t *spec;   /* the kind's spec (a "kind" key is dropped from TASK.json) */
    const json_t *state;  /* the stored state to re-attach to, or NULL for a new job */
} cluster_job;

/* AA_OK with *result (the kind's typed result, free with kind->free_result); AA_ECANCELED after
 * a cancel (the arrays are gone from squeue, or a bounded wait passed); CLUSTER_EDETACHED; or
 * another negative code with err filled and, when a shard failed, the whole message (longer
 * than aa_error's) in failure. */
int cluster_driver_run(const cluster_config *cfg, const cluster_job *job, const cluster_job_io *io,
                       void **result, char *failure, size_t failure_cap, aa_error *err);

/* The number of stored states' arrays, for tests: every array id of a state in ids (at most
 * cap), returns how many there are. */
size_t cluster_state_arrays(const json_t *state, long long *ids, size_t cap);

#endif
