/* Whether Slurm answers, for GET /v1/health and for the submit of a Slurm job: a thread runs
 * `scontrol ping` every CLUSTER_PROBE_INTERVAL seconds so that no HTTP handler ever waits for
 * Slurm; readers get the last answer. */
#ifndef AALAB_CLUSTER_PROBE_H
#define AALAB_CLUSTER_PROBE_H

#include <stdbool.h>

#include "aa_core.h"

#define CLUSTER_PROBE_INTERVAL 5.0

typedef struct cluster_probe cluster_probe;

typedef struct cluster_status {
    bool configured;
    int answering; /* 1 yes, 0 no, -1 not known yet (health: null) */
    char message[240];
} cluster_status;

/* Housekeeping the probe thread runs at its first round and then every
 * CLUSTER_HOUSEKEEPING_INTERVAL seconds (the job manager removes the shared files of deleted
 * jobs, cluster_sweep.h); NULL: none. */
#define CLUSTER_HOUSEKEEPING_INTERVAL 60.0
typedef void (*cluster_housekeeping_fn)(void *user);

/* configured false: no thread; the status says Slurm is not configured. NULL when out of
 * memory or no thread could start (err). */
cluster_probe *cluster_probe_start(bool configured, cluster_housekeeping_fn housekeeping,
                                   void *user, aa_error *err);
void cluster_probe_status(cluster_probe *p, cluster_status *out);
/* Asks the thread to run the housekeeping now rather than at its next interval (a purge: the
 * handler does not unlink a job's shared files itself). No thread: nothing happens. */
void cluster_probe_housekeep_soon(cluster_probe *p);
void cluster_probe_stop(cluster_probe *p); /* joins the thread; NULL is fine */

#endif
