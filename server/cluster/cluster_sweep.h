/* A job's files in the shared directory (DIR/job-<id>, cluster_layout.h) live as long as its
 * record: when the job is purged (DELETE ?purge=1) the probe thread sweeps at once, and when
 * retention (--keep-days) deletes it, the next sweep (within a minute) removes them. A failed
 * job keeps its files until then, since its error names the log of the shard that failed. */
#ifndef AALAB_CLUSTER_SWEEP_H
#define AALAB_CLUSTER_SWEEP_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_core.h"

/* Whether the daemon still has a record of job_id. */
typedef bool (*cluster_job_known_fn)(void *user, long long job_id);

/* Removes DIR/job-<id> and everything under it; AA_OK when it does not exist. */
int cluster_remove_job_dir(const char *shared_dir, long long job_id, aa_error *err);
/* Removes every DIR/job-<id> whose job known() no longer has; other entries of DIR are left
 * alone. *removed counts the directories removed. */
int cluster_sweep_orphans(const char *shared_dir, cluster_job_known_fn known, void *user,
                          size_t *removed, aa_error *err);

#endif
