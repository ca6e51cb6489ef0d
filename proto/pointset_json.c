/* JSON point sets -> points (pointset.h): [[x,y], [x,y,w], {"x","y","w"}, ...] or the object
 * form {"aalab": {...}, "points": [...]}. */
#include "pointset.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "codec_internal.h"

/* One JSON point at index i. */
static int json_point(const json_t *e, size_t i, bool by_index, proto_point *p, bool *has_w,
                      const char *field, aa_error *err)
{
    char f[PROTO_FIELD_MAX], where[40] = "";
    if (by_index) {
        char idx[32];
        snprintf(idx, sizeof idx, "[%zu]", i);
        proto_join_field(f, sizeof f, field, idx);
    } else {
        proto_join_field(f, sizeof f, field, "");
        snprintf(where, sizeof where, "point %zu: ", i);
    }
    const json_t *v[3] = {NULL, NULL, NULL};
    if (json_is_array(e)) {
        size_t n = json_array_size(e);
        if (n != 2 && n != 3)
            return aa_error_set(err, AA_EINVAL, f, "%sa point is [x, y] or [x, y, w]", where);
        for (size_t k = 0; k < n; k++)
            v[k] = json_array_get(e, k);
    } else if (json_is_object(e)) {
        static const char *const keys[] = {"x", "y", "w", NULL};
        const char *key;
        json_t *val;
        char cut[48];
        json_object_foreach((json_t *)e, key, val)
        {
            bool ok = false;
            for (int k = 0; keys[k]; k++)
                ok = ok || !strcmp(key, keys[k]);
            if (!ok)
                return aa_error_set(err, AA_EINVAL, f,
                                    "%sunknown key '%s' (a point has x, y "
                                    "and optionally w)",
                                    where, proto_utf8_prefix(cut, sizeof cut, key, 40));
        }
        v[0] = json_object_get(e, "x");
        v[1] = json_object_get(e, "y");
        v[2] = json_object_get(e, "w");
        if (!v[0] || !v[1])
            return aa_error_set(err, AA_EINVAL, f, "%sa point needs x and y", where);
    } else {
        return aa_error_set(err, AA_EINVAL, f,
                            "%sa point is [x, y], [x, y, w] or {\"x\":..,\"y\":..,\"w\":..}",
                            where);
    }
    double d[3] = {0, 0, 0};
    static const char *const names[] = {"x", "y", "w"};
    for (int k = 0; k < 3; k++) {
        if (!v[k])
            continue;
        if (!json_is_number(v[k]) || !isfinite(json_number_value(v[k])))
            return aa_error_set(err, AA_EINVAL, f, "%s%s must be a finite number", where, names[k]);
        d[k] = json_number_value(v[k]);
    }
    *p = (proto_point){d[0], d[1], d[2]};
    *has_w = v[2] != NULL;
    return AA_OK;
}

int proto_pointset_from_json(const json_t *j, bool by_index, proto_pointset *out, const char *field,
                             aa_error *err)
{
    memset(out, 0, sizeof *out);
    out->by_index = by_index;
    const json_t *arr = j;
    char f[PROTO_FIELD_MAX];
    proto_join_field(f, sizeof f, field, "");
    if (json_is_object(j)) {
        static const char *const keys[] = {"aalab", "points", NULL};
        int rc = proto_check_keys(j, keys, err, f);
        if (rc)
            return rc;
        arr = json_object_get(j, "points");
        const json_t *h = json_object_get(j, "aalab");
        if (!arr)
            return proto_fail(err, AA_EINVAL, f, "points", "the object form needs points");
        if (h && !json_is_object(h))
            return proto_fail(err, AA_EINVAL, f, "aalab", "must be an object");
        if (h)
            out->header = json_incref((json_t *)h);
        if (by_index)
            proto_join_field(f, sizeof f, field, "points");
    }
    if (!json_is_array(arr)) {
        proto_pointset_free(out);
        return aa_error_set(
            err, AA_EINVAL, f,
            "must be an array of points ([x, y], [x, y, w] or {\"x\",\"y\",\"w\"})");
    }
    size_t n = json_array_size(arr), cap = 0;
    int rc = AA_OK;
    if (n > PROTO_POINTS_MAX)
        rc = aa_error_set(err, AA_ERANGE, f, "more than %d points", PROTO_POINTS_MAX);
    for (size_t i = 0; i < n && !rc; i++) {
        proto_point p = {0, 0, 0};
        bool has_w = false;
        rc = json_point(json_array_get(arr, i), i, by_index, &p, &has_w, f, err);
        if (!rc && i > 0 && has_w != out->has_weights) {
            char idx[32], pf[PROTO_FIELD_MAX], where[40] = "";
            snprintf(idx, sizeof idx, "[%zu]", i);
            proto_join_field(pf, sizeof pf, f, by_index ? idx : "");
            if (!by_index)
                snprintf(where, sizeof where, "point %zu: ", i);
            rc =
                aa_error_set(err, AA_EINVAL, pf, "%s%s (give w for every point or for none)", where,
                             has_w ? "has w but point 0 has not" : "has no w but point 0 has");
        }
        if (!rc && i == 0)
            out->has_weights = has_w;
        if (!rc && proto_pointset_push(out, &cap, p, i))
            rc = aa_error_set(err, AA_ENOMEM, f, "out of memory");
    }
    if (!rc && n == 0)
        rc = aa_error_set(err, AA_EINVAL, f, "no points");
    if (rc)
        proto_pointset_free(out);
    return rc;
}
