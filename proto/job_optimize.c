#include "job_optimize.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec_internal.h"
#include "job_result_util.h"

static const char *const kind_keys[] = {"family",        "pattern",   "seeds",
                                        "distributions", "objective", NULL};

int proto_decode_optimize_spec(const json_t *spec, proto_optimize_spec *s, aa_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = proto_optimizer_spec_decode(spec, kind_keys, PROTO_OPT_MODE | PROTO_OPT_GRID, 30,
                                         &s->common, err);
    if (rc)
        return rc;
    json_t *pattern = json_object_get(spec, "pattern");
    rc = proto_spec_family(spec, false, &s->have_family, &s->family, err);
    if (!rc && s->have_family == (pattern != NULL))
        rc = aa_error_set(err, AA_EINVAL, "family", "give exactly one of family and pattern");
    if (!rc && pattern)
        rc = proto_decode_pattern_filtered(pattern, 0, &s->common.filter, &s->pattern, "pattern",
                                           err);
    json_int_t seeds = s->have_family ? 64 : 1;
    if (!rc)
        rc = proto_spec_integer(spec, "seeds", 1, 100000, &seeds, err);
    if (!rc && !s->have_family && seeds != 1)
        rc = aa_error_set(err, AA_EINVAL, "seeds", "a given pattern is one seed");
    s->seeds = (size_t)seeds;
    if (!rc)
        rc = proto_spec_distributions(spec, s->distributions, &s->distribution_count, err);
    if (!rc)
        rc = proto_decode_scene_objective(spec, &s->objective, err);
    /* The scene descent keeps positions off any grid (objective_scene.h). */
    if (!rc && s->objective.enabled && s->common.grid_bits)
        rc = aa_error_set(err, AA_EINVAL, "objective",
                          "a scene objective cannot be combined with grid");
    if (rc)
        proto_optimize_spec_free(s);
    return rc;
}

void proto_optimize_spec_free(proto_optimize_spec *s)
{
    proto_optimizer_spec_free(&s->common);
    aa_pattern_free(&s->pattern);
}

static json_t *encode_per_seed(const proto_seed_summary *s, size_t n)
{
    json_t *a = json_array();
    for (size_t i = 0; a && i < n; i++)
        json_array_append_new(
            a, json_pack("{s:I,s:s,s:o,s:o,s:I}", "seed", (json_int_t)s[i].seed, "distribution",
                         aa_seed_distribution_name(s[i].distribution), "initial_e2",
                         proto_real(s[i].initial_e2), "e2", proto_real(s[i].e2), "iterations",
                         (json_int_t)s[i].iterations));
    return a;
}

json_t *proto_encode_optimize_result(const proto_optimize_result *r)
{
    json_t *o =
        json_pack("{s:o,s:o,s:{s:I,s:o},s:I,s:I,s:I,s:o,s:s,s:s,s:o}", "best",
                  proto_encode_pattern(&r->best), "e2", proto_real(r->e2), "argmax", "kernel",
                  (json_int_t)r->argmax_kernel, "angle_deg", proto_real(r->argmax_angle_deg),
                  "seeds_run", (json_int_t)r->seeds_run, "iterations", (json_int_t)r->iterations,
                  "evaluations", (json_int_t)r->evaluations, "seconds", proto_real(r->seconds),
                  "family", r->best.family, "method", aa_optimize_method_name(r->method),
                  "per_seed", encode_per_seed(r->per_seed, r->per_seed_count));
    if (o && r->have_grid)
        json_object_set_new(o, "grid",
                            json_pack("{s:I,s:b,s:o,s:o}", "bits", (json_int_t)r->grid_bits,
                                      "d3d12", r->d3d12, "e2_before_snap",
                                      proto_real(r->e2_before_snap), "quantisation_cost",
                                      proto_real(r->e2 - r->e2_before_snap)));
    if (o && r->scene.spec.enabled)
        json_object_set_new(o, "scene_objective", proto_encode_scene_objective_result(&r->scene));
    if (o && !proto_run_info_encode(o, &r->run)) {
        json_decref(o);
        o = NULL;
    }
    return o;
}

static const char *const result_keys[] = {
    "best",    "e2",           "argmax", "seeds_run",       "iterations", "evaluations",
    "seconds", "family",       "method", "per_seed",        "grid",       "executor",
    "shards",  "reproducible", "acuity", "scene_objective", NULL};
static const char *const seed_keys[] = {"seed", "distribution", "initial_e2",
                                        "e2",   "iterations",   NULL};

static int decode_seed(const json_t *j, proto_seed_summary *s, aa_error *err)
{
    long long seed = 0, iterations = 0;
    int rc = proto_check_keys(j, seed_keys, err, "");
    if (!rc)
        rc = proto_result_integer(j, "seed", &seed, err);
    if (!rc && aa_seed_distribution_parse(json_string_value(json_object_get(j, "distribution")),
                                          &s->distribution))
        rc = aa_error_set(err, AA_EINVAL, "distribution", "unknown distribution");
    if (!rc)
        rc = proto_result_real(j, "initial_e2", &s->initial_e2, err);
    if (!rc)
        rc = proto_result_real(j, "e2", &s->e2, err);
    if (!rc)
        rc = proto_result_integer(j, "iterations", &iterations, err);
    s->seed = (size_t)seed;
    s->iterations = (long)iterations;
    return rc;
}

static int decode_grid_result(const json_t *g, proto_optimize_result *r, aa_error *err)
{
    static const char *const keys[] = {"bits", "d3d12", "e2_before_snap", "quantisation_cost",
                                       NULL};
    long long bits = 0;
    int rc = proto_check_keys(g, keys, err, "grid");
    if (!rc)
        rc = proto_result_integer(g, "bits", &bits, err);
    if (!rc && !json_is_boolean(json_object_get(g, "d3d12")))
        rc = aa_error_set(err, AA_EINVAL, "grid.d3d12", "must be true or false");
    if (!rc)
        rc = proto_result_real(g, "e2_before_snap", &r->e2_before_snap, err);
    r->have_grid = true;
    r->grid_bits = (int)bits;
    r->d3d12 = json_is_true(json_object_get(g, "d3d12"));
    return rc;
}

int proto_decode_optimize_result(const json_t *j, proto_optimize_result *r, aa_error *err)
{
    memset(r, 0, sizeof *r);
    long long kernel = 0, seeds_run = 0, iterations = 0, evaluations = 0;
    const json_t *argmax = json_object_get(j, "argmax");
    const json_t *per_seed = json_object_get(j, "per_seed");
    int rc = proto_check_keys(j, result_keys, err, "");
    if (!rc)
        rc = proto_result_pattern(j, "best", false, &r->best, NULL, err);
    if (!rc)
        rc = proto_result_real(j, "e2", &r->e2, err);
    if (!rc)
        rc = proto_result_integer(argmax, "kernel", &kernel, err);
    if (!rc)
        rc = proto_result_real(argmax, "angle_deg", &r->argmax_angle_deg, err);
    if (!rc)
        rc = proto_result_integer(j, "seeds_run", &seeds_run, err);
    if (!rc)
        rc = proto_result_integer(j, "iterations", &iterations, err);
    if (!rc)
        rc = proto_result_integer(j, "evaluations", &evaluations, err);
    if (!rc)
        rc = proto_result_real(j, "seconds", &r->seconds, err);
    if (!rc)
        rc = proto_result_method(j, "method", &r->method, err);
    if (!rc && !json_is_array(per_seed))
        rc = aa_error_set(err, AA_EINVAL, "per_seed", "must be an array");
    r->argmax_kernel = (int)kernel;
    r->seeds_run = (long)seeds_run;
    r->iterations = (long)iterations;
    r->evaluations = (long)evaluations;
    size_t n = json_array_size(per_seed);
    if (!rc && n) {
        r->per_seed = calloc(n, sizeof *r->per_seed);
        if (!r->per_seed)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    for (size_t i = 0; !rc && i < n; i++) {
        rc = decode_seed(json_array_get(per_seed, i), &r->per_seed[i], err);
        if (rc) {
            char at[32];
            snprintf(at, sizeof at, "per_seed[%zu]", i);
            proto_prefix_error(err, at);
        }
        r->per_seed_count = i + 1;
    }
    const json_t *grid = json_object_get(j, "grid");
    if (!rc && grid)
        rc = decode_grid_result(grid, r, err);
    const json_t *scene = json_object_get(j, "scene_objective");
    if (!rc && scene)
        rc = proto_decode_scene_objective_result(scene, &r->scene, err);
    if (!rc)
        rc = proto_run_info_decode(j, &r->run, err);
    if (rc)
        proto_optimize_result_free(r);
    return rc;
}

void proto_optimize_result_free(proto_optimize_result *r)
{
    aa_pattern_free(&r->best);
    free(r->per_seed);
    r->per_seed = NULL;
    r->per_seed_count = 0;
}
