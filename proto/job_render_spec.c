#include "job_render_spec.h"

#include <math.h>
#include <string.h>

#include "codec.h"
#include "codec_internal.h"
#include "preset_suggest.h"

static int check_keys(const json_t *spec, const char *const *kind_keys, unsigned fields,
                      aa_error *err)
{
    static const char *const shared[] = {"scene", "size", "reference", NULL};
    static const char *const acuity[] = {"acuity", NULL}, *const tiles[] = {"tiles", NULL};
    static const char *const none[] = {NULL};
    const char *const *const lists[] = {shared, fields & PROTO_RENDER_SPEC_ACUITY ? acuity : none,
                                        fields & PROTO_RENDER_SPEC_TILES ? tiles : none, kind_keys,
                                        NULL};
    return proto_check_keys_in(spec, lists, err, "");
}

int proto_render_spec_decode(const json_t *spec, const char *const *kind_keys, unsigned fields,
                             proto_render_spec *s, aa_error *err)
{
    memset(s, 0, sizeof *s);
    s->tiles = true;
    int rc = check_keys(spec, kind_keys, fields, err);
    if (!rc)
        rc = proto_decode_scene_request(spec, &s->scene, err);
    if (!rc)
        rc = proto_decode_reference(json_object_get(spec, "reference"), &s->ref, "reference", err);
    if (!rc)
        rc = proto_decode_acuity(json_object_get(spec, "acuity"), &s->acuity, "acuity", err);
    json_t *tiles = json_object_get(spec, "tiles");
    if (!rc && tiles) {
        if (!json_is_boolean(tiles))
            rc = aa_error_set(err, AA_EINVAL, "tiles", "must be true or false");
        else
            s->tiles = json_is_true(tiles);
    }
    return rc;
}

int proto_render_pattern_decode(const json_t *j, aa_pattern *out, const char *field, aa_error *err)
{
    if (json_is_string(j) && !aa_preset_find(json_string_value(j)))
        return proto_unknown_preset(err, field, json_string_value(j));
    int rc = proto_pattern_from_preset_name(j, out, field, err);
    if (rc == 1)
        rc = proto_decode_pattern(j, 0, out, field, err);
    return rc;
}

static int field_error(aa_error *err, int code, const char *prefix, const char *key,
                       const char *message)
{
    aa_error_set(err, code, key, "%s", message);
    return proto_prefix_error(err, prefix);
}

int proto_result_number(const json_t *obj, const char *key, double *out, const char *prefix,
                        aa_error *err)
{
    const json_t *v = json_object_get(obj, key);
    if (!json_is_number(v) || !isfinite(json_number_value(v)))
        return field_error(err, AA_EINVAL, prefix, key, "must be a number");
    *out = json_number_value(v);
    return AA_OK;
}

int proto_result_count(const json_t *obj, const char *key, long long *out, const char *prefix,
                       aa_error *err)
{
    const json_t *v = json_object_get(obj, key);
    if (!json_is_integer(v))
        return field_error(err, AA_EINVAL, prefix, key, "must be an integer");
    if (json_integer_value(v) < 0)
        return field_error(err, AA_ERANGE, prefix, key, "must be >= 0");
    *out = json_integer_value(v);
    return AA_OK;
}

int proto_result_string(const json_t *obj, const char *key, char *out, size_t size,
                        const char *prefix, aa_error *err)
{
    const char *v = json_string_value(json_object_get(obj, key));
    if (!v)
        return field_error(err, AA_EINVAL, prefix, key, "must be a string");
    if (strlen(v) >= size)
        return field_error(err, AA_ERANGE, prefix, key, "is too long");
    memcpy(out, v, strlen(v) + 1);
    return AA_OK;
}

int proto_result_tile(const json_t *obj, const char *key, json_t **out, const char *prefix,
                      aa_error *err)
{
    json_t *v = json_object_get(obj, key);
    *out = NULL;
    if (!v)
        return AA_OK;
    if (!json_is_object(v))
        return field_error(err, AA_EINVAL, prefix, key, "must be a tile reference object");
    *out = json_incref(v);
    return AA_OK;
}

int proto_decode_diff(const json_t *j, aa_diff_stats *d, const char *prefix, aa_error *err)
{
    static const char *const keys[] = {"rmse",   "histogram",           "max_dev",
                                       "pixels", "penalised_histogram", NULL};
    memset(d, 0, sizeof *d);
    if (!json_is_object(j))
        return field_error(err, AA_EINVAL, prefix, "", "must be an object");
    long long pixels = 0;
    int rc = proto_check_keys(j, keys, err, prefix);
    if (!rc)
        rc = proto_result_number(j, "rmse", &d->rmse, prefix, err);
    if (!rc)
        rc = proto_result_number(j, "max_dev", &d->max_dev, prefix, err);
    if (!rc)
        rc = proto_result_count(j, "pixels", &pixels, prefix, err);
    d->pixels = (size_t)pixels;
    const json_t *hist = json_object_get(j, "histogram");
    const json_t *pen = json_object_get(j, "penalised_histogram");
    if (!rc && (!json_is_array(hist) || json_array_size(hist) != 256))
        rc = field_error(err, AA_EINVAL, prefix, "histogram", "must be an array of 256 counts");
    if (!rc && (!json_is_array(pen) || json_array_size(pen) != 256))
        rc = field_error(err, AA_EINVAL, prefix, "penalised_histogram",
                         "must be an array of 256 numbers");
    double n = d->pixels ? (double)d->pixels : 1.0;
    size_t total = 0;
    for (int i = 0; i < 256 && !rc; i++) {
        const json_t *h = json_array_get(hist, (size_t)i), *p = json_array_get(pen, (size_t)i);
        char at[40];
        if (!json_is_integer(h) || json_integer_value(h) < 0) {
            snprintf(at, sizeof at, "histogram[%d]", i);
            rc = field_error(err, AA_EINVAL, prefix, at, "must be an integer >= 0");
            break;
        }
        d->histogram[i] = (size_t)json_integer_value(h);
        total += d->histogram[i];
        d->penalised[i] = (double)d->histogram[i] * i * i / n;
        if (!json_is_number(p) || json_number_value(p) != d->penalised[i]) {
            snprintf(at, sizeof at, "penalised_histogram[%d]", i);
            rc = field_error(err, AA_EINVAL, prefix, at, "must be histogram[i] * i^2 / pixels");
        }
    }
    if (!rc && total != d->pixels)
        rc = field_error(err, AA_EINVAL, prefix, "histogram", "must count every pixel once");
    d->sum_sq = d->rmse * d->rmse * n;
    return rc;
}
