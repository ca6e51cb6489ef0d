/* Job kind "table3": Laine & Aila's Table 3 protocol (aa_table3_cell_run) for K rng_seeds and
 * each distribution, reported as mean +- sd of Min, Avg, Max, Opt W and Opt W+P beside the
 * paper's values (proto/job_table3.h). Why a kind of its own rather than a seeds list on
 * random-stats: its result is a different table (rows per distribution, columns with mean, sd
 * and the paper's value), the random-stats result is a stable wire form, and one table3 job
 * gives both of the paper's rows.
 * Split (job_split.h), one stage of K shards, one per rng_seed ({"seed_index": i}); a shard runs
 * the distributions of its seed side by side on the threads it may use (shard_ctx.workers; in
 * turn on one) and outputs {"rng_seed", "cells": [{"distribution",
 * "min", "avg", "max", "opt_w", "opt_wp", "best_index", "patterns"?}], "best": its lowest Opt
 * W+P pattern, "best_e2"}; merge keeps the outputs in seed order, finish computes the
 * statistics. "patterns" (spec "metrics", issue 31): the cell's random patterns' E2 and
 * point-set figures as columns (job_point_metrics.h); finish joins a distribution's over the
 * seeds and ranks them (Spearman's rho with E2). The trace
 * is the Opt W+P progress: the best Opt W+P E2 so far against the Opt W+P seconds spent. */
#include <math.h>
#include <pthread.h>
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
#include "lock_held.h"
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

/* Engine progress of one cell -> the cell's bridge: the random patterns are the first 10 % of
 * a cell, Opt W the next 10 %, Opt W+P the rest (and the trace). */
static int cell_progress(void *user, const aa_table3_progress *p)
{
    opt_bridge *b = user;
    if (p->phase == 2) {
        b->base = 0.2;
        b->span = 0.8;
        return opt_bridge_progress(b, p->opt);
    }
    b->base = 0;
    b->span = 1;
    return opt_bridge_report(b, p->phase == 0 ? 0.1 * p->random_fraction
                                              : 0.1 + 0.1 * p->opt->fraction);
}

/* The cells of a shard (one per distribution) run side by side when the shard may use more
 * than one thread, one after the other otherwise; either way each reports through a bridge of
 * its own to this hub, which passes them on to the shard under one lock: progress as the mean
 * of the cells', the trace as their summed Opt W+P work against the best Opt W+P E2 of any
 * (so run in turn, the trace is the one continuous line it was), a best so far when it
 * improves, and a stop to every cell once the shard says stop or a cell fails. */
typedef struct cell_hub {
    pthread_mutex_t lock;
    const shard_ctx *outer;
    size_t count;
    double fraction[PROTO_MAX_DISTRIBUTIONS];
    job_trace_point work[PROTO_MAX_DISTRIBUTIONS]; /* each cell's latest point */
    double best_posted;
    bool stopped;
} cell_hub;

typedef struct cell_slot {
    cell_hub *hub;
    size_t index;
    shard_ctx ctx; /* this cell's reports, into the hub */
    opt_bridge bridge;
    /* the run */
    const proto_table3_spec *sp;
    const aa_metric_params *metric;
    const aa_table3_params *tp;
    aa_table3_params tp_own;     /* the shard's, with this cell's figures as the visitor */
    proto_point_metrics figures; /* the random patterns' figures when the spec asks */
    uint64_t seed;
    aa_table3_cell cell;
    int rc;
    aa_error err;
} cell_slot;

static bool hub_progress(void *user, double fraction, json_t *best_so_far)
{
    cell_slot *c = user;
    cell_hub *h = c->hub;
    pthread_mutex_lock(&h->lock);
    h->fraction[c->index] = fraction;
    double sum = 0;
    for (size_t k = 0; k < h->count; k++)
        sum += h->fraction[k];
    const json_t *e2 = json_object_get(best_so_far, "e2");
    json_t *forward = NULL;
    if (json_is_number(e2) && json_number_value(e2) < h->best_posted) {
        h->best_posted = json_number_value(e2);
        forward = best_so_far;
    }
    /* The shard's context may pause this thread (the daemon's fair share): the other cells
     * wait here meanwhile, and the job's clock stands still for all. */
    if (!h->stopped && h->outer->progress &&
        h->outer->progress(h->outer->user, sum / (double)h->count, forward))
        h->stopped = true;
    bool stop = h->stopped;
    pthread_mutex_unlock(&h->lock);
    return stop;
}

/* The cells' summed work and best E2 (h->lock held). */
static job_trace_point hub_total_locked(const cell_hub *h)
{
    ASSERT_LOCK_HELD(&h->lock);
    job_trace_point t = {0, 0, 0, INFINITY};
    for (size_t k = 0; k < h->count; k++) {
        t.seconds += h->work[k].seconds;
        t.iterations += h->work[k].iterations;
        t.evaluations += h->work[k].evaluations;
        t.best_e2 = fmin(t.best_e2, h->work[k].best_e2);
    }
    return t;
}

static void hub_trace(void *user, const job_trace_point *p)
{
    cell_slot *c = user;
    cell_hub *h = c->hub;
    pthread_mutex_lock(&h->lock);
    h->work[c->index] = *p;
    job_trace_point t = hub_total_locked(h);
    if (h->outer->trace)
        h->outer->trace(h->outer->user, &t);
    pthread_mutex_unlock(&h->lock);
}

static void run_cell(void *item)
{
    cell_slot *c = item;
    const proto_table3_spec *sp = c->sp;
    c->rc = aa_table3_cell_run(&sp->family, sp->distributions[c->index], c->metric, c->tp, c->seed,
                               cell_progress, &c->bridge, &c->cell, &c->err);
    if (!c->rc) {
        opt_bridge_add(&c->bridge, c->cell.opt_wp_run.iterations, c->cell.opt_wp_run.evaluations,
                       c->cell.opt_wp_run.seconds);
        opt_bridge_end(&c->bridge); /* the cell's whole Opt W+P work into the hub */
    } else if (c->rc != AA_ECANCELED) {
        pthread_mutex_lock(&c->hub->lock);
        c->hub->stopped = true; /* the shard fails: the other cells need not finish */
        pthread_mutex_unlock(&c->hub->lock);
    }
}

static json_t *cell_json(aa_seed_distribution distribution, const aa_table3_cell *c,
                         const proto_point_metrics *figures)
{
    json_t *o = json_pack("{s:s,s:o,s:o,s:o,s:o,s:o,s:I}", "distribution",
                          aa_seed_distribution_name(distribution), "min", proto_real(c->random.min),
                          "avg", proto_real(c->random.avg), "max", proto_real(c->random.max),
                          "opt_w", proto_real(c->opt_w), "opt_wp", proto_real(c->opt_wp),
                          "best_index", (json_int_t)c->best_index);
    if (o && figures->spec.count &&
        json_object_set_new(o, "patterns", proto_point_metrics_columns(figures))) {
        json_decref(o);
        o = NULL;
    }
    return o;
}

/* The shard's output from its finished cells, in distribution order (the lowest Opt W+P
 * pattern, the first of equals, is its best). */
static int shard_output(const proto_table3_spec *sp, uint64_t seed, cell_slot *slots,
                        json_t **output, aa_error *err)
{
    json_t *cells = json_array();
    const aa_pattern *best = NULL;
    double best_e2 = INFINITY;
    bool ok = cells != NULL;
    for (size_t k = 0; ok && k < sp->distribution_count; k++) {
        ok = !json_array_append_new(
            cells, cell_json(sp->distributions[k], &slots[k].cell, &slots[k].figures));
        if (slots[k].cell.opt_wp < best_e2) {
            best_e2 = slots[k].cell.opt_wp;
            best = &slots[k].cell.opt_wp_pattern;
        }
    }
    json_t *pattern = ok && best ? proto_encode_pattern(best) : NULL;
    *output = pattern ? json_pack("{s:I,s:O,s:o,s:o}", "rng_seed", (json_int_t)seed, "cells", cells,
                                  "best", pattern, "best_e2", proto_real(best_e2))
                      : NULL;
    json_decref(cells);
    return *output ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
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
    tp.clock = ctx->clock; /* the job's clock: each cell's budget is its own run time */
    cell_hub hub = {.outer = ctx, .count = sp->distribution_count, .best_posted = INFINITY};
    cell_slot slots[PROTO_MAX_DISTRIBUTIONS];
    memset(slots, 0, sizeof slots);
    int figures_rc = AA_OK;
    if (pthread_mutex_init(&hub.lock, NULL))
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t k = 0; k < sp->distribution_count; k++) {
        hub.work[k] = (job_trace_point){0, 0, 0, INFINITY};
        cell_slot *c = &slots[k];
        *c = (cell_slot){.hub = &hub,
                         .index = k,
                         .sp = sp,
                         .metric = &metric,
                         .tp = &c->tp_own,
                         .tp_own = tp,
                         .seed = seed};
        c->ctx = (shard_ctx){hub_progress, hub_trace, c, ctx->clock, 1};
        c->bridge = opt_bridge_make(&c->ctx, 0, 1);
        if (sp->metrics.count && !figures_rc) {
            figures_rc = proto_point_metrics_init(&c->figures, &sp->metrics, sp->count, err);
            c->tp_own.visit = proto_point_metrics_visit;
            c->tp_own.visit_user = &c->figures;
        }
    }
    if (figures_rc) {
        for (size_t k = 0; k < sp->distribution_count; k++)
            proto_point_metrics_free(&slots[k].figures);
        pthread_mutex_destroy(&hub.lock);
        return figures_rc;
    }
    /* As many cells at once as the shard has threads; every cell's streams are its own, so a
     * clock-free budget gives the same output either way. */
    size_t batch = ctx->workers > 1 ? (size_t)ctx->workers : 1;
    for (size_t k = 0; k < sp->distribution_count; k += batch) {
        size_t n = sp->distribution_count - k < batch ? sp->distribution_count - k : batch;
        aa_fork_join(&slots[k], sizeof slots[0], (int)n, run_cell);
    }
    /* A cell's own failure before the cancel it caused in the others. */
    int rc = AA_OK;
    for (size_t k = 0; k < sp->distribution_count && (!rc || rc == AA_ECANCELED); k++)
        if (slots[k].rc && (!rc || slots[k].rc != AA_ECANCELED)) {
            rc = slots[k].rc;
            *err = slots[k].err;
        }
    if (!rc) {
        /* The threads have joined: the lock is uncontended, taken for hub_total_locked. */
        pthread_mutex_lock(&hub.lock);
        job_trace_point total = hub_total_locked(&hub);
        pthread_mutex_unlock(&hub.lock);
        if (ctx->trace)
            ctx->trace(ctx->user, &total); /* the shard's last point: its whole work */
        rc = shard_output(sp, seed, slots, output, err);
    }
    for (size_t k = 0; k < sp->distribution_count; k++) {
        aa_table3_cell_free(&slots[k].cell);
        proto_point_metrics_free(&slots[k].figures);
    }
    pthread_mutex_destroy(&hub.lock);
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
    r->row_count = sp->distribution_count;
    r->e2 = INFINITY;
    bool paper = !strcmp(sp->family.label, "P(16,16,4)");
    int rc = AA_OK;
    size_t best_seed = 0;
    for (size_t s = 0; !rc && s < sp->seeds; s++) {
        const json_t *out = json_array_get(seeds, s), *cells = json_object_get(out, "cells");
        long long rs = 0;
        rc = proto_result_integer(out, "rng_seed", &rs, err);
        r->seeds[s] = (uint64_t)rs;
        if (!rc && json_array_size(cells) != sp->distribution_count)
            rc = aa_error_set(err, AA_EINVAL, "output", "seed %zu: expected %zu cells", s,
                              sp->distribution_count);
        for (size_t k = 0; !rc && k < sp->distribution_count; k++)
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
    /* Each distribution's figures over every seed's patterns, in seed order, then ranked. */
    for (size_t k = 0; !rc && sp->metrics.count && k < sp->distribution_count; k++) {
        proto_point_metrics *pm = &r->rows[k].point_metrics;
        rc = proto_point_metrics_init(pm, &sp->metrics, sp->seeds * sp->count, err);
        for (size_t s = 0; !rc && s < sp->seeds; s++) {
            const json_t *cells = json_object_get(json_array_get(seeds, s), "cells");
            rc = proto_point_metrics_append(
                pm, json_object_get(json_array_get(cells, k), "patterns"), "output", err);
        }
        if (!rc && pm->n != sp->seeds * sp->count)
            rc = aa_error_set(err, AA_EINVAL, "output", "figures of %zu patterns for %zu", pm->n,
                              sp->seeds * sp->count);
        if (!rc)
            rc = proto_point_metrics_rank(pm, err);
    }
    for (size_t k = 0; !rc && k < sp->distribution_count; k++) {
        proto_table3_row *row = &r->rows[k];
        row->distribution = sp->distributions[k];
        row->radius = sp->distributions[k] == AA_SEED_POISSON ? sp->poisson_radius : NAN;
        const aa_table3_paper *p = paper ? aa_table3_paper_row(sp->distributions[k]) : NULL;
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

/* The kind's row of the table of kinds (kind_list.h). */
JOB_KIND_ROW(table3, .name = "table3",
             .summary =
                 "Laine & Aila's Table 3 over K rng_seeds: per distribution, Min, Avg and Max E2 "
                 "of random patterns, exact Opt W and Opt W+P of the best, as mean +- sd beside "
                 "the paper's values.",
             .split = &kind_table3_split, JOB_KIND_FAMILY_MEMBERS(table3));
