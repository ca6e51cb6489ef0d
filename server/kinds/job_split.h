/* How a job kind splits into shards and how shard outputs merge: the contract the local run, the
 * batch worker (aalab-worker) and the Slurm executor (server/cluster/) share.
 *
 * A splittable kind runs in one or more stages. Each stage is a list of independent shards
 * (plan); a shard runs anywhere, in the daemon or in aalab-worker on a cluster node (run_shard),
 * and its output is JSON; the outputs of a stage merge, in shard order, into the stage's merged
 * state (merge), which the next stage's plan and shards read as `prior`; finish turns the last
 * merged state into the kind's typed result (job_kind.run's result).
 *
 * Determinism: a shard's output depends on (spec, stage, shard descriptor, prior) only, and
 * merge depends on the outputs in shard order, so with a clock-free budget (max_iterations and
 * no max_seconds) a job's result is the same for any number of shards: seed i's random stream
 * is (rng_seed, i) whichever shard runs it. The local executor runs the same stages with one
 * shard per stage where it can (the kind's plan with max_shards = 1).
 *
 * Shard descriptors, outputs and merged states are the kind's own JSON, opaque to the executors;
 * they travel in TASK.json files (docs/cluster.md) and must round-trip through JSON exactly
 * (numbers as reals printed with 17 significant digits, patterns with the codec). */
#ifndef AALAB_JOB_SPLIT_H
#define AALAB_JOB_SPLIT_H

#include <stdbool.h>
#include <stddef.h>

#include <jansson.h>

#include "aa_core.h"
#include "job_kind.h"

/* Where a running shard reports: the daemon's job (through job_ctx) or aalab-worker's files. */
typedef struct shard_ctx {
    /* Progress of this shard 0..1 and optionally its best so far ({"pattern", "e2"}, borrowed,
     * NULL keeps the previous). Returns true when the shard must stop (cancelled, SIGTERM). */
    bool (*progress)(void *user, double fraction, json_t *best_so_far);
    /* A trace point, seconds since the shard started, counts of this shard only. */
    void (*trace)(void *user, const job_trace_point *point);
    void *user;
    aa_clock clock; /* the shard's clock for time budgets */
    int workers;    /* threads the shard may use (1..64) */
} shard_ctx;

#define JOB_SPLIT_STAGES_MAX 4

typedef struct job_split {
    int stages; /* 1 (optimize, family-sweep, table3) or 2 (random-stats) */
    /* Each stage's share of the job's progress, summing to 1; all 0 = equal shares. The local
     * executor and the Slurm driver both report progress by these (job_split_stage_span). */
    double stage_weight[JOB_SPLIT_STAGES_MAX];
    /* The shards of stage `stage` as a new JSON array of descriptors (at least one, at most
     * max_shards unless the stage has a fixed number of parts), given the previous stage's
     * merged state (NULL for stage 0). */
    int (*plan)(const void *params, int stage, const json_t *prior, size_t max_shards,
                json_t **shards, aa_error *err);
    /* Runs one shard; *output: new JSON. AA_ECANCELED when ctx said stop. */
    int (*run_shard)(const void *params, int stage, const json_t *shard, const json_t *prior,
                     const shard_ctx *ctx, json_t **output, aa_error *err);
    /* Merges a stage's outputs (outputs[i] is shard i's) into *merged (new JSON). */
    int (*merge)(const void *params, int stage, json_t *const *outputs, size_t count,
                 const json_t *prior, json_t **merged, aa_error *err);
    /* The typed result (the kind's proto result struct, free with job_kind.free_result) from the
     * last stage's merged state. executor ("local" or "slurm") and shards (the most shards a
     * stage had) are recorded in the result. */
    int (*finish)(const void *params, const json_t *merged, const char *executor, size_t shards,
                  void **result, aa_error *err);
    /* The best pattern ({"pattern", "e2"}, new reference) of one shard output, or NULL: the
     * executors show the best finished shard's as the job's best so far. */
    json_t *(*best_of_output)(const void *params, int stage, const json_t *output);
} job_split;

/* The part [*base, *base + *span] of the job's progress that stage `stage` fills. */
static inline void job_split_stage_span(const job_split *split, int stage, double *base,
                                        double *span)
{
    double total = 0, before = 0;
    for (int s = 0; s < split->stages && s < JOB_SPLIT_STAGES_MAX; s++) {
        total += split->stage_weight[s];
        if (s < stage)
            before += split->stage_weight[s];
    }
    if (total <= 0) {
        *base = (double)stage / split->stages;
        *span = 1.0 / split->stages;
    } else {
        *base = before / total;
        *span = split->stage_weight[stage] / total;
    }
}

#endif
