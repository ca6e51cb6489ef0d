/* The local executor of splittable kinds (job_split_local.h). */
#include "job_split_local.h"

#include <math.h>
#include <stdlib.h>

/* One shard's reports -> the job: its progress onto [base, base + span] of the job's, its trace
 * continued after the shards before it, its best so far when it beats the job's. */
typedef struct local_shard {
    job_ctx *ctx;
    double base, span;
    double seconds_before; /* the finished shards' work, where this shard's trace continues */
    long iterations_before, evaluations_before;
    job_trace_point last; /* this shard's latest point, in its own counts */
    double best_posted;   /* best E2 forwarded to the job */
} local_shard;

static bool local_progress(void *user, double fraction, json_t *best_so_far)
{
    local_shard *l = user;
    json_t *forward = NULL;
    const json_t *e2 = json_object_get(best_so_far, "e2");
    if (json_is_number(e2) && json_number_value(e2) < l->best_posted) {
        l->best_posted = json_number_value(e2);
        forward = best_so_far;
    }
    return job_ctx_progress(l->ctx, l->base + l->span * fmin(fmax(fraction, 0), 1), forward);
}

static void local_trace(void *user, const job_trace_point *p)
{
    local_shard *l = user;
    l->last = *p;
    job_trace_point tp = {l->seconds_before + p->seconds, l->iterations_before + p->iterations,
                          l->evaluations_before + p->evaluations, p->best_e2};
    job_ctx_trace(l->ctx, &tp); /* keeps improvements only */
}

static int run_stage(const job_split *split, void *params, int stage, const json_t *prior,
                     local_shard *l, json_t **merged, aa_error *err)
{
    json_t *shards = NULL;
    int rc = split->plan(params, stage, prior, 1, &shards, err);
    if (rc)
        return rc;
    size_t n = json_array_size(shards);
    json_t **outputs = calloc(n ? n : 1, sizeof *outputs);
    if (!outputs || n == 0)
        rc = outputs ? aa_error_set(err, AA_EINVAL, "", "the plan has no shards")
                     : aa_error_set(err, AA_ENOMEM, "", "out of memory");
    double base, span;
    job_split_stage_span(split, stage, &base, &span);
    int w = job_ctx_workers(l->ctx);
    shard_ctx sc = {local_progress, local_trace, l, job_ctx_clock(l->ctx),
                    w < 1    ? 1
                    : w > 64 ? 64
                             : w};
    for (size_t i = 0; !rc && i < n; i++) {
        l->base = base + span * (double)i / (double)n;
        l->span = span / (double)n;
        l->last = (job_trace_point){0, 0, 0, INFINITY};
        rc = split->run_shard(params, stage, json_array_get(shards, i), prior, &sc, &outputs[i],
                              err);
        l->seconds_before += l->last.seconds;
        l->iterations_before += l->last.iterations;
        l->evaluations_before += l->last.evaluations;
    }
    if (!rc)
        rc = split->merge(params, stage, outputs, n, prior, merged, err);
    for (size_t i = 0; outputs && i < n; i++)
        json_decref(outputs[i]);
    free(outputs);
    json_decref(shards);
    return rc;
}

int job_split_run_local(const job_split *split, void *params, job_ctx *ctx, void **result,
                        aa_error *err)
{
    *result = NULL;
    local_shard l = {ctx, 0, 1, 0, 0, 0, {0, 0, 0, INFINITY}, INFINITY};
    json_t *prior = NULL;
    int rc = AA_OK;
    for (int stage = 0; !rc && stage < split->stages; stage++) {
        json_t *merged = NULL;
        rc = run_stage(split, params, stage, prior, &l, &merged, err);
        json_decref(prior);
        prior = merged;
    }
    if (!rc && job_ctx_cancelled(ctx))
        rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
    if (!rc)
        rc = split->finish(params, prior, "local", 1, result, err);
    json_decref(prior);
    return rc;
}
