/* Job kind "optimize" (issue 3): multi-start L&A sec. 5 descent for a family or from a given
 * pattern. Spec: {"kind":"optimize", "family":"P(4,1+,2)" | "pattern":P, "seeds":N,
 * "max_seconds":S, "rng_seed":K, "mode":"weights|positions|both",
 * "method":"auto|laine-aila|minimax|smooth"?, "filter":F?, "acuity":A?,
 * "angles":[...]?, "grid":{"bits":4,"d3d12":false}?, "distributions":["uniform",...]?}.
 * For P(4,1+,n) every placement configuration is screened first (150 steps each, at most a
 * quarter of the budget) and the seeds go to the best min(seeds, 8) configurations. For tiled
 * families without border samples (mode both) each seed's optimum is refined by iterated local
 * search (aa_optimize_perturbed).
 * Also holds the helpers shared with family-sweep and random-stats (kind_optimize_spec.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "kind_optimize_spec.h"

int opt_spec_check_keys(const json_t *spec, const char *const *allowed, aa_error *err)
{
    const char *key;
    json_t *v;
    json_object_foreach((json_t *)spec, key, v)
    {
        bool ok = false;
        for (size_t i = 0; allowed[i] && !ok; i++)
            ok = !strcmp(key, allowed[i]);
        if (!ok)
            return aa_error_set(err, AA_EINVAL, key, "unknown field");
    }
    return AA_OK;
}

int opt_spec_number(const json_t *spec, const char *key, double lo, double hi, double *out,
                    aa_error *err)
{
    json_t *v = json_object_get(spec, key);
    if (!v)
        return AA_OK;
    double d;
    json_error_t je;
    if (json_unpack_ex(v, &je, JSON_STRICT, "F", &d) || !isfinite(d))
        return aa_error_set(err, AA_EINVAL, key, "must be a number");
    if (d < lo || d > hi)
        return aa_error_set(err, AA_EINVAL, key, "must be in [%g, %g]", lo, hi);
    *out = d;
    return AA_OK;
}

int opt_spec_integer(const json_t *spec, const char *key, json_int_t lo, json_int_t hi,
                     json_int_t *out, aa_error *err)
{
    json_t *v = json_object_get(spec, key);
    if (!v)
        return AA_OK;
    json_int_t i;
    json_error_t je;
    if (json_unpack_ex(v, &je, JSON_STRICT, "I", &i))
        return aa_error_set(err, AA_EINVAL, key, "must be an integer");
    if (i < lo || i > hi)
        return aa_error_set(err, AA_EINVAL, key, "must be in [%lld, %lld]", (long long)lo,
                            (long long)hi);
    *out = i;
    return AA_OK;
}

int opt_spec_string(const json_t *spec, const char *key, const char **out, aa_error *err)
{
    json_t *v = json_object_get(spec, key);
    if (!v)
        return AA_OK;
    if (!json_is_string(v))
        return aa_error_set(err, AA_EINVAL, key, "must be a string");
    *out = json_string_value(v);
    return AA_OK;
}

int opt_common_parse(const json_t *spec, double def_seconds, opt_common_spec *c, aa_error *err)
{
    memset(c, 0, sizeof *c);
    c->max_seconds = def_seconds;
    c->mode = AA_OPTIMIZE_BOTH;
    c->rng_seed = 1;
    int rc = proto_decode_filter(json_object_get(spec, "filter"), &c->filter, "filter", err);
    if (!rc)
        rc = proto_decode_acuity(json_object_get(spec, "acuity"), &c->acuity, "acuity", err);
    if (!rc)
        rc = proto_decode_angles(json_object_get(spec, "angles"), &c->angles, &c->angle_count,
                                 "angles", err);
    if (!rc)
        rc = opt_spec_number(spec, "max_seconds", 0.01, 86400, &c->max_seconds, err);
    json_int_t seed = 1;
    if (!rc)
        rc = opt_spec_integer(spec, "rng_seed", 0, (json_int_t)1 << 53, &seed, err);
    c->rng_seed = (uint64_t)seed;
    const char *mode = NULL;
    if (!rc)
        rc = opt_spec_string(spec, "mode", &mode, err);
    if (!rc && mode) {
        if (!strcmp(mode, "weights"))
            c->mode = AA_OPTIMIZE_WEIGHTS;
        else if (!strcmp(mode, "positions"))
            c->mode = AA_OPTIMIZE_POSITIONS;
        else if (!strcmp(mode, "both"))
            c->mode = AA_OPTIMIZE_BOTH;
        else
            rc = aa_error_set(err, AA_EINVAL, "mode", "must be weights, positions or both");
    }
    const char *method = NULL;
    c->method_auto = true;
    if (!rc)
        rc = opt_spec_string(spec, "method", &method, err);
    if (!rc && method && strcmp(method, "auto")) {
        c->method_auto = false;
        if (aa_optimize_method_parse(method, &c->method))
            rc = aa_error_set(err, AA_EINVAL, "method",
                              "must be auto, laine-aila, minimax or smooth");
    }
    json_t *grid = json_object_get(spec, "grid");
    if (!rc && grid) {
        json_int_t bits = 4;
        int d3d12 = 0;
        json_error_t je;
        if (!json_is_object(grid))
            rc = aa_error_set(err, AA_EINVAL, "grid", "must be an object");
        else if (json_unpack_ex(grid, &je, JSON_STRICT, "{s?I,s?b}", "bits", &bits, "d3d12",
                                &d3d12))
            rc = aa_error_set(err, AA_EINVAL, "grid", "expected {\"bits\":k,\"d3d12\":bool}");
        else if (bits < 1 || bits > 12)
            rc = aa_error_set(err, AA_EINVAL, "grid.bits", "must be 1..12");
        c->grid_bits = (int)bits;
        c->d3d12 = d3d12;
    }
    if (rc)
        opt_common_free(c);
    return rc;
}

aa_optimize_method opt_common_method(const opt_common_spec *c, bool tiled_without_border,
                                     aa_optimize_mode mode)
{
    return c->method_auto ? aa_auto_method(tiled_without_border, mode) : c->method;
}

void opt_common_free(opt_common_spec *c)
{
    free(c->angles);
    c->angles = NULL;
}

aa_metric_params opt_common_metric(const opt_common_spec *c)
{
    aa_metric_params m = {&c->filter, &c->acuity, c->angles, c->angle_count, 0};
    return m;
}

int opt_job_progress(void *user, const aa_optimize_progress *p)
{
    opt_job_bridge *b = user;
    json_t *best = NULL;
    bool better = p->best_e2 < b->best_e2;
    if (better) {
        b->best_e2 = p->best_e2;
        job_trace_point tp = {b->seconds_before + p->seconds, b->iterations_before + p->iterations,
                              b->evaluations_before + p->evaluations, b->best_e2};
        job_ctx_trace(b->ctx, &tp);
        /* The pattern JSON is the expensive part: at most 10 a second. */
        if (p->best && p->seconds - b->last_best_post >= 0.1) {
            b->last_best_post = p->seconds;
            json_t *pj = proto_encode_pattern(p->best);
            if (pj)
                best = json_pack("{s:o,s:o}", "pattern", pj, "e2", proto_real(p->best_e2));
        }
    }
    bool stop = job_ctx_progress(b->ctx, b->base + b->span * p->fraction, best);
    json_decref(best);
    return stop || job_ctx_cancelled(b->ctx);
}

/* --- the "optimize" kind -------------------------------------------------------------- */

typedef struct optimize_params {
    opt_common_spec common;
    bool have_family;
    aa_family family;
    aa_pattern pattern;
    size_t seeds;
    aa_seed_kind kinds[5];
    size_t kind_count;
} optimize_params;

static void optimize_free(void *params)
{
    optimize_params *op = params;
    if (!op)
        return;
    opt_common_free(&op->common);
    aa_pattern_free(&op->pattern);
    free(op);
}

static const char *const optimize_keys[] = {
    "kind",   "family", "pattern", "seeds",  "max_seconds", "rng_seed",      "mode",
    "method", "filter", "acuity",  "angles", "grid",        "distributions", NULL};

int opt_parse_distributions(const json_t *spec, aa_seed_kind *kinds, size_t *count, aa_error *err)
{
    json_t *d = json_object_get(spec, "distributions");
    *count = 0;
    if (!d)
        return AA_OK;
    if (!json_is_array(d) || json_array_size(d) == 0 || json_array_size(d) > 5)
        return aa_error_set(err, AA_EINVAL, "distributions", "must be an array of 1..5 names");
    for (size_t i = 0; i < json_array_size(d); i++) {
        char field[40];
        snprintf(field, sizeof field, "distributions[%zu]", i);
        json_t *v = json_array_get(d, i);
        if (!json_is_string(v) || aa_seed_kind_parse(json_string_value(v), &kinds[i]))
            return aa_error_set(err, AA_EINVAL, field,
                                "must be uniform, jittered, n-rooks, poisson or lloyd");
        (*count)++;
    }
    return AA_OK;
}

static int optimize_parse(const json_t *spec, void **params, aa_error *err)
{
    *params = NULL;
    int rc = opt_spec_check_keys(spec, optimize_keys, err);
    if (rc)
        return rc;
    optimize_params *op = calloc(1, sizeof *op);
    if (!op)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    rc = opt_common_parse(spec, 30, &op->common, err);
    const char *family = NULL;
    json_t *pattern = json_object_get(spec, "pattern");
    if (!rc)
        rc = opt_spec_string(spec, "family", &family, err);
    if (!rc && !family == !pattern)
        rc = aa_error_set(err, AA_EINVAL, "family", "give exactly one of family and pattern");
    if (!rc && family) {
        op->have_family = true;
        rc = aa_family_parse(family, &op->family, err);
    }
    if (!rc && pattern)
        rc = proto_decode_pattern(pattern, 0, &op->pattern, "pattern", err);
    json_int_t seeds = op->have_family ? 64 : 1;
    if (!rc)
        rc = opt_spec_integer(spec, "seeds", 1, 100000, &seeds, err);
    if (!rc && !op->have_family && seeds != 1)
        rc = aa_error_set(err, AA_EINVAL, "seeds", "a given pattern is one seed");
    op->seeds = (size_t)seeds;
    if (!rc)
        rc = opt_parse_distributions(spec, op->kinds, &op->kind_count, err);
    if (rc) {
        optimize_free(op);
        return rc;
    }
    *params = op;
    return AA_OK;
}

json_t *opt_per_seed_json(const aa_multistart_result *r)
{
    json_t *a = json_array();
    for (size_t i = 0; a && i < r->seed_count; i++) {
        const aa_multistart_seed *s = &r->per_seed[i];
        if (isnan(s->e2))
            continue;
        json_array_append_new(a, json_pack("{s:I,s:s,s:o,s:o,s:I}", "seed", (json_int_t)i,
                                           "distribution", aa_seed_kind_name(s->kind), "initial_e2",
                                           proto_real(s->initial_e2), "e2", proto_real(s->e2),
                                           "iterations", (json_int_t)s->iterations));
    }
    return a;
}

static int optimize_run(void *params, job_ctx *ctx, json_t **result, aa_error *err)
{
    optimize_params *op = params;
    aa_metric_params metric = opt_common_metric(&op->common);
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
    mp.local.method = opt_common_method(&op->common, tiled, op->common.mode);
    opt_job_bridge b = {ctx, 0, 1, 0, 0, 0, INFINITY, -1};
    aa_pattern best;
    aa_multistart_result r;
    int rc = aa_multistart(&mp, &metric, opt_job_progress, &b, &best, &r, err);
    if (rc) {
        aa_pattern_free(&best);
        aa_multistart_result_free(&r);
        return rc;
    }
    json_t *res = json_pack(
        "{s:o,s:o,s:{s:I,s:o},s:I,s:I,s:I,s:o,s:s,s:s,s:o}", "best", proto_encode_pattern(&best),
        "e2", proto_real(r.e2), "argmax", "kernel", (json_int_t)r.argmax_kernel, "angle_deg",
        proto_real(r.argmax_angle_deg), "seeds_run", (json_int_t)r.seeds_run, "iterations",
        (json_int_t)r.iterations, "evaluations", (json_int_t)r.evaluations, "seconds",
        proto_real(r.seconds), "family", best.family, "method",
        aa_optimize_method_name(mp.local.method), "per_seed", opt_per_seed_json(&r));
    if (res && op->common.grid_bits)
        json_object_set_new(res, "grid",
                            json_pack("{s:I,s:b,s:o,s:o}", "bits", (json_int_t)op->common.grid_bits,
                                      "d3d12", op->common.d3d12, "e2_before_snap",
                                      proto_real(r.e2_before_snap), "quantisation_cost",
                                      proto_real(r.e2 - r.e2_before_snap)));
    aa_pattern_free(&best);
    aa_multistart_result_free(&r);
    if (!res)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    *result = res;
    return AA_OK;
}

const job_kind job_kind_optimize = {
    .name = "optimize", .parse = optimize_parse, .run = optimize_run, .free_params = optimize_free};
