/* Job kind "optimize": multi-start L&A sec. 5 descent for a family or from a given
 * pattern; the spec is proto/job_optimize.h.
 * For P(4,1+,n) every placement configuration is screened first (150 steps each, at most a
 * quarter of the budget) and the seeds go to the best min(seeds, 8) configurations. For tiled
 * families without border samples (mode both) each seed's optimum is refined by iterated local
 * search (aa_optimize_perturbed). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "job_optimize.h"
#include "kinds.h"
#include "optimizer_bridge.h"

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

/* The seeds that ran, as the result lists them. */
static proto_seed_summary *seed_summaries(const aa_multistart_result *r, size_t *count)
{
    proto_seed_summary *s = calloc(r->seed_count ? r->seed_count : 1, sizeof *s);
    *count = 0;
    for (size_t i = 0; s && i < r->seed_count; i++) {
        const aa_multistart_seed *m = &r->per_seed[i];
        if (!isnan(m->e2))
            s[(*count)++] = (proto_seed_summary){i, m->kind, m->initial_e2, m->e2, m->iterations};
    }
    return s;
}

static int optimize_run(void *params, job_ctx *ctx, proto_optimize_result *out, aa_error *err)
{
    proto_optimize_spec *op = params;
    aa_metric_params metric = proto_optimizer_spec_metric(&op->common);
    aa_multistart_params mp;
    aa_multistart_params_default(&mp);
    mp.local.mode = op->common.mode;
    mp.local.grid_bits = op->common.grid_bits;
    mp.local.d3d12_range = op->common.d3d12;
    mp.local.max_iterations = 20000;
    mp.local.clock = job_ctx_clock(ctx);
    mp.local.stall_iterations = 500;
    mp.seed_count = op->seeds;
    mp.rng_seed = op->common.rng_seed;
    int w = job_ctx_workers(ctx);
    mp.workers = w < 1 ? 1 : w > 64 ? 64 : w;
    mp.max_seconds = op->common.max_seconds;
    if (op->have_family) {
        mp.family = &op->family;
        if (op->family.mirrored) {
            /* Screen every placement configuration (cheap: 150 steps each), then multi-start
             * on the best few; without it a handful of seeds lands on poor placements. */
            mp.screen_iterations = 150;
            mp.screen_top = op->seeds < 8 ? op->seeds : 8;
        }
        /* Tiled families stall at kinks after a few seconds per seed: refine each seed's
         * optimum by iterated local search (it resets weights, so only in mode both). */
        if (aa_family_perturbable(&op->family) && op->common.mode == AA_OPTIMIZE_BOTH)
            mp.perturb.rounds = AA_PERTURB_UNTIL_STALL;
        mp.kinds = op->kind_count ? op->kinds : NULL;
        mp.kind_count = op->kind_count;
    } else {
        mp.seeds = &op->pattern;
    }
    bool tiled = op->have_family ? aa_family_perturbable(&op->family)
                                 : aa_pattern_tiled_without_border(&op->pattern);
    mp.local.method = proto_optimizer_spec_method(&op->common, tiled, op->common.mode);
    opt_job_bridge b = {ctx, 0, 1, 0, 0, 0, INFINITY, -1};
    aa_pattern best;
    aa_multistart_result r;
    int rc = aa_multistart(&mp, &metric, opt_job_progress, &b, &best, &r, err);
    if (rc) {
        aa_pattern_free(&best);
        aa_multistart_result_free(&r);
        return rc;
    }
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
    out->per_seed = seed_summaries(&r, &out->per_seed_count);
    aa_multistart_result_free(&r);
    if (!out->per_seed)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    return AA_OK;
}

JOB_KIND_RESULT(kind_optimize, proto_optimize_result, optimize_run, proto_encode_optimize_result,
                proto_optimize_result_free)
