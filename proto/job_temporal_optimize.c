/* The temporal-optimize job kind's spec and result (job_temporal_optimize.h). */
#include "job_temporal_optimize.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec_internal.h"
#include "job_optimizer_spec.h"

static const char *const spec_keys[] = {
    "family", "pattern",        "blend",       "resolve",        "frame_pattern", "jitter_range",
    "seeds",  "flicker_weight", "flicker_cap", "grid",           "order",         "filter",
    "acuity", "angles",         "max_seconds", "max_iterations", "rng_seed",      NULL};

/* The keys of a temporal pattern a family spec gives at its top level. */
static const char *const setting_keys[] = {"blend", "resolve", "frame_pattern", "jitter_range",
                                           NULL};

static int parse_family(const char *text, long *n, aa_error *err)
{
    int used = 0;
    if (sscanf(text, "T(%ld)%n", n, &used) != 1 || used <= 0 || text[used] || *n < 1 ||
        *n > PROTO_TEMPORAL_OPT_MAX_PHASES)
        return aa_error_set(err, AA_EINVAL, "family",
                            "a temporal family is \"T(N)\", N = 1..%d jitter offsets",
                            PROTO_TEMPORAL_OPT_MAX_PHASES);
    return AA_OK;
}

/* The family's setting: the spec's temporal keys around N offsets at the centre. */
static int decode_family_setting(const json_t *spec, long n, proto_temporal *t, aa_error *err)
{
    json_t *v = json_object();
    json_t *jit = json_array();
    if (!v || !jit) {
        json_decref(v);
        json_decref(jit);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    for (long f = 0; f < n; f++)
        json_array_append_new(jit, json_pack("[f,f]", 0.0, 0.0));
    json_object_set_new(v, "jitter", jit);
    for (size_t i = 0; setting_keys[i]; i++) {
        json_t *k = json_object_get(spec, setting_keys[i]);
        if (k)
            json_object_set(v, setting_keys[i], k);
    }
    int rc = proto_decode_temporal_object(v, t, "", err);
    json_decref(v);
    return rc;
}

static int decode_grid_bits(const json_t *grid, int *bits, aa_error *err)
{
    *bits = 0;
    if (!grid)
        return AA_OK;
    json_int_t b = 0;
    json_error_t je;
    if (!json_is_object(grid) ||
        json_unpack_ex((json_t *)grid, &je, JSON_STRICT, "{s:I}", "bits", &b))
        return aa_error_set(err, AA_EINVAL, "grid", "expected {\"bits\": k}");
    if (b < 1 || b > 12)
        return aa_error_set(err, AA_EINVAL, "grid.bits", "must be 1..12");
    *bits = (int)b;
    return AA_OK;
}

/* The setting must expand (a resolve needs a tiled frame pattern, sample limits): checked at
 * submission so that it is a 400, not a failed job. */
static int check_builds(const proto_temporal *t, const char *prefix, aa_error *err)
{
    aa_temporal built;
    int rc = proto_temporal_build(t, prefix, &built, err);
    if (!rc)
        aa_temporal_free(&built);
    return rc;
}

static int decode_spec(const json_t *spec, proto_temporal_optimize_spec *s, aa_error *err)
{
    int rc = proto_check_keys(spec, spec_keys, err, "");
    if (rc)
        return rc;
    const json_t *fam = json_object_get(spec, "family"), *pj = json_object_get(spec, "pattern");
    if (!fam == !pj)
        return aa_error_set(err, AA_EINVAL, "family", "give exactly one of family and pattern");
    if (fam) {
        if (!json_is_string(fam))
            return aa_error_set(err, AA_EINVAL, "family", "must be a string \"T(N)\"");
        long n = 0;
        rc = parse_family(json_string_value(fam), &n, err);
        if (!rc)
            rc = decode_family_setting(spec, n, &s->temporal, err);
        if (!rc)
            rc = check_builds(&s->temporal, "", err);
        s->have_family = true;
    } else {
        for (size_t i = 0; setting_keys[i]; i++)
            if (json_object_get(spec, setting_keys[i]))
                return aa_error_set(err, AA_EINVAL, setting_keys[i],
                                    "with a given pattern, give %s inside pattern.temporal",
                                    setting_keys[i]);
        if (!json_is_object(pj) || !json_object_get(pj, "temporal"))
            return aa_error_set(err, AA_EINVAL, "pattern",
                                "must be a temporal pattern {\"temporal\": {...}} (spatial "
                                "patterns: the optimize kind)");
        rc = proto_decode_temporal(pj, &s->temporal, "pattern", err);
        if (!rc && s->temporal.count > PROTO_TEMPORAL_OPT_MAX_PHASES)
            rc = aa_error_set(err, AA_EINVAL, "pattern.temporal.jitter",
                              "at most %d offsets to optimise", PROTO_TEMPORAL_OPT_MAX_PHASES);
        if (!rc)
            rc = check_builds(&s->temporal, "pattern.temporal", err);
    }
    snprintf(s->family, sizeof s->family, "T(%zu)", s->temporal.count);
    json_int_t seeds = 16, seed = 1;
    if (!rc)
        rc = proto_spec_integer(spec, "seeds", 1, 100000, &seeds, err);
    s->seeds = (long)seeds;
    if (!rc)
        rc = proto_spec_number(spec, "flicker_weight", 0, 1000, &s->flicker_weight, err);
    if (!rc)
        rc = proto_spec_number(spec, "flicker_cap", 0, 16, &s->flicker_cap, err);
    if (!rc && s->flicker_weight > 0 && s->temporal.has_resolve)
        rc = aa_error_set(err, AA_EINVAL, "flicker_weight",
                          "a flicker weight under a resolve is not supported yet");
    if (!rc && s->flicker_cap > 0 && !(s->flicker_weight > 0))
        rc = aa_error_set(err, AA_EINVAL, "flicker_cap", "a cap needs a flicker_weight > 0");
    if (!rc)
        rc = decode_grid_bits(json_object_get(spec, "grid"), &s->grid_bits, err);
    if (!rc && s->grid_bits && ldexp(1, -s->grid_bits) > s->temporal.jitter_range / 2)
        rc = aa_error_set(err, AA_EINVAL, "grid.bits",
                          "the grid step must be at most half the "
                          "jitter range");
    const char *order = "auto";
    if (!rc)
        rc = proto_spec_string(spec, "order", &order, err);
    if (!rc && strcmp(order, "auto") && strcmp(order, "none"))
        rc = aa_error_set(err, AA_EINVAL, "order", "must be auto or none");
    s->order_search = !strcmp(order, "auto");
    if (!rc)
        rc = proto_spec_metric(spec, &s->filter, &s->acuity, &s->angles, &s->angle_count, err);
    s->max_seconds = 30;
    if (!rc)
        rc = proto_spec_budget(spec, 100000, &s->max_seconds, &s->max_iterations, &s->reproducible,
                               err);
    if (!rc)
        rc = proto_spec_integer(spec, "rng_seed", 0, (json_int_t)1 << 53, &seed, err);
    s->rng_seed = (uint64_t)seed;
    return rc;
}

int proto_decode_temporal_optimize_spec(const json_t *spec, proto_temporal_optimize_spec *s,
                                        aa_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = decode_spec(spec, s, err);
    if (rc)
        proto_temporal_optimize_spec_free(s);
    return rc;
}

void proto_temporal_optimize_spec_free(proto_temporal_optimize_spec *s)
{
    proto_temporal_free(&s->temporal);
    free(s->angles);
    s->angles = NULL;
}

aa_metric_params proto_temporal_optimize_metric(const proto_temporal_optimize_spec *s)
{
    return (aa_metric_params){&s->filter, &s->acuity, s->angles, s->angle_count, 0};
}

static const char *const start_names[] = {"given", "random", "hop"};

static json_t *encode_per_seed(const proto_temporal_seed *s, size_t n)
{
    json_t *a = json_array();
    for (size_t i = 0; a && i < n; i++)
        json_array_append_new(
            a, json_pack("{s:I,s:s,s:o,s:o,s:o,s:o}", "seed", (json_int_t)s[i].seed, "start",
                         start_names[s[i].start < 0 || s[i].start > 2 ? 1 : s[i].start],
                         "initial_score", proto_real(s[i].initial_score), "score",
                         proto_real(s[i].score), "e2", proto_real(s[i].e2), "f2",
                         proto_real(s[i].f2)));
    return a;
}

json_t *proto_encode_temporal_optimize_result(const proto_temporal_optimize_result *r)
{
    char objective[64] = "e2";
    if (r->flicker_weight > 0 && r->flicker_cap > 0)
        snprintf(objective, sizeof objective, "e2 + %g max(0, f2 - %g)", r->flicker_weight,
                 r->flicker_cap);
    else if (r->flicker_weight > 0)
        snprintf(objective, sizeof objective, "e2 + %g f2", r->flicker_weight);
    json_t *phases = json_array();
    for (size_t p = 0; phases && p < r->best.count; p++)
        json_array_append_new(phases, proto_real(r->phase_e2 ? r->phase_e2[p] : NAN));
    json_t *o = json_pack(
        "{s:o,s:o,s:o,s:o,s:o,s:o,s:o,s:s,s:s,s:o,s:o,s:I,s:I,s:o,s:o}", "best",
        proto_encode_temporal(&r->best), "e2", proto_real(r->e2), "mean_phase_e2",
        proto_real(r->mean_phase_e2), "phase_e2", phases, "f2", proto_real(r->f2),
        "frames_to_settle",
        r->frames_to_settle > 0 ? json_integer((json_int_t)r->frames_to_settle) : json_null(),
        "score", proto_real(r->score), "objective", objective, "family", r->family,
        "flicker_weight", proto_real(r->flicker_weight), "start_e2", proto_real(r->start_e2),
        "seeds_run", (json_int_t)r->seeds_run, "evaluations", (json_int_t)r->evaluations, "seconds",
        proto_real(r->seconds), "per_seed", encode_per_seed(r->per_seed, r->per_seed_count));
    if (o && r->grid_bits)
        json_object_set_new(o, "grid",
                            json_pack("{s:I,s:o}", "bits", (json_int_t)r->grid_bits, "step",
                                      proto_real(ldexp(1, -r->grid_bits))));
    if (o && !proto_run_info_encode(o, &r->run)) {
        json_decref(o);
        return NULL;
    }
    return o;
}

int proto_decode_temporal_optimize_result(const json_t *j, proto_temporal *best, double *e2,
                                          aa_error *err)
{
    memset(best, 0, sizeof *best);
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, "", "must be an object");
    int rc = proto_result_real(j, "e2", e2, err);
    if (!rc)
        rc = proto_decode_temporal(json_object_get(j, "best"), best, "best", err);
    return rc;
}

void proto_temporal_optimize_result_free(proto_temporal_optimize_result *r)
{
    proto_temporal_free(&r->best);
    free(r->phase_e2);
    free(r->per_seed);
    r->phase_e2 = NULL;
    r->per_seed = NULL;
}
