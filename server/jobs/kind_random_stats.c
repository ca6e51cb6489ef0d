/* Job kind "random-stats" (L&A Table 3): N random patterns of a distribution in a family, with
 * weights from the filter's impulse response; min / average / max E2; then the best of them
 * optimised for weights only ("Opt W") and, again from the best random pattern, for weights and
 * positions ("Opt W+P"), each with half of the remaining time budget. Opt W+P does not start
 * from Opt W: the weights-only optimum is a kink of the max where the descent finds no step in
 * the joint space either (measured, P(16,16,4) Poisson: W+P from Opt W 0.241 = Opt W, from the
 * random pattern 0.199). The spec is proto/job_random_stats.h.
 * Split (job_split.h), two stages. Stage 0: shards of contiguous pattern ranges, pattern i drawn
 * from stream (rng_seed, i) (since issue 13: before, the patterns came one after the other from
 * stream (rng_seed, 0), so results of the same spec differ from older ones; accepted, it is what
 * lets ranges reproduce one run); a shard's output is {"e2": [its patterns' E2 in order], "best":
 * pattern, "best_index", "best_e2"}, merged into {"count", "min", "avg", "max", "best_random",
 * "best_index", "best_e2"} with min / avg / max over the concatenated lists (the order one run
 * sums them in, so bit-identical for any split). With the spec's "metrics" (issue 31) a shard
 * also outputs "metrics": its patterns' figures and E2 as columns (job_point_metrics.h), merged
 * into "point_metrics" by concatenation; finish ranks them (Spearman's rho with E2), so the
 * split result equals the local one. Stage 1: two fixed shards, Opt W and Opt W+P
 * ({"stage": "opt_w" | "opt_wp"}), both from the merged best random pattern; each outputs {"e2",
 * "pattern", "method"}; the merged state is stage 0's plus "opt_w" and "opt_wp". */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aa_optimizer.h"
#include "codec.h"
#include "job_random_stats.h"
#include "job_result_util.h"
#include "job_split_local.h"
#include "kinds.h"
#include "optimizer_bridge.h"
#include "split_ranges.h"

JOB_KIND_SPEC_PARAMS(kind_random_stats, proto_random_stats_spec, proto_decode_random_stats_spec,
                     proto_random_stats_spec_free)

double kind_random_stats_max_seconds(const void *params)
{
    return ((const proto_random_stats_spec *)params)->common.max_seconds;
}

const char *kind_random_stats_family(const void *params)
{
    const proto_random_stats_spec *sp = params;
    return sp->family.label;
}

json_t *kind_random_stats_best_of(const json_t *result, double *e2)
{
    proto_random_stats_result r;
    aa_error err = {0};
    *e2 = NAN;
    if (proto_decode_random_stats_result(result, &r, &err))
        return NULL;
    *e2 = r.opt_wp.e2;
    json_t *best = proto_encode_pattern(&r.opt_wp.pattern);
    proto_random_stats_result_free(&r);
    return best;
}

/* Stream of Opt W+P's iterated local search: apart from every pattern's stream (rng_seed, i),
 * i < 10^6. */
#define PERTURB_STREAM (UINT64_C(1) << 32)

static int optimize_stage(const aa_pattern *seed, const aa_metric_params *metric,
                          aa_optimize_mode mode, aa_optimize_method method, double seconds,
                          const proto_random_stats_spec *sp, opt_bridge *b, aa_pattern *out,
                          aa_optimize_result *r, aa_error *err)
{
    aa_optimize_params op;
    aa_optimize_params_default(&op);
    op.mode = mode;
    op.method = method;
    op.max_seconds = seconds; /* 0: the search runs until it stalls */
    op.max_iterations = proto_optimizer_spec_iterations(&sp->common, 1000000);
    op.stall_iterations = 2000;
    op.clock = b->ctx->clock;
    /* Opt W+P: the descent stops at a kink within its budget, iterated local search from its
     * optimum spends the rest (as optimize jobs do for tiled families); the spec's
     * max_iterations bounds the stage's whole work. */
    aa_perturb_params pp;
    aa_perturb_params_default(&pp);
    pp.rounds = AA_PERTURB_UNTIL_STALL;
    aa_rng rng;
    aa_rng_seed(&rng, sp->common.rng_seed, PERTURB_STREAM);
    memset(r, 0, sizeof *r);
    int rc = aa_optimize_refined(seed, metric, &op, sp->common.max_iterations, &pp, &rng,
                                 opt_bridge_progress, b, out, r, err);
    opt_bridge_add(b, r->iterations, r->evaluations, r->seconds);
    return rc; /* AA_ECANCELED: the job was cancelled, *out is the best so far */
}

static int plan(const void *params, int stage, const json_t *prior, size_t max_shards,
                json_t **shards, aa_error *err)
{
    (void)prior;
    const proto_random_stats_spec *sp = params;
    if (stage == 0)
        *shards = split_ranges(sp->count, max_shards);
    else if (stage == 1)
        *shards = json_pack("[{s:s},{s:s}]", "stage", "opt_w", "stage", "opt_wp");
    else
        return aa_error_set(err, AA_EINVAL, "stage", "random-stats has two stages");
    return *shards ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
}

typedef struct random_progress {
    const shard_ctx *ctx;
    size_t count;
} random_progress;

static int random_patterns_progress(void *user, size_t i)
{
    const random_progress *rp = user;
    return rp->ctx->progress &&
           rp->ctx->progress(rp->ctx->user, (double)i / (double)rp->count, NULL);
}

static int run_patterns(const proto_random_stats_spec *sp, const json_t *shard,
                        const shard_ctx *ctx, json_t **output, aa_error *err)
{
    size_t first, count, best_index;
    int rc = split_range_decode(shard, sp->count, &first, &count, err);
    if (rc)
        return rc;
    double *e2 = calloc(count, sizeof *e2);
    if (!e2)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    aa_metric_params metric = proto_optimizer_spec_metric(&sp->common);
    random_progress rp = {ctx, count};
    aa_pattern best;
    aa_random_stats rs;
    proto_point_metrics pm;
    memset(&pm, 0, sizeof pm);
    bool figures = sp->metrics.count > 0;
    if (figures)
        rc = proto_point_metrics_init(&pm, &sp->metrics, count, err);
    if (rc) {
        free(e2);
        return rc;
    }
    rc = aa_random_patterns_range_visit(&sp->family, sp->distribution, sp->poisson_radius, &metric,
                                        sp->common.rng_seed, first, count, random_patterns_progress,
                                        &rp, figures ? proto_point_metrics_visit : NULL, &pm, e2,
                                        &best, &best_index, &rs, err);
    json_t *list = rc ? NULL : json_array();
    for (size_t i = 0; list && i < count; i++)
        if (json_array_append_new(list, proto_real(e2[i]))) {
            json_decref(list);
            list = NULL;
        }
    if (!rc) {
        *output =
            list ? json_pack("{s:o,s:o,s:I,s:o}", "e2", list, "best", proto_encode_pattern(&best),
                             "best_index", (json_int_t)best_index, "best_e2", proto_real(rs.min))
                 : NULL;
        if (*output && figures &&
            json_object_set_new(*output, "metrics", proto_point_metrics_columns(&pm))) {
            json_decref(*output);
            *output = NULL;
        }
        if (!*output)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    aa_pattern_free(&best);
    proto_point_metrics_free(&pm);
    free(e2);
    return rc;
}

static int run_optimized(const proto_random_stats_spec *sp, const json_t *shard,
                         const json_t *prior, const shard_ctx *ctx, json_t **output, aa_error *err)
{
    const char *which = NULL;
    json_error_t je;
    if (json_unpack_ex((json_t *)shard, &je, JSON_STRICT, "{s:s}", "stage", &which) ||
        (strcmp(which, "opt_w") && strcmp(which, "opt_wp")))
        return aa_error_set(err, AA_EINVAL, "shard", "expected {\"stage\":\"opt_w\"|\"opt_wp\"}");
    bool both = !strcmp(which, "opt_wp");
    aa_pattern start, out;
    memset(&out, 0, sizeof out);
    int rc = proto_result_pattern(prior, "best_random", false, &start, NULL, err);
    if (rc)
        return rc; /* the error names best_random */
    aa_metric_params metric = proto_optimizer_spec_metric(&sp->common);
    aa_optimize_mode mode = both ? AA_OPTIMIZE_BOTH : AA_OPTIMIZE_WEIGHTS;
    aa_optimize_method method =
        proto_optimizer_spec_method(&sp->common, aa_pattern_tiled_without_border(&start), mode);
    opt_bridge b = opt_bridge_make(ctx, 0, 1);
    aa_optimize_result r;
    memset(&r, 0, sizeof r);
    rc = optimize_stage(&start, &metric, mode, method, sp->common.max_seconds / 2, sp, &b, &out, &r,
                        err);
    if (!rc) {
        opt_bridge_end(&b);
        *output = json_pack("{s:o,s:o,s:s}", "e2", proto_real(r.e2), "pattern",
                            proto_encode_pattern(&out), "method", aa_optimize_method_name(method));
        if (!*output)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    aa_pattern_free(&start);
    aa_pattern_free(&out);
    return rc;
}

static int run_shard(const void *params, int stage, const json_t *shard, const json_t *prior,
                     const shard_ctx *ctx, json_t **output, aa_error *err)
{
    const proto_random_stats_spec *sp = params;
    *output = NULL;
    if (stage == 0)
        return run_patterns(sp, shard, ctx, output, err);
    if (stage == 1 && prior)
        return run_optimized(sp, shard, prior, ctx, output, err);
    return aa_error_set(err, AA_EINVAL, "stage", "random-stats has two stages");
}

/* Stage 0: the concatenated E2 lists and the best pattern, the first of equals. */
static int merge_patterns(const proto_random_stats_spec *sp, json_t *const *outputs, size_t count,
                          json_t **merged, aa_error *err)
{
    double *e2 = calloc(sp->count, sizeof *e2);
    if (!e2)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    size_t n = 0, win = 0;
    double win_e2 = INFINITY;
    bool figures = sp->metrics.count > 0;
    proto_point_metrics pm;
    memset(&pm, 0, sizeof pm);
    int rc = figures ? proto_point_metrics_init(&pm, &sp->metrics, sp->count, err) : AA_OK;
    for (size_t s = 0; !rc && s < count; s++) {
        json_t *list = json_object_get(outputs[s], "e2"), *v;
        json_t *best_e2 = json_object_get(outputs[s], "best_e2");
        if (!json_is_array(list) || !json_is_number(best_e2) ||
            !json_is_object(json_object_get(outputs[s], "best")) ||
            !json_is_integer(json_object_get(outputs[s], "best_index")) ||
            json_object_size(outputs[s]) != 4u + figures || json_array_size(list) > sp->count - n) {
            rc = aa_error_set(err, AA_EINVAL, "output",
                              "shard %zu: expected {\"e2\",\"best\","
                              "\"best_index\",\"best_e2\"}",
                              s);
            break;
        }
        size_t i;
        json_array_foreach(list, i, v) e2[n++] = json_is_number(v) ? json_number_value(v) : NAN;
        if (figures) {
            char field[48];
            snprintf(field, sizeof field, "output[%zu].metrics", s);
            rc =
                proto_point_metrics_append(&pm, json_object_get(outputs[s], "metrics"), field, err);
            if (rc)
                break;
        }
        if (json_number_value(best_e2) < win_e2) {
            win_e2 = json_number_value(best_e2);
            win = s;
        }
    }
    if (!rc && n != sp->count)
        rc = aa_error_set(err, AA_EINVAL, "output", "%zu E2 values for %zu patterns", n, sp->count);
    if (!rc) {
        aa_random_stats st = aa_random_stats_of(e2, n);
        *merged =
            json_pack("{s:I,s:o,s:o,s:o,s:O,s:O,s:O}", "count", (json_int_t)st.count, "min",
                      proto_real(st.min), "avg", proto_real(st.avg), "max", proto_real(st.max),
                      "best_random", json_object_get(outputs[win], "best"), "best_index",
                      json_object_get(outputs[win], "best_index"), "best_e2",
                      json_object_get(outputs[win], "best_e2"));
        /* The figures stay per pattern in the merged state; finish ranks them. */
        if (*merged && figures &&
            json_object_set_new(*merged, "point_metrics", proto_point_metrics_columns(&pm))) {
            json_decref(*merged);
            *merged = NULL;
        }
        if (!*merged)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    if (!rc && figures && pm.n != sp->count)
        rc = aa_error_set(err, AA_EINVAL, "output", "figures of %zu patterns for %zu", pm.n,
                          sp->count);
    proto_point_metrics_free(&pm);
    free(e2);
    return rc;
}

static int merge(const void *params, int stage, json_t *const *outputs, size_t count,
                 const json_t *prior, json_t **merged, aa_error *err)
{
    *merged = NULL;
    if (stage == 0)
        return merge_patterns(params, outputs, count, merged, err);
    if (stage != 1 || count != 2 || !prior)
        return aa_error_set(err, AA_EINVAL, "stage", "stage 1 merges Opt W and Opt W+P");
    *merged = json_deep_copy(prior);
    if (!*merged || json_object_set(*merged, "opt_w", outputs[0]) ||
        json_object_set(*merged, "opt_wp", outputs[1])) {
        json_decref(*merged);
        *merged = NULL;
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    return AA_OK;
}

static int decode_stage(const json_t *j, const char *field, proto_stats_stage *s, aa_error *err)
{
    if (!json_is_object(j) || json_object_size(j) != 3)
        return aa_error_set(err, AA_EINVAL, field, "expected {\"e2\",\"pattern\",\"method\"}");
    int rc = proto_result_real(j, "e2", &s->e2, err);
    if (!rc)
        rc = proto_result_pattern(j, "pattern", false, &s->pattern, NULL, err);
    if (!rc)
        rc = proto_result_method(j, "method", &s->method, err);
    return rc;
}

static int finish(const void *params, const json_t *merged, const char *executor, size_t shards,
                  void **result, aa_error *err)
{
    const proto_random_stats_spec *sp = params;
    *result = NULL;
    proto_random_stats_result *r = calloc(1, sizeof *r);
    if (!r)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    long long count = 0;
    int rc = proto_result_integer(merged, "count", &count, err);
    if (!rc)
        rc = proto_result_real(merged, "min", &r->min, err);
    if (!rc)
        rc = proto_result_real(merged, "avg", &r->avg, err);
    if (!rc)
        rc = proto_result_real(merged, "max", &r->max, err);
    if (!rc)
        rc = proto_result_pattern(merged, "best_random", false, &r->best_random, NULL, err);
    if (!rc)
        rc = decode_stage(json_object_get(merged, "opt_w"), "opt_w", &r->opt_w, err);
    if (!rc)
        rc = decode_stage(json_object_get(merged, "opt_wp"), "opt_wp", &r->opt_wp, err);
    if (!rc && sp->metrics.count)
        rc = proto_point_metrics_init(&r->point_metrics, &sp->metrics, sp->count, err);
    if (!rc && sp->metrics.count)
        rc = proto_point_metrics_append(&r->point_metrics, json_object_get(merged, "point_metrics"),
                                        "point_metrics", err);
    if (!rc && sp->metrics.count && r->point_metrics.n != (size_t)count)
        rc = aa_error_set(err, AA_EINVAL, "point_metrics", "expected %lld patterns", count);
    if (!rc && sp->metrics.count)
        rc = proto_point_metrics_rank(&r->point_metrics, err);
    if (rc) {
        proto_random_stats_result_free(r);
        free(r);
        return rc;
    }
    r->distribution = sp->distribution;
    r->radius =
        sp->distribution == AA_SEED_POISSON && !sp->family.mirrored ? sp->poisson_radius : NAN;
    r->count = (long)count;
    snprintf(r->family, sizeof r->family, "%s", sp->family.label);
    r->run = proto_run_info_make(executor, shards, sp->common.reproducible, &sp->common.acuity);
    *result = r;
    return AA_OK;
}

static json_t *best_of_output(const void *params, int stage, const json_t *output)
{
    (void)params;
    const char *pk = stage == 0 ? "best" : "pattern", *ek = stage == 0 ? "best_e2" : "e2";
    json_t *best = json_object_get(output, pk), *e2 = json_object_get(output, ek);
    if (!json_is_object(best) || !json_is_number(e2))
        return NULL;
    return json_pack("{s:O,s:O}", "pattern", best, "e2", e2);
}

/* The random patterns are the first 20 % of the progress, as they were before the split. */
const job_split kind_random_stats_split = {.stages = 2,
                                           .stage_weight = {0.2, 0.8},
                                           .plan = plan,
                                           .run_shard = run_shard,
                                           .merge = merge,
                                           .finish = finish,
                                           .best_of_output = best_of_output};

JOB_KIND_SPLIT_RESULT(kind_random_stats, kind_random_stats_split, proto_encode_random_stats_result,
                      proto_random_stats_result_free)

/* The kind's row of the table of kinds (kind_list.h). */
JOB_KIND_ROW(random_stats, .name = "random-stats",
             .summary =
                 "Min, average and max E2 of random patterns of a family, and the best of them "
                 "optimised for weights (Opt W) and for weights and positions (Opt W+P).",
             .split = &kind_random_stats_split, JOB_KIND_FAMILY_MEMBERS(random_stats));
