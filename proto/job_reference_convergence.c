#include "job_reference_convergence.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "codec.h"
#include "codec_internal.h"

static const char *const kind_keys[] = {"levels", "baseline_spp", "kernel_size", NULL};

static bool valid_spp(const json_t *v, int *out)
{
    if (!json_is_integer(v))
        return false;
    json_int_t x = json_integer_value(v);
    if (x < 1 || x > AA_REFERENCE_MAX_SPP)
        return false;
    long m = lround(sqrt((double)x));
    *out = (int)x;
    return m * m == x;
}

int proto_decode_reference_convergence_spec(const json_t *spec,
                                            proto_reference_convergence_spec *cp, aa_error *err)
{
    static const int default_levels[] = {16, 64, 256, 1024};
    memset(cp, 0, sizeof *cp);
    memcpy(cp->levels, default_levels, sizeof default_levels);
    cp->level_count = 4;
    cp->baseline_spp = 4096;
    cp->kernel_size = 1;
    int rc = proto_render_spec_decode(spec, kind_keys, 0, &cp->common, err);
    json_t *levels = json_object_get(spec, "levels");
    if (!rc && levels) {
        if (!json_is_array(levels) || json_array_size(levels) == 0 ||
            json_array_size(levels) > PROTO_CONVERGENCE_MAX_LEVELS) {
            rc = aa_error_set(err, AA_EINVAL, "levels", "a list of 1..%d spp values",
                              PROTO_CONVERGENCE_MAX_LEVELS);
        } else {
            cp->level_count = json_array_size(levels);
            for (size_t i = 0; i < cp->level_count && !rc; i++) {
                if (!valid_spp(json_array_get(levels, i), &cp->levels[i])) {
                    char field[32];
                    snprintf(field, sizeof field, "levels[%zu]", i);
                    rc = aa_error_set(err, AA_EINVAL, field, "spp must be a square in 1..%d",
                                      AA_REFERENCE_MAX_SPP);
                }
            }
        }
    }
    json_t *base = json_object_get(spec, "baseline_spp");
    if (!rc && base && !valid_spp(base, &cp->baseline_spp))
        rc = aa_error_set(err, AA_EINVAL, "baseline_spp", "spp must be a square in 1..%d",
                          AA_REFERENCE_MAX_SPP);
    json_t *ks = json_object_get(spec, "kernel_size");
    if (!rc && ks) {
        if (!json_is_integer(ks) || json_integer_value(ks) < 1 ||
            json_integer_value(ks) > AA_MAX_KERNEL_SIZE)
            rc = aa_error_set(err, AA_EINVAL, "kernel_size", "must be 1..%d", AA_MAX_KERNEL_SIZE);
        else
            cp->kernel_size = (int)json_integer_value(ks);
    }
    return rc;
}

void proto_reference_convergence_spec_free(proto_reference_convergence_spec *s)
{
    (void)s; /* nothing of its own to free */
}

json_t *proto_encode_reference_convergence_result(const proto_reference_convergence_result *r)
{
    json_t *rows = json_array();
    for (size_t i = 0; rows && i < r->row_count; i++) {
        const proto_convergence_level *l = &r->rows[i];
        if (json_array_append_new(rows, json_pack("{s:I, s:f, s:f, s:f, s:I, s:I}", "spp",
                                                  (json_int_t)l->spp, "rmse", l->rmse, "max_dev",
                                                  l->max_dev, "seconds", l->seconds, "supersampled",
                                                  (json_int_t)l->supersampled, "samples",
                                                  (json_int_t)l->samples))) {
            json_decref(rows);
            return NULL;
        }
    }
    const proto_convergence_level *b = &r->baseline;
    return json_pack("{s:o, s:f, s:{s:I, s:f, s:I, s:I}, s:o}", "scene",
                     proto_encode_scene(&r->scene), "output_offset", r->output_offset, "baseline",
                     "spp", (json_int_t)b->spp, "seconds", b->seconds, "supersampled",
                     (json_int_t)b->supersampled, "samples", (json_int_t)b->samples, "rows", rows);
}

static const char *const result_keys[] = {"scene", "output_offset", "baseline", "rows", NULL};
static const char *const baseline_keys[] = {"spp", "seconds", "supersampled", "samples", NULL};
static const char *const row_keys[] = {"spp",          "rmse",    "max_dev", "seconds",
                                       "supersampled", "samples", NULL};

static int decode_level(const json_t *j, bool row, proto_convergence_level *l, const char *at,
                        aa_error *err)
{
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, at, "must be an object");
    int rc = proto_check_keys(j, row ? row_keys : baseline_keys, err, at);
    if (!rc)
        rc = proto_result_count(j, "spp", &l->spp, at, err);
    if (!rc && (l->spp < 1 || l->spp > AA_REFERENCE_MAX_SPP)) {
        aa_error_set(err, AA_ERANGE, "spp", "must be in 1..%d", AA_REFERENCE_MAX_SPP);
        rc = proto_prefix_error(err, at);
    }
    if (!rc && row)
        rc = proto_result_number(j, "rmse", &l->rmse, at, err);
    if (!rc && row)
        rc = proto_result_number(j, "max_dev", &l->max_dev, at, err);
    if (!rc)
        rc = proto_result_number(j, "seconds", &l->seconds, at, err);
    if (!rc)
        rc = proto_result_count(j, "supersampled", &l->supersampled, at, err);
    if (!rc)
        rc = proto_result_count(j, "samples", &l->samples, at, err);
    return rc;
}

int proto_decode_reference_convergence_result(const json_t *j,
                                              proto_reference_convergence_result *r, aa_error *err)
{
    memset(r, 0, sizeof *r);
    const json_t *rows = json_object_get(j, "rows");
    int rc = json_is_object(j) ? proto_check_keys(j, result_keys, err, "")
                               : aa_error_set(err, AA_EINVAL, "", "must be an object");
    if (!rc)
        rc = proto_decode_scene(json_object_get(j, "scene"), &r->scene, "scene", err);
    if (!rc)
        rc = proto_result_number(j, "output_offset", &r->output_offset, "", err);
    if (!rc && r->output_offset != 0.5 && r->output_offset != 1.0)
        rc = aa_error_set(err, AA_ERANGE, "output_offset", "must be 0.5 or 1");
    if (!rc)
        rc = decode_level(json_object_get(j, "baseline"), false, &r->baseline, "baseline", err);
    if (!rc && (!json_is_array(rows) || json_array_size(rows) > PROTO_CONVERGENCE_MAX_LEVELS))
        rc = aa_error_set(err, AA_EINVAL, "rows", "must be an array of at most %d levels",
                          PROTO_CONVERGENCE_MAX_LEVELS);
    for (size_t i = 0; !rc && i < json_array_size(rows); i++) {
        char at[32];
        snprintf(at, sizeof at, "rows[%zu]", i);
        rc = decode_level(json_array_get(rows, i), true, &r->rows[i], at, err);
        r->row_count = i + 1;
    }
    return rc;
}

void proto_reference_convergence_result_free(proto_reference_convergence_result *r)
{
    (void)r; /* nothing of its own to free */
}
