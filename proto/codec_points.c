/* The "points" pattern form: a point-set file inside a request (pointset.h).
 * {"points": {"format": "utk"|"xyw"|"csv"|"json", "text": "..." | "data": [...] (json),
 *  "tile": T, "kernel": K, "border": bool, "weights": "file"|"filter"|"equal"}} */
#include "codec_internal.h"
#include "pointset.h"

#include <string.h>

static int option_int(const json_t *j, const char *key, int lo, int hi, int *out, const char *field,
                      aa_error *err)
{
    const json_t *v = json_object_get(j, key);
    if (!v)
        return AA_OK;
    if (!json_is_integer(v))
        return proto_fail(err, AA_EINVAL, field, key, "must be an integer");
    json_int_t n = json_integer_value(v);
    if (n < lo || n > hi) {
        char f[PROTO_FIELD_MAX];
        proto_join_field(f, sizeof f, field, key);
        return aa_error_set(err, AA_ERANGE, f, "must be in %d..%d", lo, hi);
    }
    *out = (int)n;
    return AA_OK;
}

int proto_decode_points_form(const json_t *j, unsigned flags, const aa_filter *weight_filter,
                             aa_pattern *out, const char *prefix, aa_error *err)
{
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, prefix, "points");
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, field,
                            "must be an object {\"format\", \"text\" or \"data\", ...}");
    static const char *const keys[] = {"format", "text",   "data",    "tile",
                                       "kernel", "border", "weights", NULL};
    int rc = proto_check_keys(j, keys, err, field);
    if (rc)
        return rc;
    const json_t *fj = json_object_get(j, "format");
    proto_points_format fmt;
    if (!fj)
        return proto_fail(err, AA_EINVAL, field, "format", "is required: utk, xyw, csv or json");
    if (!json_is_string(fj) || !proto_points_format_parse(json_string_value(fj), &fmt))
        return proto_fail(err, AA_EINVAL, field, "format", "must be utk, xyw, csv or json");
    proto_points_options o = proto_points_options_default();
    o.flags = flags;
    o.filter = weight_filter;
    if ((rc = option_int(j, "tile", 1, AA_MAX_TILE, &o.tile, field, err)) ||
        (rc = option_int(j, "kernel", 1, AA_MAX_KERNEL_SIZE, &o.kernel, field, err)))
        return rc;
    const json_t *b = json_object_get(j, "border");
    if (b && !json_is_boolean(b))
        return proto_fail(err, AA_EINVAL, field, "border", "must be true or false");
    if (b)
        o.border = json_is_true(b);
    const json_t *w = json_object_get(j, "weights");
    if (w && (!json_is_string(w) || !proto_weights_rule_parse(json_string_value(w), &o.weights)))
        return proto_fail(err, AA_EINVAL, field, "weights", "must be file, filter or equal");
    const json_t *text = json_object_get(j, "text"), *data = json_object_get(j, "data");
    if (!text == !data)
        return proto_fail(err, AA_EINVAL, field, text ? "data" : "",
                          "give exactly one of text (the file's contents) and data (json only)");
    char pfield[PROTO_FIELD_MAX];
    proto_join_field(pfield, sizeof pfield, field, text ? "text" : "data");
    proto_pointset ps;
    if (text) {
        if (!json_is_string(text))
            return aa_error_set(err, AA_EINVAL, pfield, "must be a string (the file's contents)");
        rc = proto_pointset_parse(json_string_value(text), json_string_length(text), fmt, &ps,
                                  pfield, err);
    } else {
        if (fmt != PROTO_POINTS_JSON)
            return aa_error_set(err, AA_EINVAL, pfield,
                                "data is for format json; give the file's contents as text");
        rc = proto_pointset_from_json(data, true, &ps, pfield, err);
    }
    if (rc)
        return rc;
    rc = proto_pattern_from_pointset(&ps, &o, out, field, pfield, err);
    proto_pointset_free(&ps);
    return rc;
}
