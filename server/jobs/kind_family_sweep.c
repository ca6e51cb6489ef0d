/* Job kind "family-sweep" (Hasselgren et al. Fig. 3 workflow): enumerate the mirrored
 * P(4,1+,n) placement configurations of a cost, optimise each from K seeds, rank by E2 and keep
 * every configuration's best pattern. The spec is proto/job_family_sweep.h.
 * The time budget is split evenly over the configurations.
 * Split (job_split.h): one stage, shards of contiguous configuration ranges (configuration c's
 * seeds draw from stream (rng_seed, c) whichever shard runs it). A shard's output, and the
 * merged state, is {"rows": [{"config": index, "e2", "best": pattern|null, "iterations",
 * "evaluations", "seconds"}]} in configuration order; finish ranks them. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aa_pattern.h"
#include "codec.h"
#include "job_family_sweep.h"
#include "job_result_util.h"
#include "job_split_local.h"
#include "kinds.h"
#include "optimizer_bridge.h"
#include "split_ranges.h"

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

static int plan(const void *params, int stage, const json_t *prior, size_t max_shards,
                json_t **shards, aa_error *err)
{
    (void)prior;
    const proto_family_sweep_spec *sp = params;
    if (stage != 0)
        return aa_error_set(err, AA_EINVAL, "stage", "family-sweep has one stage");
    aa_mirrored_config *configs;
    size_t count;
    int rc = aa_enumerate_mirrored(sp->cost, &configs, &count, err);
    if (rc)
        return rc;
    free(configs);
    if (count == 0)
        return aa_error_set(err, AA_EINVAL, "cost", "no configuration of this cost");
    *shards = split_ranges(count, max_shards);
    return *shards ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
}

/* Configuration c (of count) from the spec's seeds per configuration; *row gets its result. */
static int run_config(const proto_family_sweep_spec *sp, const aa_mirrored_config *config, size_t c,
                      size_t count, aa_pattern *seeds, opt_bridge *b, json_t **row, aa_error *err)
{
    aa_metric_params metric = proto_optimizer_spec_metric(&sp->common);
    aa_rng rng;
    aa_rng_seed(&rng, sp->common.rng_seed, (uint64_t)c);
    int rc = AA_OK;
    size_t made = 0;
    for (; made < sp->per_config && !rc; made++) {
        aa_seed_distribution distribution = sp->distribution_count
                                                ? sp->distributions[made % sp->distribution_count]
                                                : (aa_seed_distribution)(made % 5);
        rc = aa_mirrored_config_seed(config, distribution, &sp->common.filter, &rng, &seeds[made],
                                     err);
    }
    aa_multistart_params mp;
    aa_multistart_params_default(&mp);
    mp.local.mode = sp->common.mode;
    /* Mirrored configurations are never tiled without border samples. */
    mp.local.method = proto_optimizer_spec_method(&sp->common, false, sp->common.mode);
    mp.local.grid_bits = sp->common.grid_bits;
    mp.local.d3d12_range = sp->common.d3d12;
    mp.local.max_iterations = proto_optimizer_spec_iterations(&sp->common, 20000);
    mp.local.clock = b->ctx->clock;
    mp.local.stall_iterations = 300;
    mp.seeds = seeds;
    mp.seed_count = sp->per_config;
    mp.rng_seed = sp->common.rng_seed;
    int w = b->ctx->workers;
    mp.workers = w < 1 ? 1 : w > 64 ? 64 : w;
    mp.max_seconds = sp->common.max_seconds / (double)count; /* 0 (none) stays none */
    aa_pattern best;
    aa_multistart_result r;
    memset(&best, 0, sizeof best);
    memset(&r, 0, sizeof r);
    if (!rc)
        rc = aa_multistart(&mp, &metric, opt_bridge_progress, b, &best, &r, err);
    for (size_t i = 0; i < made; i++)
        aa_pattern_free(&seeds[i]);
    if (rc) {
        /* A cancelled run still hands back its best so far. */
        aa_pattern_free(&best);
        aa_multistart_result_free(&r);
        return rc;
    }
    opt_bridge_add(b, r.iterations, r.evaluations, r.seconds);
    *row = json_pack("{s:I,s:o,s:o,s:I,s:I,s:o}", "config", (json_int_t)c, "e2", proto_real(r.e2),
                     "best", proto_encode_pattern(&best), "iterations", (json_int_t)r.iterations,
                     "evaluations", (json_int_t)r.evaluations, "seconds", proto_real(r.seconds));
    aa_pattern_free(&best);
    aa_multistart_result_free(&r);
    return *row ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
}

static int run_shard(const void *params, int stage, const json_t *shard, const json_t *prior,
                     const shard_ctx *ctx, json_t **output, aa_error *err)
{
    (void)prior;
    const proto_family_sweep_spec *sp = params;
    *output = NULL;
    if (stage != 0)
        return aa_error_set(err, AA_EINVAL, "stage", "family-sweep has one stage");
    aa_mirrored_config *configs;
    size_t count, first, n;
    int rc = aa_enumerate_mirrored(sp->cost, &configs, &count, err);
    if (rc)
        return rc;
    rc = split_range_decode(shard, count, &first, &n, err);
    aa_pattern *seeds = calloc(sp->per_config, sizeof *seeds);
    json_t *rows = json_array();
    if (!rc && (!seeds || !rows))
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    opt_bridge b = opt_bridge_make(ctx, 0, 0);
    for (size_t i = 0; !rc && i < n; i++) {
        b.base = (double)i / (double)n;
        b.span = 1.0 / (double)n;
        json_t *row = NULL;
        rc = run_config(sp, &configs[first + i], first + i, count, seeds, &b, &row, err);
        if (!rc && json_array_append_new(rows, row))
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
        if (!rc && opt_bridge_report(&b, (double)(i + 1) / (double)n))
            rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
    }
    if (!rc) {
        opt_bridge_end(&b);
        *output = json_pack("{s:O}", "rows", rows);
        if (!*output)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    json_decref(rows);
    free(seeds);
    free(configs);
    return rc;
}

static int merge(const void *params, int stage, json_t *const *outputs, size_t count,
                 const json_t *prior, json_t **merged, aa_error *err)
{
    (void)params;
    (void)stage;
    (void)prior;
    json_t *rows = json_array();
    int rc = rows ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t i = 0; !rc && i < count; i++) {
        json_t *part = json_object_get(outputs[i], "rows");
        if (!json_is_array(part) || json_object_size(outputs[i]) != 1)
            rc = aa_error_set(err, AA_EINVAL, "rows", "shard %zu: expected {\"rows\": [...]}", i);
        else if (json_array_extend(rows, part))
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    *merged = rc ? NULL : json_pack("{s:o}", "rows", rows);
    if (rc)
        json_decref(rows);
    else if (!*merged)
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    return rc;
}

static int decode_row(const json_t *j, size_t count, size_t *config, proto_sweep_row *row,
                      aa_error *err)
{
    json_int_t c = -1, iterations, evaluations;
    json_t *e2 = NULL, *best = NULL, *seconds = NULL;
    json_error_t je;
    if (json_unpack_ex((json_t *)j, &je, JSON_STRICT, "{s:I,s:o,s:o,s:I,s:I,s:o}", "config", &c,
                       "e2", &e2, "best", &best, "iterations", &iterations, "evaluations",
                       &evaluations, "seconds", &seconds))
        return aa_error_set(err, AA_EINVAL, "rows", "bad row: %s", je.text);
    if (c < 0 || (size_t)c >= count)
        return aa_error_set(err, AA_EINVAL, "rows", "configuration %lld out of range",
                            (long long)c);
    *config = (size_t)c;
    int rc = proto_result_real(j, "e2", &row->e2, err);
    if (!rc)
        rc = proto_result_pattern(j, "best", true, &row->best, &row->have_best, err);
    return rc;
}

static int finish(const void *params, const json_t *merged, const char *executor, size_t shards,
                  void **result, aa_error *err)
{
    const proto_family_sweep_spec *sp = params;
    *result = NULL;
    aa_mirrored_config *configs;
    size_t count;
    int rc = aa_enumerate_mirrored(sp->cost, &configs, &count, err);
    if (rc)
        return rc;
    json_t *rows = json_object_get(merged, "rows");
    proto_family_sweep_result *r = calloc(1, sizeof *r);
    proto_sweep_row *ranked = calloc(count ? count : 1, sizeof *ranked);
    bool *seen = calloc(count ? count : 1, sizeof *seen);
    if (!r || !ranked || !seen)
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    if (!rc && json_array_size(rows) != count)
        rc = aa_error_set(err, AA_EINVAL, "rows", "%zu rows for %zu configurations",
                          json_array_size(rows), count);
    size_t decoded = 0;
    for (; !rc && decoded < count; decoded++) {
        size_t c;
        rc = decode_row(json_array_get(rows, decoded), count, &c, &ranked[decoded], err);
        if (!rc && (seen[c] || c != decoded))
            rc = aa_error_set(err, AA_EINVAL, "rows", "rows out of configuration order");
        if (rc) {
            aa_pattern_free(&ranked[decoded].best);
            break;
        }
        seen[c] = true;
        ranked[decoded].config = configs[c];
    }
    if (!rc) {
        /* The same order as one run's: rows in configuration order, then sorted by E2. */
        qsort(ranked, count, sizeof *ranked, row_cmp);
        for (size_t c = 0; c < count; c++) {
            ranked[c].rank = (long)c + 1;
            ranked[c].cost = aa_mirrored_config_cost(&ranked[c].config);
        }
        *r = (proto_family_sweep_result){.cost = sp->cost,
                                         .configurations = (long)count,
                                         .seeds_per_config = (long)sp->per_config,
                                         .ranked = ranked,
                                         .ranked_count = count};
        r->run = proto_run_info_make(executor, shards, sp->common.reproducible, &sp->common.acuity);
        *result = r;
    } else {
        for (size_t i = 0; i < decoded; i++)
            aa_pattern_free(&ranked[i].best);
        free(ranked);
        free(r);
    }
    free(seen);
    free(configs);
    return rc;
}

static json_t *best_of_output(const void *params, int stage, const json_t *output)
{
    (void)params;
    (void)stage;
    const json_t *rows = json_object_get(output, "rows"), *row, *best = NULL, *best_e2 = NULL;
    size_t i;
    json_array_foreach(rows, i, row)
    {
        const json_t *e2 = json_object_get(row, "e2");
        if (json_is_number(e2) && json_is_object(json_object_get(row, "best")) &&
            (!best_e2 || json_number_value(e2) < json_number_value(best_e2))) {
            best_e2 = e2;
            best = json_object_get(row, "best");
        }
    }
    return best ? json_pack("{s:O,s:O}", "pattern", best, "e2", best_e2) : NULL;
}

const job_split kind_family_sweep_split = {.stages = 1,
                                           .plan = plan,
                                           .run_shard = run_shard,
                                           .merge = merge,
                                           .finish = finish,
                                           .best_of_output = best_of_output};

JOB_KIND_SPLIT_RESULT(kind_family_sweep, kind_family_sweep_split, proto_encode_family_sweep_result,
                      proto_family_sweep_result_free)

/* The kind's row of the table of kinds (kind_list.h). */
JOB_KIND_ROW(family_sweep, .name = "family-sweep",
             .summary =
                 "Optimises every mirrored P(4,1+,n) placement configuration of one cost and "
                 "ranks them by E2.",
             .split = &kind_family_sweep_split, JOB_KIND_FAMILY_MEMBERS(family_sweep));
