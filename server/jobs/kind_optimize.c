/* Job kind "optimize": multi-start L&A sec. 5 descent for a family or from a given
 * pattern; the spec is proto/job_optimize.h.
 * For P(4,1+,n) every placement configuration is screened first (150 steps each, at most a
 * quarter of the budget) and the seeds go to the best min(seeds, 8) configurations. For tiled
 * families without border samples (mode both) each seed's optimum is refined by iterated local
 * search (aa_optimize_perturbed).
 * Split (job_split.h): one stage, shards of contiguous seed ranges; a shard's output is
 * {"result": an optimize result of its seeds, "best_seed": global index or -1 for a screened
 * configuration}; the merged state has the same shape. Every shard screens every configuration
 * (deterministic, so alike everywhere) and runs its seeds on the best ones. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "job_optimize.h"
#include "job_split_local.h"
#include "kind_optimize_scene.h"
#include "kinds.h"
#include "optimizer_bridge.h"
#include "split_ranges.h"

JOB_KIND_SPEC_PARAMS(kind_optimize, proto_optimize_spec, proto_decode_optimize_spec,
                     proto_optimize_spec_free)

double kind_optimize_max_seconds(const void *params)
{
    return ((const proto_optimize_spec *)params)->common.max_seconds;
}

const char *kind_optimize_family(const void *params)
{
    const proto_optimize_spec *op = params;
    return op->have_family ? op->family.label : NULL;
}

json_t *kind_optimize_best_of(const json_t *result, double *e2)
{
    proto_optimize_result r;
    aa_error err = {0};
    *e2 = NAN;
    if (proto_decode_optimize_result(result, &r, &err))
        return NULL;
    *e2 = r.e2;
    json_t *best = proto_encode_pattern(&r.best);
    proto_optimize_result_free(&r);
    return best;
}

/* The seeds that ran, as the result lists them (global indices). */
static proto_seed_summary *seed_summaries(const aa_multistart_result *r, size_t first,
                                          size_t *count)
{
    proto_seed_summary *s = calloc(r->seed_count ? r->seed_count : 1, sizeof *s);
    *count = 0;
    for (size_t i = 0; s && i < r->seed_count; i++) {
        const aa_multistart_seed *m = &r->per_seed[i];
        if (!isnan(m->e2))
            s[(*count)++] = (proto_seed_summary){first + i, m->distribution, m->initial_e2, m->e2,
                                                 m->iterations};
    }
    return s;
}

static int plan(const void *params, int stage, const json_t *prior, size_t max_shards,
                json_t **shards, aa_error *err)
{
    (void)prior;
    const proto_optimize_spec *op = params;
    if (stage != 0)
        return aa_error_set(err, AA_EINVAL, "stage", "optimize has one stage");
    /* A scene objective is relative to the whole job's E2 optimum: one shard
     * (kind_optimize_scene.h). */
    *shards = split_ranges(op->seeds, op->objective.enabled ? 1 : max_shards);
    return *shards ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
}

/* Seeds [first, first + count) of the job; *best_seed: global index, SIZE_MAX screened. */
static int run_seeds(const proto_optimize_spec *op, size_t first, size_t count,
                     const shard_ctx *ctx, proto_optimize_result *out, size_t *best_seed,
                     aa_error *err)
{
    aa_metric_params metric = proto_optimizer_spec_metric(&op->common);
    aa_multistart_params mp;
    aa_multistart_params_default(&mp);
    mp.local.mode = op->common.mode;
    mp.local.grid_bits = op->common.grid_bits;
    mp.local.d3d12_range = op->common.d3d12;
    mp.local.max_iterations = proto_optimizer_spec_iterations(&op->common, 20000);
    /* The spec's max_iterations bounds a seed's whole work, its refinement included. */
    mp.seed_iterations = op->common.max_iterations;
    mp.local.clock = ctx->clock;
    mp.local.stall_iterations = 500;
    mp.first_seed = first;
    mp.seed_count = count;
    mp.rng_seed = op->common.rng_seed;
    mp.workers = ctx->workers < 1 ? 1 : ctx->workers > 64 ? 64 : ctx->workers;
    mp.max_seconds = op->common.max_seconds;
    /* A scene objective: half the time for the global-E2 search, half for the scene descent. */
    if (op->objective.enabled)
        mp.max_seconds /= 2;
    if (op->have_family) {
        mp.family = &op->family;
        if (op->family.mirrored) {
            /* Screen every placement configuration (cheap: 150 steps each), then multi-start
             * on the best few; without it a handful of seeds lands on poor placements. The
             * number kept follows the job's seeds, not the shard's, so shards agree. */
            mp.screen_iterations = 150;
            mp.screen_top = op->seeds < 8 ? op->seeds : 8;
        }
        /* Tiled families stall at kinks after a few seconds per seed: refine each seed's
         * optimum by iterated local search (it resets weights, so only in mode both). */
        if (aa_family_perturbable(&op->family) && op->common.mode == AA_OPTIMIZE_BOTH)
            mp.perturb.rounds = AA_PERTURB_UNTIL_STALL;
        mp.distributions = op->distribution_count ? op->distributions : NULL;
        mp.distribution_count = op->distribution_count;
    } else {
        mp.seeds = &op->pattern;
    }
    bool tiled = op->have_family ? aa_family_perturbable(&op->family)
                                 : aa_pattern_tiled_without_border(&op->pattern);
    mp.local.method = proto_optimizer_spec_method(&op->common, tiled, op->common.mode);
    opt_bridge b = opt_bridge_make(ctx, 0, op->objective.enabled ? 0.5 : 1);
    aa_pattern best;
    aa_multistart_result r;
    int rc = aa_multistart(&mp, &metric, opt_bridge_progress, &b, &best, &r, err);
    if (rc) {
        aa_pattern_free(&best);
        aa_multistart_result_free(&r);
        return rc;
    }
    opt_bridge_add(&b, r.iterations, r.evaluations, r.seconds);
    opt_bridge_end(&b);
    *best_seed = r.best_seed;
    *out = (proto_optimize_result){.best = best,
                                   .e2 = r.e2,
                                   .argmax_kernel = (int)r.argmax_kernel,
                                   .argmax_angle_deg = r.argmax_angle_deg,
                                   .seeds_run = (long)r.seeds_run,
                                   .iterations = r.iterations,
                                   .evaluations = r.evaluations,
                                   .seconds = r.seconds,
                                   .method = mp.local.method,
                                   .have_grid = op->common.grid_bits != 0,
                                   .grid_bits = op->common.grid_bits,
                                   .d3d12 = op->common.d3d12,
                                   .e2_before_snap = r.e2_before_snap};
    out->per_seed = seed_summaries(&r, first, &out->per_seed_count);
    aa_multistart_result_free(&r);
    if (!out->per_seed)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    if (op->objective.enabled)
        return kind_optimize_scene_refine(op, &metric, ctx, mp.max_seconds, out, err);
    return AA_OK;
}

static json_t *shard_json(const proto_optimize_result *r, size_t best_seed)
{
    json_t *enc = proto_encode_optimize_result(r);
    if (!enc)
        return NULL;
    return json_pack("{s:o,s:I}", "result", enc, "best_seed",
                     best_seed == SIZE_MAX ? (json_int_t)-1 : (json_int_t)best_seed);
}

static int run_shard(const void *params, int stage, const json_t *shard, const json_t *prior,
                     const shard_ctx *ctx, json_t **output, aa_error *err)
{
    (void)prior;
    const proto_optimize_spec *op = params;
    *output = NULL;
    if (stage != 0)
        return aa_error_set(err, AA_EINVAL, "stage", "optimize has one stage");
    size_t first, count, best_seed;
    int rc = split_range_decode(shard, op->seeds, &first, &count, err);
    if (rc)
        return rc;
    proto_optimize_result r;
    memset(&r, 0, sizeof r);
    rc = run_seeds(op, first, count, ctx, &r, &best_seed, err);
    if (!rc && !(*output = shard_json(&r, best_seed)))
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    proto_optimize_result_free(&r);
    return rc;
}

/* A shard output or merged state decoded. */
static int decode_state(const json_t *j, proto_optimize_result *r, json_int_t *best_seed,
                        aa_error *err)
{
    json_t *result = NULL;
    json_error_t je;
    memset(r, 0, sizeof *r);
    if (json_unpack_ex((json_t *)j, &je, JSON_STRICT, "{s:o,s:I}", "result", &result, "best_seed",
                       best_seed))
        return aa_error_set(err, AA_EINVAL, "output", "expected {\"result\",\"best_seed\"}: %s",
                            je.text);
    return proto_decode_optimize_result(result, r, err);
}

/* The order of one run's choice: lowest E2; on a tie a focused seed before the screened
 * configuration (aa_multistart keeps the screen's only when strictly better), then the lowest
 * seed. NaN (no seed ran) loses. */
static bool better(double e2, json_int_t seed, double best_e2, json_int_t best_seed)
{
    if (isnan(e2))
        return false;
    if (isnan(best_e2) || e2 != best_e2)
        return isnan(best_e2) || e2 < best_e2;
    if ((seed < 0) != (best_seed < 0))
        return seed >= 0;
    return seed < best_seed;
}

static int merge(const void *params, int stage, json_t *const *outputs, size_t count,
                 const json_t *prior, json_t **merged, aa_error *err)
{
    (void)params;
    (void)stage;
    (void)prior;
    *merged = NULL;
    if (count == 0)
        return aa_error_set(err, AA_EINVAL, "outputs", "no shard outputs");
    proto_optimize_result *rs = calloc(count, sizeof *rs);
    json_int_t *seeds = calloc(count, sizeof *seeds);
    size_t per_seed = 0, win = 0;
    int rc = rs && seeds ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
    size_t decoded = 0;
    for (; !rc && decoded < count; decoded++) {
        rc = decode_state(outputs[decoded], &rs[decoded], &seeds[decoded], err);
        if (rc)
            break;
        per_seed += rs[decoded].per_seed_count;
        if (decoded > 0 && better(rs[decoded].e2, seeds[decoded], rs[win].e2, seeds[win]))
            win = decoded;
    }
    proto_optimize_result m;
    memset(&m, 0, sizeof m);
    if (!rc) {
        m = rs[win]; /* shallow: the winner's pattern and scalars */
        m.seeds_run = m.iterations = m.evaluations = 0;
        m.seconds = 0;
        m.per_seed = calloc(per_seed ? per_seed : 1, sizeof *m.per_seed);
        m.per_seed_count = 0;
        if (!m.per_seed)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    for (size_t i = 0; !rc && i < count; i++) {
        /* Work adds up over shards (seconds: compute time, not wall time). */
        m.seeds_run += rs[i].seeds_run;
        m.iterations += rs[i].iterations;
        m.evaluations += rs[i].evaluations;
        m.seconds += rs[i].seconds;
        memcpy(m.per_seed + m.per_seed_count, rs[i].per_seed,
               rs[i].per_seed_count * sizeof *m.per_seed);
        m.per_seed_count += rs[i].per_seed_count;
    }
    if (!rc && !(*merged = shard_json(&m, seeds[win] < 0 ? SIZE_MAX : (size_t)seeds[win])))
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    if (m.per_seed)
        free(m.per_seed);
    for (size_t i = 0; rs && i < decoded; i++)
        proto_optimize_result_free(&rs[i]);
    free(rs);
    free(seeds);
    return rc;
}

static int finish(const void *params, const json_t *merged, const char *executor, size_t shards,
                  void **result, aa_error *err)
{
    const proto_optimize_spec *op = params;
    *result = NULL;
    proto_optimize_result *r = calloc(1, sizeof *r);
    if (!r)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    json_int_t best_seed;
    int rc = decode_state(merged, r, &best_seed, err);
    if (rc) {
        free(r);
        return rc;
    }
    r->run = proto_run_info_make(executor, shards, op->common.reproducible, &op->common.acuity);
    *result = r;
    return AA_OK;
}

static json_t *best_of_output(const void *params, int stage, const json_t *output)
{
    (void)params;
    (void)stage;
    const json_t *r = json_object_get(output, "result");
    json_t *best = json_object_get(r, "best"), *e2 = json_object_get(r, "e2");
    if (!best || !json_is_number(e2))
        return NULL;
    return json_pack("{s:O,s:O}", "pattern", best, "e2", e2);
}

const job_split kind_optimize_split = {.stages = 1,
                                       .plan = plan,
                                       .run_shard = run_shard,
                                       .merge = merge,
                                       .finish = finish,
                                       .best_of_output = best_of_output};

JOB_KIND_SPLIT_RESULT(kind_optimize, kind_optimize_split, proto_encode_optimize_result,
                      proto_optimize_result_free)

/* The kind's row of the table of kinds (kind_list.h). */
JOB_KIND_ROW(optimize, .name = "optimize",
             .summary =
                 "Multi-start optimisation of a sample pattern (a family, or a given pattern) "
                 "for the smallest worst-case error E2.",
             .split = &kind_optimize_split, JOB_KIND_FAMILY_MEMBERS(optimize));
