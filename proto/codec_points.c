/* The "points" pattern form: a point-set file inside a request (pointset.h).
 * {"points": {"format": "utk"|"xyw"|"csv"|"json"|"bin"|"rps",
 *  "text": "..." | "data": [...] (json) | "base64": "..." (the file's bytes; bin and rps),
 *  "set": n (one set of a file holding several), "tile": T, "kernel": K, "border": bool,
 *  "weights": "file"|"filter"|"equal"}} */
#include "codec_internal.h"
#include "pointset.h"

#include <stdio.h>
#include <stdlib.h>
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

/* The file's bytes from "text" or "base64" (*owned: to free); field gets the key's field. */
static int file_bytes(const json_t *j, proto_points_format fmt, const char **bytes, size_t *len,
                      char **owned, char *pfield, size_t pcap, const char *field, aa_error *err)
{
    const json_t *text = json_object_get(j, "text"), *b64 = json_object_get(j, "base64");
    *owned = NULL;
    proto_join_field(pfield, pcap, field, text ? "text" : "base64");
    if (text) {
        if (proto_points_format_is_binary(fmt))
            return aa_error_set(err, AA_EINVAL, pfield,
                                "a %s file is bytes: give them base64-encoded as base64",
                                proto_points_format_name(fmt));
        if (!json_is_string(text))
            return aa_error_set(err, AA_EINVAL, pfield, "must be a string (the file's contents)");
        *bytes = json_string_value(text);
        *len = json_string_length(text);
        return AA_OK;
    }
    if (!json_is_string(b64))
        return aa_error_set(err, AA_EINVAL, pfield,
                            "must be a string (the file's bytes in base64)");
    size_t bad = 0;
    unsigned char *b =
        proto_base64_decode(json_string_value(b64), json_string_length(b64), len, &bad);
    if (!b && bad == (size_t)-1)
        return aa_error_set(err, AA_ENOMEM, pfield, "out of memory");
    if (!b)
        return aa_error_set(err, AA_EINVAL, pfield,
                            "not base64 (RFC 4648, padded, no line breaks): character %zu", bad);
    *owned = (char *)b;
    *bytes = *owned;
    return AA_OK;
}

static int decode_format(const json_t *j, proto_points_format *fmt, const char *field,
                         aa_error *err)
{
    const json_t *fj = json_object_get(j, "format");
    if (!fj)
        return proto_fail(err, AA_EINVAL, field, "format", "is required: " PROTO_POINTS_FORMATS);
    if (!json_is_string(fj) || !proto_points_format_parse(json_string_value(fj), fmt))
        return proto_fail(err, AA_EINVAL, field, "format", "must be " PROTO_POINTS_FORMATS);
    return AA_OK;
}

int proto_points_form_set_count(const json_t *j, size_t *count, const char *prefix, aa_error *err)
{
    char field[PROTO_FIELD_MAX], pfield[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, prefix, "points");
    proto_points_format fmt;
    int rc = decode_format(j, &fmt, field, err);
    if (rc)
        return rc;
    *count = 1;
    if (!proto_points_format_has_sets(fmt) || json_object_get(j, "data"))
        return AA_OK;
    const char *bytes;
    size_t len;
    char *owned;
    rc = file_bytes(j, fmt, &bytes, &len, &owned, pfield, sizeof pfield, field, err);
    if (!rc)
        rc = proto_pointset_count_sets(bytes, len, fmt, count, pfield, err);
    free(owned);
    return rc;
}

int proto_decode_points_form(const json_t *j, unsigned flags, const aa_filter *weight_filter,
                             aa_pattern *out, const char *prefix, aa_error *err)
{
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, prefix, "points");
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, field,
                            "must be an object {\"format\", \"text\", \"base64\" or \"data\", "
                            "...}");
    static const char *const keys[] = {"format", "text",   "data",   "base64",  "set",
                                       "tile",   "kernel", "border", "weights", NULL};
    int rc = proto_check_keys(j, keys, err, field);
    if (rc)
        return rc;
    proto_points_format fmt;
    if ((rc = decode_format(j, &fmt, field, err)))
        return rc;
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
    const json_t *sj = json_object_get(j, "set");
    size_t set = PROTO_POINTS_WHOLE;
    char sfield[PROTO_FIELD_MAX];
    proto_join_field(sfield, sizeof sfield, field, "set");
    if (sj && json_is_string(sj) && !strcmp(json_string_value(sj), "all"))
        return aa_error_set(err, AA_EINVAL, sfield,
                            "\"all\" is for POST /v1/analyze (every set, spectra averaged); give "
                            "a set number here");
    if (sj &&
        (!json_is_integer(sj) || json_integer_value(sj) < 0 || json_integer_value(sj) > 0x7fffffff))
        return aa_error_set(err, AA_EINVAL, sfield,
                            "must be a set number from 0 (several sets in one file)");
    if (sj)
        set = (size_t)json_integer_value(sj);
    const json_t *text = json_object_get(j, "text"), *data = json_object_get(j, "data"),
                 *b64 = json_object_get(j, "base64");
    if (!!text + !!data + !!b64 != 1)
        return proto_fail(err, AA_EINVAL, field,
                          text && data   ? "data"
                          : text || data ? "base64"
                                         : "",
                          "give exactly one of text (the file's contents), base64 (its bytes) "
                          "and data (json only)");
    char pfield[PROTO_FIELD_MAX];
    proto_pointset ps;
    if (data) {
        proto_join_field(pfield, sizeof pfield, field, "data");
        if (fmt != PROTO_POINTS_JSON)
            return aa_error_set(err, AA_EINVAL, pfield,
                                "data is for format json; give the file's contents as text");
        if (sj)
            return aa_error_set(err, AA_EINVAL, sfield, "a json point set holds one set");
        rc = proto_pointset_from_json(data, true, &ps, pfield, err);
    } else {
        const char *bytes;
        size_t len;
        char *owned;
        rc = file_bytes(j, fmt, &bytes, &len, &owned, pfield, sizeof pfield, field, err);
        if (!rc)
            rc = proto_pointset_parse_set(bytes, len, fmt, set, &ps, NULL, pfield, sfield, err);
        free(owned);
    }
    if (rc)
        return rc;
    rc = proto_pattern_from_pointset(&ps, &o, out, field, pfield, err);
    proto_pointset_free(&ps);
    return rc;
}
