/* Job kind "family-sweep" (Hasselgren et al. Fig. 3 workflow): enumerate the mirrored
 * P(4,1+,n) placement configurations of a cost, optimise each from K seeds, rank by E2 and keep
 * every configuration's best pattern. Spec: {"kind":"family-sweep", "family":"P(4,1+,1.25)" |
 * "cost":1.25, "seeds_per_config":K?, "max_seconds":S?, "rng_seed":K?, "mode":...?, "method":...?,
 * "distributions":[...]?, "filter":F?, "acuity":A?, "angles":[...]?, "grid":{...}?}.
 * The time budget is split evenly over the configurations. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "aa_pattern.h"
#include "kind_optimize_spec.h"

typedef struct sweep_params {
    opt_common_spec common;
    double cost;
    size_t per_config;
    aa_seed_kind kinds[5];
    size_t kind_count;
} sweep_params;

static void sweep_free(void *params)
{
    sweep_params *sp = params;
    if (!sp)
        return;
    opt_common_free(&sp->common);
    free(sp);
}

static const char *const sweep_keys[] = {
    "kind",   "family",        "cost",   "seeds_per_config", "max_seconds", "rng_seed", "mode",
    "method", "distributions", "filter", "acuity",           "angles",      "grid",     NULL};

static int sweep_parse(const json_t *spec, void **params, aa_error *err)
{
    *params = NULL;
    int rc = opt_spec_check_keys(spec, sweep_keys, err);
    if (rc)
        return rc;
    sweep_params *sp = calloc(1, sizeof *sp);
    if (!sp)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    rc = opt_common_parse(spec, 60, &sp->common, err);
    const char *family = NULL;
    double cost = NAN;
    if (!rc)
        rc = opt_spec_string(spec, "family", &family, err);
    if (!rc)
        rc = opt_spec_number(spec, "cost", 0.25, AA_ENUMERATE_MAX_COST, &cost, err);
    if (!rc && (family != NULL) == !isnan(cost))
        rc = aa_error_set(err, AA_EINVAL, "family", "give exactly one of family and cost");
    if (!rc && family) {
        aa_family fam;
        rc = aa_family_parse(family, &fam, err);
        if (!rc && !fam.mirrored)
            rc = aa_error_set(err, AA_EINVAL, "family", "the sweep enumerates P(4,1+,n)");
        cost = fam.cost;
    }
    if (!rc) {
        aa_mirrored_config *list;
        size_t n;
        rc = aa_enumerate_mirrored(cost, &list, &n, err); /* validates the cost ("cost") */
        if (!rc)
            free(list);
    }
    sp->cost = cost;
    json_int_t k = 8;
    if (!rc)
        rc = opt_spec_integer(spec, "seeds_per_config", 1, 10000, &k, err);
    sp->per_config = (size_t)k;
    if (!rc)
        rc = opt_parse_distributions(spec, sp->kinds, &sp->kind_count, err);
    if (rc) {
        sweep_free(sp);
        return rc;
    }
    *params = sp;
    return AA_OK;
}

typedef struct sweep_row {
    aa_mirrored_config config;
    double e2;
    json_t *pattern;
} sweep_row;

static int row_cmp(const void *a, const void *b)
{
    const sweep_row *x = a, *y = b;
    return (x->e2 > y->e2) - (x->e2 < y->e2);
}

static int sweep_run(void *params, job_ctx *ctx, json_t **result, aa_error *err)
{
    sweep_params *sp = params;
    aa_metric_params metric = opt_common_metric(&sp->common);
    aa_mirrored_config *configs;
    size_t count;
    int rc = aa_enumerate_mirrored(sp->cost, &configs, &count, err);
    if (rc)
        return rc;
    sweep_row *rows = calloc(count ? count : 1, sizeof *rows);
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
        mp.local.method = opt_common_method(&sp->common, false, sp->common.mode);
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
            rows[c].pattern = proto_encode_pattern(&best);
            b.iterations_before += r.iterations;
            b.evaluations_before += r.evaluations;
            b.seconds_before += r.seconds;
            done++;
            aa_pattern_free(&best);
            aa_multistart_result_free(&r);
        }
        for (size_t i = 0; i < made; i++)
            aa_pattern_free(&seeds[i]);
        if (!rc && job_ctx_cancelled(ctx))
            rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
    }
    if (!rc) {
        qsort(rows, count, sizeof *rows, row_cmp);
        json_t *list = json_array();
        for (size_t c = 0; c < count && list; c++) {
            const aa_mirrored_config *k = &rows[c].config;
            json_array_append_new(
                list,
                json_pack("{s:I,s:{s:[IIII],s:[IIII],s:I},s:f,s:o,s:O}", "rank", (json_int_t)c + 1,
                          "config", "corners", (json_int_t)k->corners[0], (json_int_t)k->corners[1],
                          (json_int_t)k->corners[2], (json_int_t)k->corners[3], "edges",
                          (json_int_t)k->edges[0], (json_int_t)k->edges[1], (json_int_t)k->edges[2],
                          (json_int_t)k->edges[3], "interior", (json_int_t)k->interior, "cost",
                          aa_mirrored_config_cost(k), "e2", proto_real(rows[c].e2), "best",
                          rows[c].pattern ? rows[c].pattern : json_null()));
        }
        *result =
            json_pack("{s:f,s:I,s:I,s:o}", "cost", sp->cost, "configurations", (json_int_t)count,
                      "seeds_per_config", (json_int_t)sp->per_config, "ranked", list);
        if (!*result)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
        /* The winner also as the job's "best" / "e2", like the optimize kind's result. */
        if (!rc && count && rows[0].pattern) {
            json_object_set(*result, "best", rows[0].pattern);
            json_object_set_new(*result, "e2", proto_real(rows[0].e2));
        }
    }
    for (size_t c = 0; c < count; c++)
        json_decref(rows[c].pattern);
    free(rows);
    free(seeds);
    free(configs);
    return rc;
}

const job_kind job_kind_family_sweep = {
    .name = "family-sweep", .parse = sweep_parse, .run = sweep_run, .free_params = sweep_free};
