/* Job kind "table3": Laine & Aila's Table 3 protocol (aa_table3_cell_run) for K rng_seeds and
 * each distribution, reported as mean +- sd of Min, Avg, Max, Opt W and Opt W+P beside the
 * paper's values (proto/job_table3.h). Why a kind of its own rather than a seeds list on
 * random-stats: its result is a different table (rows per distribution, columns with mean, sd
 * and the paper's value), the random-stats result is a stable wire form, and one table3 job
 * gives both of the paper's rows.
 * Split (job_split.h), one stage of K shards, one per rng_seed ({"seed_index": i}); a shard runs
 * every distribution of its seed in turn and outputs {"rng_seed", "cells": [{"distribution",
 * "min", "avg", "max", "opt_w", "opt_wp", "best_index"}], "best": its lowest Opt W+P pattern,
 * "best_e2"}; merge keeps the outputs in seed order, finish computes the statistics. The trace
 * is the Opt W+P progress: the best Opt W+P E2 so far against the Opt W+P seconds spent. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aa_optimizer.h"
#include "codec.h"
#include "job_result_util.h"
#include "job_split_local.h"
#include "job_table3.h"
#include "kinds.h"
#include "optimizer_bridge.h"
#include "split_ranges.h"

JOB_KIND_SPEC_PARAMS(kind_table3, proto_table3_spec, proto_decode_table3_spec,
                     proto_table3_spec_free)

double kind_table3_max_seconds(const void *params)
{
    return proto_table3_spec_seconds(params);
}

const char *kind_table3_family(const void *params)
{
    return ((const proto_table3_spec *)params)->family.label;
}

json_t *kind_table3_best_of(const json_t *result, double *e2)
{
    proto_table3_result *r = calloc(1, sizeof *r);
    aa_error err = {0};
    *e2 = NAN;
    if (!r || proto_decode_table3_result(result, r, &err)) {
        free(r);
        return NULL;
    }
    *e2 = r->e2;
    json_t *best = proto_encode_pattern(&r->best);
    proto_table3_result_free(r);
    free(r);
    return best;
}

static int plan(const void *params, int stage, const json_t *prior, size_t max_shards,
                json_t **shards, aa_error *err)
{
    (void)prior;
    (void)max_shards; /* a fixed number of parts: one per seed */
    const proto_table3_spec *sp = params;
    if (stage != 0)
        return aa_error_set(err, AA_EINVAL, "stage", "table3 has one stage");
    *shards = json_array();
    for (size_t i = 0; *shards && i < sp->seeds; i++)
        if (json_array_append_new(*shards, json_pack("{s:I}", "seed_index", (json_int_t)i))) {
            json_decref(*shards);
            *shards = NULL;
        }
    return *shards ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
}

/* Engine progress of one cell -> the shard: the random patterns are the first 10 % of a cell,
 * Opt W the next 10 %, Opt W+P the rest (and the trace). */
typedef struct cell_report {
    opt_bridge *b;
    double base, span;
} cell_report;

static int cell_progress(void *user, const aa_table3_progress *p)
{
    cell_report *c = user;
    if (p->phase == 2) {
        c->b->base = c->base + 0.2 * c->span;
        c->b->span = 0.8 * c->span;
        return opt_bridge_progress(c->b, p->opt);
    }
    double f = p->phase == 0 ? 0.1 * p->random_fraction : 0.1 + 0.1 * p->opt->fraction;
    return opt_bridge_report(c->b, c->base + c->span * f);
}

static json_t *cell_json(aa_seed_kind kind, const aa_table3_cell *c)
{
    return json_pack("{s:s,s:o,s:o,s:o,s:o,s:o,s:I}", "distribution", aa_seed_kind_name(kind),
                     "min", proto_real(c->random.min), "avg", proto_real(c->random.avg), "max",
                     proto_real(c->random.max), "opt_w", proto_real(c->opt_w), "opt_wp",
                     proto_real(c->opt_wp), "best_index", (json_int_t)c->best_index);
}

static int run_shard(const void *params, int stage, const json_t *shard, const json_t *prior,
                     const shard_ctx *ctx, json_t **output, aa_error *err)
{
    (void)prior;
    const proto_table3_spec *sp = params;
    *output = NULL;
    json_int_t index = -1;
    json_error_t je;
    if (stage != 0 ||
        json_unpack_ex((json_t *)shard, &je, JSON_STRICT, "{s:I}", "seed_index", &index) ||
        index < 0 || (size_t)index >= sp->seeds)
        return aa_error_set(err, AA_EINVAL, "shard", "expected {\"seed_index\": 0..%zu}",
                            sp->seeds - 1);
    uint64_t seed = sp->common.rng_seed + (uint64_t)index;
    aa_metric_params metric = proto_optimizer_spec_metric(&sp->common);
    aa_table3_params tp;
    aa_table3_params_default(&tp);
    tp.count = sp->count;
    tp.poisson_radius = sp->poisson_radius;
    tp.opt_wp_seconds = sp->common.max_seconds;
    tp.max_iterations = sp->common.max_iterations;
    if (sp->common.reproducible)
        tp.opt_w_seconds = 0; /* a clock-free budget: Opt W runs until it stalls */
    if (!sp->common.method_auto)
        tp.opt_wp_method = (int)sp->common.method;
    tp.clock = ctx->clock;
    opt_bridge b = opt_bridge_make(ctx, 0, 1);
    json_t *cells = json_array();
    aa_pattern best;
    memset(&best, 0, sizeof best);
    double best_e2 = INFINITY;
    int rc = cells ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t k = 0; !rc && k < sp->kind_count; k++) {
        cell_report cr = {&b, (double)k / (double)sp->kind_count, 1.0 / (double)sp->kind_count};
        aa_table3_cell c;
        rc = aa_table3_cell_run(&sp->family, sp->kinds[k], &metric, &tp, seed, cell_progress, &cr,
                                &c, err);
        if (!rc) {
            opt_bridge_add(&b, c.opt_wp_run.iterations, c.opt_wp_run.evaluations,
                           c.opt_wp_run.seconds);
            if (json_array_append_new(cells, cell_json(sp->kinds[k], &c)))
                rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
            if (c.opt_wp < best_e2) {
                best_e2 = c.opt_wp;
                aa_pattern_free(&best);
                best = c.opt_wp_pattern;
                memset(&c.opt_wp_pattern, 0, sizeof c.opt_wp_pattern);
            }
        }
        aa_table3_cell_free(&c);
    }
    if (!rc) {
        opt_bridge_end(&b);
        *output = json_pack("{s:I,s:O,s:o,s:o}", "rng_seed", (json_int_t)seed, "cells", cells,
                            "best", proto_encode_pattern(&best), "best_e2", proto_real(best_e2));
        if (!*output)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    json_decref(cells);
    aa_pattern_free(&best);
    return rc;
}

static int merge(const void *params, int stage, json_t *const *outputs, size_t count,
                 const json_t *prior, json_t **merged, aa_error *err)
{
    (void)params;
    (void)prior;
    *merged = NULL;
    if (stage != 0)
        return aa_error_set(err, AA_EINVAL, "stage", "table3 has one stage");
    json_t *list = json_array();
    for (size_t i = 0; list && i < count; i++)
        if (json_array_append(list, outputs[i])) {
            json_decref(list);
            list = NULL;
        }
    *merged = list ? json_pack("{s:o}", "seeds", list) : NULL;
    return *merged ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
}

static int finish(const void *params, const json_t *merged, const char *executor, size_t shards,
                  void **result, aa_error *err)
{
    const proto_table3_spec *sp = params;
    *result = NULL;
    const json_t *seeds = json_object_get(merged, "seeds");
    if (json_array_size(seeds) != sp->seeds)
        return aa_error_set(err, AA_EINVAL, "output", "expected %zu seeds", sp->seeds);
    proto_table3_result *r = calloc(1, sizeof *r);
    if (!r)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    snprintf(r->family, sizeof r->family, "%s", sp->family.label);
    r->count = (long)sp->count;
    r->seed_count = sp->seeds;
    r->row_count = sp->kind_count;
    r->e2 = INFINITY;
    bool paper = !strcmp(sp->family.label, "P(16,16,4)");
    int rc = AA_OK;
    size_t best_seed = 0;
    for (size_t s = 0; !rc && s < sp->seeds; s++) {
        const json_t *out = json_array_get(seeds, s), *cells = json_object_get(out, "cells");
        long long rs = 0;
        rc = proto_result_integer(out, "rng_seed", &rs, err);
        r->seeds[s] = (uint64_t)rs;
        if (!rc && json_array_size(cells) != sp->kind_count)
            rc = aa_error_set(err, AA_EINVAL, "output", "seed %zu: expected %zu cells", s,
                              sp->kind_count);
        for (size_t k = 0; !rc && k < sp->kind_count; k++)
            for (int c = 0; !rc && c < PROTO_T3_COLS; c++)
                rc = proto_result_real(json_array_get(cells, k), proto_table3_columns[c],
                                       &r->rows[k].values[c][s], err);
        double e2 = NAN;
        if (!rc)
            rc = proto_result_real(out, "best_e2", &e2, err);
        if (!rc && e2 < r->e2) {
            r->e2 = e2;
            best_seed = s;
        }
    }
    if (!rc)
        rc = proto_result_pattern(json_array_get(seeds, best_seed), "best", false, &r->best, NULL,
                                  err);
    for (size_t k = 0; !rc && k < sp->kind_count; k++) {
        proto_table3_row *row = &r->rows[k];
        row->distribution = sp->kinds[k];
        row->radius = sp->kinds[k] == AA_SEED_POISSON ? sp->poisson_radius : NAN;
        const aa_table3_paper *p = paper ? aa_table3_paper_row(sp->kinds[k]) : NULL;
        const double pv[PROTO_T3_COLS] = {p ? p->min : NAN, p ? p->avg : NAN, p ? p->max : NAN,
                                          p ? p->opt_w : NAN, p ? p->opt_wp : NAN};
        for (int c = 0; c < PROTO_T3_COLS; c++) {
            aa_mean_sd(row->values[c], sp->seeds, &row->mean[c], &row->sd[c]);
            row->paper[c] = pv[c];
        }
    }
    if (rc) {
        proto_table3_result_free(r);
        free(r);
        return rc;
    }
    r->run = proto_run_info_make(executor, shards, sp->common.reproducible, &sp->common.acuity);
    *result = r;
    return AA_OK;
}

static json_t *best_of_output(const void *params, int stage, const json_t *output)
{
    (void)params;
    (void)stage;
    json_t *best = json_object_get(output, "best"), *e2 = json_object_get(output, "best_e2");
    if (!json_is_object(best) || !json_is_number(e2))
        return NULL;
    return json_pack("{s:O,s:O}", "pattern", best, "e2", e2);
}

const job_split kind_table3_split = {.stages = 1,
                                     .plan = plan,
                                     .run_shard = run_shard,
                                     .merge = merge,
                                     .finish = finish,
                                     .best_of_output = best_of_output};

JOB_KIND_SPLIT_RESULT(kind_table3, kind_table3_split, proto_encode_table3_result,
                      proto_table3_result_free)
