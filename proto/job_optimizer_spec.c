/* The optimizer kinds' shared spec fields (job_optimizer_spec.h). */
#include "job_optimizer_spec.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"

static const char *const shared_keys[] = {"filter",         "acuity",   "angles", "max_seconds",
                                          "max_iterations", "rng_seed", "method", NULL};

int proto_spec_number(const json_t *spec, const char *key, double lo, double hi, double *out,
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

int proto_spec_poisson_radius(const json_t *spec, double spp, double *out, aa_error *err)
{
    *out = aa_poisson_default_radius(spp);
    return proto_spec_number(spec, "poisson_radius", 0.001, 0.8 / sqrt(spp), out, err);
}

int proto_spec_integer(const json_t *spec, const char *key, json_int_t lo, json_int_t hi,
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

int proto_spec_string(const json_t *spec, const char *key, const char **out, aa_error *err)
{
    json_t *v = json_object_get(spec, key);
    if (!v)
        return AA_OK;
    if (!json_is_string(v) || strlen(json_string_value(v)) != json_string_length(v))
        return aa_error_set(err, AA_EINVAL, key, "must be a string");
    *out = json_string_value(v);
    return AA_OK;
}

int proto_spec_family(const json_t *spec, bool required, bool *present, aa_family *out,
                      aa_error *err)
{
    const char *text = NULL;
    int rc = proto_spec_string(spec, "family", &text, err);
    if (present)
        *present = text != NULL;
    if (rc)
        return rc;
    if (!text)
        return required ? aa_error_set(err, AA_EINVAL, "family", "family is required") : AA_OK;
    /* T(N) names a temporal jitter sequence (docs/temporal.md), not a spatial family. */
    if (!strncmp(text, "T(", 2))
        return aa_error_set(err, AA_EINVAL, "family",
                            "T(N) is a temporal family: the temporal-optimize kind optimises it");
    return aa_family_parse(text, out, err);
}

int proto_spec_distributions(const json_t *spec,
                             aa_seed_distribution distributions[PROTO_MAX_DISTRIBUTIONS],
                             size_t *count, aa_error *err)
{
    json_t *d = json_object_get(spec, "distributions");
    *count = 0;
    if (!d)
        return AA_OK;
    if (!json_is_array(d) || json_array_size(d) == 0 ||
        json_array_size(d) > PROTO_MAX_DISTRIBUTIONS)
        return aa_error_set(err, AA_EINVAL, "distributions", "must be an array of 1..%d names",
                            PROTO_MAX_DISTRIBUTIONS);
    for (size_t i = 0; i < json_array_size(d); i++) {
        char field[40];
        snprintf(field, sizeof field, "distributions[%zu]", i);
        json_t *v = json_array_get(d, i);
        if (!json_is_string(v) ||
            aa_seed_distribution_parse(json_string_value(v), &distributions[i]))
            return aa_error_set(err, AA_EINVAL, field,
                                "must be uniform, jittered, n-rooks, poisson or lloyd");
        (*count)++;
    }
    return AA_OK;
}

static int decode_mode(const json_t *spec, aa_optimize_mode *mode, aa_error *err)
{
    const char *text = NULL;
    int rc = proto_spec_string(spec, "mode", &text, err);
    if (rc || !text)
        return rc;
    if (!strcmp(text, "weights"))
        *mode = AA_OPTIMIZE_WEIGHTS;
    else if (!strcmp(text, "positions"))
        *mode = AA_OPTIMIZE_POSITIONS;
    else if (!strcmp(text, "both"))
        *mode = AA_OPTIMIZE_BOTH;
    else
        return aa_error_set(err, AA_EINVAL, "mode", "must be weights, positions or both");
    return AA_OK;
}

static int decode_method(const json_t *spec, proto_optimizer_spec *s, aa_error *err)
{
    const char *text = NULL;
    s->method_auto = true;
    int rc = proto_spec_string(spec, "method", &text, err);
    if (rc || !text || !strcmp(text, "auto"))
        return rc;
    s->method_auto = false;
    if (aa_optimize_method_parse(text, &s->method))
        return aa_error_set(err, AA_EINVAL, "method",
                            "must be auto, laine-aila, minimax or smooth");
    return AA_OK;
}

static int decode_grid(const json_t *grid, proto_optimizer_spec *s, aa_error *err)
{
    if (!grid)
        return AA_OK;
    json_int_t bits = 4;
    int d3d12 = 0;
    json_error_t je;
    if (!json_is_object(grid))
        return aa_error_set(err, AA_EINVAL, "grid", "must be an object");
    if (json_unpack_ex((json_t *)grid, &je, JSON_STRICT, "{s?I,s?b}", "bits", &bits, "d3d12",
                       &d3d12))
        return aa_error_set(err, AA_EINVAL, "grid", "expected {\"bits\":k,\"d3d12\":bool}");
    if (bits < 1 || bits > 12)
        return aa_error_set(err, AA_EINVAL, "grid.bits", "must be 1..12");
    s->grid_bits = (int)bits;
    s->d3d12 = d3d12;
    return AA_OK;
}

static int check_keys(const json_t *spec, const char *const *kind_keys, unsigned fields,
                      aa_error *err)
{
    static const char *const mode[] = {"mode", NULL}, *const grid[] = {"grid", NULL};
    static const char *const none[] = {NULL};
    const char *const *const lists[] = {shared_keys, fields & PROTO_OPT_MODE ? mode : none,
                                        fields & PROTO_OPT_GRID ? grid : none, kind_keys, NULL};
    return proto_check_keys_in(spec, lists, err, "");
}

int proto_spec_metric(const json_t *spec, aa_filter *filter, aa_acuity *acuity, double **angles,
                      size_t *angle_count, aa_error *err)
{
    int rc = proto_decode_filter(json_object_get(spec, "filter"), filter, "filter", err);
    if (!rc)
        rc = proto_decode_acuity(json_object_get(spec, "acuity"), acuity, "acuity", err);
    if (!rc)
        rc = proto_decode_angles(json_object_get(spec, "angles"), angles, angle_count, "angles",
                                 err);
    return rc;
}

int proto_spec_budget(const json_t *spec, json_int_t iterations_max, double *max_seconds,
                      long *max_iterations, bool *reproducible, aa_error *err)
{
    json_int_t iterations = 0;
    int rc = proto_spec_number(spec, "max_seconds", 0.01, 86400, max_seconds, err);
    if (!rc)
        rc = proto_spec_integer(spec, "max_iterations", 1, iterations_max, &iterations, err);
    *max_iterations = (long)iterations;
    *reproducible = iterations > 0 && !json_object_get(spec, "max_seconds");
    if (*reproducible)
        *max_seconds = 0;
    return rc;
}

int proto_optimizer_spec_decode(const json_t *spec, const char *const *kind_keys, unsigned fields,
                                double def_seconds, proto_optimizer_spec *s, aa_error *err)
{
    memset(s, 0, sizeof *s);
    s->max_seconds = def_seconds;
    s->mode = AA_OPTIMIZE_BOTH;
    s->rng_seed = 1;
    int rc = check_keys(spec, kind_keys, fields, err);
    if (!rc)
        rc = proto_spec_metric(spec, &s->filter, &s->acuity, &s->angles, &s->angle_count, err);
    if (!rc)
        rc = proto_spec_budget(spec, 10000000, &s->max_seconds, &s->max_iterations,
                               &s->reproducible, err);
    json_int_t seed = 1;
    if (!rc)
        rc = proto_spec_integer(spec, "rng_seed", 0, (json_int_t)1 << 53, &seed, err);
    s->rng_seed = (uint64_t)seed;
    if (!rc)
        rc = decode_mode(spec, &s->mode, err);
    if (!rc)
        rc = decode_method(spec, s, err);
    if (!rc)
        rc = decode_grid(json_object_get(spec, "grid"), s, err);
    if (rc)
        proto_optimizer_spec_free(s);
    return rc;
}

void proto_optimizer_spec_free(proto_optimizer_spec *s)
{
    free(s->angles);
    s->angles = NULL;
}

aa_metric_params proto_optimizer_spec_metric(const proto_optimizer_spec *s)
{
    aa_metric_params m = {&s->filter, &s->acuity, s->angles, s->angle_count, 0};
    return m;
}

aa_optimize_method proto_optimizer_spec_method(const proto_optimizer_spec *s,
                                               bool tiled_without_border, aa_optimize_mode mode)
{
    return s->method_auto ? aa_auto_method(tiled_without_border, mode) : s->method;
}

long proto_optimizer_spec_iterations(const proto_optimizer_spec *s, long def)
{
    return s->max_iterations > 0 ? s->max_iterations : def;
}
