/* The local executor of a splittable kind (job_split.h): runs the stages in turn in the daemon,
 * each planned with max_shards = 1 (a stage with a fixed number of parts runs its parts one
 * after the other), so that a local run and a Slurm run of a job compute the same thing. */
#ifndef AALAB_JOB_SPLIT_LOCAL_H
#define AALAB_JOB_SPLIT_LOCAL_H

#include "job_kind.h"
#include "job_split.h"

/* job_kind.run for a kind with a split: progress mapped onto the job (each stage fills the share
 * its split.stage_weight gives it), trace points continued from shard to shard, best so far
 * forwarded when it improves, cancel through job_ctx. The result says executor "local", 1 shard. */
int job_split_run_local(const job_split *split, void *params, job_ctx *ctx, void **result,
                        aa_error *err);

#endif
