/* Job kind "family-sweep" (Hasselgren et al. Fig. 3 workflow): enumerate the mirrored
 * P(4,1+,n) placement configurations of a cost, optimise each from K seeds, rank by E2 and keep
 * every configuration's best pattern. The spec is proto/job_family_sweep.h.
 * The time budget is split evenly over the configurations. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "aa_pattern.h"
#include "job_family_sweep.h"
#include "kinds.h"
#include "optimizer_bridge.h"

JOB_KIND_SPEC_PARAMS(kind_family_sweep, proto_family_sweep_spec, proto_decode_family_sweep_spec,
                     proto_family_sweep_spec_free)

double kind_family_sweep_max_seconds(const void *params)
{
    return ((const proto_family_sweep_spec *)params)->common.max_seconds;
}

const char *kind_family_sweep_family(const void *params)
{
    const proto_family_sweep_spec *sp = params;
    return sp->family[0] ? sp->family : NULL;
}

json_t *kind_family_sweep_best_of(const json_t *result, double *e2)
{
    proto_family_sweep_result r;
    aa_error err = {0};
    *e2 = NAN;
    if (proto_decode_family_sweep_result(result, &r, &err))
        return NULL;
    json_t *best = NULL;
    if (r.ranked_count && r.ranked[0].have_best) {
        *e2 = r.ranked[0].e2;
        best = proto_encode_pattern(&r.ranked[0].best);
    }
    proto_family_sweep_result_free(&r);
    return best;
}

static int row_cmp(const void *a, const void *b)
{
    const proto_sweep_row *x = a, *y = b;
    return (x->e2 > y->e2) - (x->e2 < y->e2);
}

static int family_sweep_run(void *params, job_ctx *ctx, proto_family_sweep_result *out,
                            aa_error *err)
{
    proto_family_sweep_spec *sp = params;
    aa_metric_params metric = proto_optimizer_spec_metric(&sp->common);
    aa_mirrored_config *configs;
    size_t count;
    int rc = aa_enumerate_mirrored(sp->cost, &configs, &count, err);
    if (rc)
        return rc;
    proto_sweep_row *rows = calloc(count ? count : 1, sizeof *rows);
    aa_pattern *seeds = calloc(sp->per_config, sizeof *seeds);
    if (!rows || !seeds) {
        free(rows);
        free(seeds);
        free(configs);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    opt_job_bridge b = {ctx, 0, 0, 0, 0, 0, INFINITY, -1};
    size_t done = 0;
    for (size_t c = 0; c < count && !rc; c++) {
        rows[c].config = configs[c];
        rows[c].e2 = INFINITY;
        aa_rng rng;
        aa_rng_seed(&rng, sp->common.rng_seed, (uint64_t)c);
        size_t made = 0;
        for (; made < sp->per_config && !rc; made++) {
            aa_seed_kind kind =
                sp->kind_count ? sp->kinds[made % sp->kind_count] : (aa_seed_kind)(made % 5);
            rc = aa_mirrored_config_seed(&configs[c], kind, &sp->common.filter, &rng, &seeds[made],
                                         err);
        }
        aa_multistart_params mp;
        aa_multistart_params_default(&mp);
        mp.local.mode = sp->common.mode;
        /* Mirrored configurations are never tiled without border samples. */
        mp.local.method = proto_optimizer_spec_method(&sp->common, false, sp->common.mode);
        mp.local.grid_bits = sp->common.grid_bits;
        mp.local.d3d12_range = sp->common.d3d12;
        mp.local.max_iterations = 20000;
        mp.local.clock = job_ctx_clock(ctx);
        mp.local.stall_iterations = 300;
        mp.seeds = seeds;
        mp.seed_count = sp->per_config;
        mp.rng_seed = sp->common.rng_seed;
        int w = job_ctx_workers(ctx);
        mp.workers = w < 1 ? 1 : w > 64 ? 64 : w;
        mp.max_seconds = sp->common.max_seconds / (double)count;
        b.base = (double)c / (double)count;
        b.span = 1.0 / (double)count;
        aa_pattern best;
        aa_multistart_result r;
        if (!rc)
            rc = aa_multistart(&mp, &metric, opt_job_progress, &b, &best, &r, err);
        if (!rc) {
            rows[c].e2 = r.e2;
            rows[c].best = best; /* the row owns it now */
            rows[c].have_best = true;
            b.iterations_before += r.iterations;
            b.evaluations_before += r.evaluations;
            b.seconds_before += r.seconds;
            done++;
            aa_multistart_result_free(&r);
        }
        for (size_t i = 0; i < made; i++)
            aa_pattern_free(&seeds[i]);
        if (!rc && job_ctx_cancelled(ctx))
            rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
    }
    if (!rc) {
        qsort(rows, count, sizeof *rows, row_cmp);
        for (size_t c = 0; c < count; c++) {
            rows[c].rank = (long)c + 1;
            rows[c].cost = aa_mirrored_config_cost(&rows[c].config);
        }
    }
    *out = (proto_family_sweep_result){.cost = sp->cost,
                                       .configurations = (long)count,
                                       .seeds_per_config = (long)sp->per_config,
                                       .ranked = rows,
                                       .ranked_count = count}; /* frees rows */
    free(seeds);
    free(configs);
    return rc;
}

JOB_KIND_RESULT(kind_family_sweep, proto_family_sweep_result, family_sweep_run,
                proto_encode_family_sweep_result, proto_family_sweep_result_free)
