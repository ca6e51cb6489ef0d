/* Pattern wire forms <-> aa_pattern. */
#include "codec_internal.h"
#include "preset_suggest.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aa_pattern.h"

/* Finite number without building a field path (the fast path of decode_triple). */
static bool finite_number(const json_t *j, double *out)
{
    if (!json_is_number(j))
        return false;
    *out = json_number_value(j);
    return isfinite(*out);
}

/* [x,y,w] (or [x,y] when want_w is false) at path prefix+sub. The path is only built when
 * something is wrong (decoding is on the evaluate hot path). */
static int decode_triple(const json_t *j, bool want_w, double *x, double *y, double *w,
                         const char *prefix, const char *sub, aa_error *err)
{
    size_t need = want_w ? 3 : 2;
    if (json_is_array(j) && json_array_size(j) == need && finite_number(json_array_get(j, 0), x) &&
        finite_number(json_array_get(j, 1), y) &&
        (!want_w || finite_number(json_array_get(j, 2), w)))
        return AA_OK;
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, prefix, sub);
    if (!json_is_array(j) || json_array_size(j) != need)
        return aa_error_set(err, AA_EINVAL, field,
                            want_w ? "a sample is an array [x, y, w]" : "a sample is [x, y]");
    int rc = proto_number(json_array_get(j, 0), x, err, field, "[0]");
    if (!rc)
        rc = proto_number(json_array_get(j, 1), y, err, field, "[1]");
    if (!rc && want_w)
        rc = proto_number(json_array_get(j, 2), w, err, field, "[2]");
    return rc;
}

/* [[x,y,w],...] into a malloc'd sample array. */
static int decode_samples(const json_t *j, aa_sample **out, size_t *count, const char *prefix,
                          const char *sub, aa_error *err)
{
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, prefix, sub);
    *out = NULL;
    *count = 0;
    if (!json_is_array(j))
        return aa_error_set(err, AA_EINVAL, field, "must be an array of [x, y, w] samples");
    size_t n = json_array_size(j);
    if (n == 0)
        return aa_error_set(err, AA_EINVAL, field, "needs at least one sample");
    if (n > AA_MAX_KERNEL_SAMPLES)
        return aa_error_set(err, AA_ERANGE, field, "at most %d samples", AA_MAX_KERNEL_SAMPLES);
    aa_sample *s = malloc(n * sizeof *s);
    if (!s)
        return aa_error_set(err, AA_ENOMEM, field, "out of memory");
    for (size_t i = 0; i < n; i++) {
        const json_t *e = json_array_get(j, i);
        if (json_is_array(e) && json_array_size(e) == 3 &&
            finite_number(json_array_get(e, 0), &s[i].x) &&
            finite_number(json_array_get(e, 1), &s[i].y) &&
            finite_number(json_array_get(e, 2), &s[i].w))
            continue;
        char idx[32];
        snprintf(idx, sizeof idx, "[%zu]", i);
        int rc = decode_triple(e, true, &s[i].x, &s[i].y, &s[i].w, field, idx, err);
        if (rc) {
            free(s);
            return rc;
        }
    }
    *out = s;
    *count = n;
    return AA_OK;
}

static int decode_kernels(const json_t *j, unsigned flags, aa_pattern *out, const char *prefix,
                          aa_error *err)
{
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, prefix, "kernels");
    if (!json_is_array(j))
        return aa_error_set(err, AA_EINVAL, field, "must be an array of kernels");
    size_t s = json_array_size(j);
    if (s == 0)
        return aa_error_set(err, AA_EINVAL, field, "a pattern needs at least one kernel");
    if (s > AA_MAX_KERNELS)
        return aa_error_set(err, AA_ERANGE, field, "at most %d kernels", AA_MAX_KERNELS);
    aa_sample **kernels = calloc(s, sizeof *kernels);
    size_t *counts = calloc(s, sizeof *counts);
    int rc = AA_OK;
    if (!kernels || !counts)
        rc = aa_error_set(err, AA_ENOMEM, field, "out of memory");
    for (size_t k = 0; k < s && !rc; k++) {
        char idx[32];
        snprintf(idx, sizeof idx, "[%zu]", k);
        rc = decode_samples(json_array_get(j, k), &kernels[k], &counts[k], field, idx, err);
    }
    if (!rc) {
        rc = aa_pattern_from_kernels(out, (const aa_sample *const *)kernels, counts, s, flags, err);
        if (rc)
            proto_prefix_error(err, prefix);
    }
    for (size_t k = 0; kernels && k < s; k++)
        free(kernels[k]);
    free(kernels);
    free(counts);
    return rc;
}

static int decode_mirrored(const json_t *j, unsigned flags, aa_pattern *out, const char *prefix,
                           aa_error *err)
{
    aa_sample *s;
    size_t n;
    int rc = decode_samples(j, &s, &n, prefix, "mirrored", err);
    if (rc)
        return rc;
    rc = aa_pattern_from_mirrored(out, s, n, flags, err);
    if (rc)
        proto_prefix_error(err, prefix);
    free(s);
    return rc;
}

static int decode_int(const json_t *j, int lo, int hi, int *out, const char *prefix,
                      const char *sub, aa_error *err)
{
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, prefix, sub);
    if (!json_is_integer(j))
        return aa_error_set(err, AA_EINVAL, field, "must be an integer");
    json_int_t v = json_integer_value(j);
    if (v < lo || v > hi)
        return aa_error_set(err, AA_ERANGE, field, "must be in %d..%d", lo, hi);
    *out = (int)v;
    return AA_OK;
}

static int decode_tile(const json_t *j, unsigned flags, aa_pattern *out, const char *prefix,
                       aa_error *err)
{
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, prefix, "tile");
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, field, "must be an object");
    static const char *const keys[] = {"size", "kernel", "border", "samples", "weights", NULL};
    int rc = proto_check_keys(j, keys, err, field);
    if (rc)
        return rc;
    aa_tile_spec spec = {0};
    const json_t *v = json_object_get(j, "size");
    if (!v)
        return proto_fail(err, AA_EINVAL, field, "size", "is required");
    if ((rc = decode_int(v, 1, AA_MAX_TILE, &spec.tile, field, "size", err)))
        return rc;
    v = json_object_get(j, "kernel");
    spec.kernel_size = 1;
    if (v && (rc = decode_int(v, 1, AA_MAX_KERNEL_SIZE, &spec.kernel_size, field, "kernel", err)))
        return rc;
    v = json_object_get(j, "border");
    if (v && !json_is_boolean(v))
        return proto_fail(err, AA_EINVAL, field, "border", "must be true or false");
    spec.border = v && json_is_true(v);

    const json_t *samples = json_object_get(j, "samples");
    char sfield[PROTO_FIELD_MAX];
    proto_join_field(sfield, sizeof sfield, field, "samples");
    if (!json_is_array(samples))
        return aa_error_set(err, AA_EINVAL, sfield, "must be an array of [x, y] positions");
    size_t n = json_array_size(samples);
    if (n == 0)
        return aa_error_set(err, AA_EINVAL, sfield, "a tile needs at least one sample");
    if (n > AA_MAX_KERNEL_SAMPLES)
        return aa_error_set(err, AA_ERANGE, sfield, "at most %d samples", AA_MAX_KERNEL_SAMPLES);
    aa_point *pts = malloc(n * sizeof *pts);
    if (!pts)
        return aa_error_set(err, AA_ENOMEM, sfield, "out of memory");
    for (size_t i = 0; i < n && !rc; i++) {
        char idx[32];
        snprintf(idx, sizeof idx, "[%zu]", i);
        rc = decode_triple(json_array_get(samples, i), false, &pts[i].x, &pts[i].y, NULL, sfield,
                           idx, err);
    }
    spec.count = n;
    spec.samples = pts;

    const json_t *weights = json_object_get(j, "weights");
    double **w = NULL;
    size_t *wc = NULL;
    size_t kc = (size_t)spec.tile * (size_t)spec.tile;
    aa_filter filter;
    char wfield[PROTO_FIELD_MAX];
    proto_join_field(wfield, sizeof wfield, field, "weights");
    if (!rc && weights && !json_is_null(weights)) {
        if (!json_is_array(weights) || json_array_size(weights) != kc) {
            rc = aa_error_set(err, AA_EINVAL, wfield,
                              "must be an array of %zu weight lists (one per kernel)", kc);
        } else {
            w = calloc(kc, sizeof *w);
            wc = calloc(kc, sizeof *wc);
            if (!w || !wc)
                rc = aa_error_set(err, AA_ENOMEM, wfield, "out of memory");
        }
        for (size_t k = 0; k < kc && !rc; k++) {
            const json_t *list = json_array_get(weights, k);
            char kfield[PROTO_FIELD_MAX], idx[32];
            snprintf(idx, sizeof idx, "[%zu]", k);
            proto_join_field(kfield, sizeof kfield, wfield, idx);
            if (!json_is_array(list) || json_array_size(list) > AA_MAX_KERNEL_SAMPLES) {
                rc = aa_error_set(err, AA_EINVAL, kfield, "must be an array of numbers");
                break;
            }
            wc[k] = json_array_size(list);
            w[k] = malloc((wc[k] ? wc[k] : 1) * sizeof **w);
            if (!w[k]) {
                rc = aa_error_set(err, AA_ENOMEM, kfield, "out of memory");
                break;
            }
            for (size_t m = 0; m < wc[k] && !rc; m++) {
                snprintf(idx, sizeof idx, "[%zu]", m);
                rc = proto_number(json_array_get(list, m), &w[k][m], err, kfield, idx);
            }
        }
        spec.weights = (const double *const *)w;
        spec.weight_counts = wc;
    } else if (!rc) {
        aa_filter_default(&filter);
        spec.weight_filter = &filter;
    }
    if (!rc) {
        rc = aa_pattern_from_tile(out, &spec, flags, err);
        if (rc)
            proto_prefix_error(err, prefix);
    }
    for (size_t k = 0; w && k < kc; k++)
        free(w[k]);
    free(w);
    free(wc);
    free(pts);
    return rc;
}

int proto_decode_pattern(const json_t *j, unsigned flags, aa_pattern *out, const char *field_prefix,
                         aa_error *err)
{
    return proto_decode_pattern_filtered(j, flags, NULL, out, field_prefix, err);
}

int proto_decode_pattern_filtered(const json_t *j, unsigned flags, const aa_filter *weight_filter,
                                  aa_pattern *out, const char *field_prefix, aa_error *err)
{
    memset(out, 0, sizeof *out);
    const char *prefix = field_prefix ? field_prefix : "";
    if (!json_is_object(j))
        return proto_fail(err, AA_EINVAL, prefix, "",
                          "a pattern is an object with one of preset, kernels, mirrored, tile, "
                          "points");
    static const char *const keys[] = {
        "preset",   "kernels", "mirrored",         "tile", "points",   "normalize", "family",
        "cost_spp", "form",    "kernels_expanded", "name", "temporal", NULL};
    int rc = proto_check_keys(j, keys, err, prefix);
    if (rc)
        return rc;
    /* A temporal pattern is a set of phase kernels, not one pattern: POST /v1/evaluate,
     * POST /v1/predict, POST /v1/render, POST /v1/analyze, the exports and the compare,
     * temporal-optimize and temporal-render kinds decode it themselves (codec_temporal.h);
     * elsewhere it is refused. */
    if (json_object_get(j, "temporal"))
        return proto_fail(err, AA_EINVAL, prefix, "temporal",
                          "a temporal pattern is accepted by POST /v1/evaluate, POST "
                          "/v1/predict, POST /v1/render, POST /v1/analyze, the exports and the "
                          "compare, temporal-optimize and temporal-render job kinds only");
    const json_t *norm = json_object_get(j, "normalize");
    if (norm) {
        if (!json_is_boolean(norm))
            return proto_fail(err, AA_EINVAL, prefix, "normalize", "must be true or false");
        if (json_is_true(norm))
            flags |= AA_PATTERN_NORMALIZE;
    }
    static const char *const forms[] = {"preset", "kernels", "mirrored", "tile", "points"};
    const char *form = NULL;
    for (size_t i = 0; i < 5; i++) {
        if (json_object_get(j, forms[i])) {
            if (form)
                return proto_fail(err, AA_EINVAL, prefix, forms[i],
                                  "give exactly one of preset, kernels, mirrored, tile, points");
            form = forms[i];
        }
    }
    if (!form)
        return proto_fail(err, AA_EINVAL, prefix, "",
                          "a pattern needs one of preset, kernels, mirrored, tile, points");
    const json_t *v = json_object_get(j, form);
    if (!strcmp(form, "preset")) {
        if (!json_is_string(v))
            return proto_fail(err, AA_EINVAL, prefix, "preset", "must be a preset name");
        const aa_preset *pr = aa_preset_find(json_string_value(v));
        if (!pr) {
            char field[PROTO_FIELD_MAX];
            proto_join_field(field, sizeof field, prefix, "preset");
            return proto_unknown_preset(err, field, json_string_value(v));
        }
        rc = aa_pattern_from_preset(out, pr, err);
        if (rc)
            proto_prefix_error(err, prefix);
        return rc;
    }
    if (!strcmp(form, "kernels"))
        return decode_kernels(v, flags, out, prefix, err);
    if (!strcmp(form, "mirrored"))
        return decode_mirrored(v, flags, out, prefix, err);
    if (!strcmp(form, "points"))
        return proto_decode_points_form(v, flags, weight_filter, out, prefix, err);
    return decode_tile(v, flags, out, prefix, err);
}

/* --- encoding ---------------------------------------------------------------------------- */

static json_t *encode_samples(const aa_sample *s, size_t n)
{
    assert(s || !n);
    json_t *a = json_array();
    for (size_t i = 0; a && i < n; i++)
        json_array_append_new(a, json_pack("[fff]", s[i].x, s[i].y, s[i].w));
    return a;
}

static json_t *encode_kernels(const aa_pattern *p)
{
    json_t *a = json_array();
    for (size_t k = 0; a && k < p->kernel_count; k++)
        json_array_append_new(a, encode_samples(p->kernels[k].samples, p->kernels[k].count));
    return a;
}

static json_t *encode_tile(const aa_pattern *p)
{
    json_t *samples = json_array(), *weights = json_array();
    for (size_t i = 0; i < p->tile_count; i++)
        json_array_append_new(samples,
                              json_pack("[ff]", p->tile_samples[i].x, p->tile_samples[i].y));
    for (size_t k = 0; k < p->kernel_count; k++) {
        json_t *w = json_array();
        for (size_t m = 0; m < p->kernels[k].count; m++)
            json_array_append_new(w, json_real(p->kernels[k].samples[m].w));
        json_array_append_new(weights, w);
    }
    return json_pack("{s:i,s:i,s:b,s:o,s:o}", "size", p->tile, "kernel", p->kernel_size, "border",
                     p->border, "samples", samples, "weights", weights);
}

static const char *form_name(aa_pattern_form f)
{
    return f == AA_FORM_MIRRORED ? "mirrored" : f == AA_FORM_TILE ? "tile" : "kernels";
}

json_t *proto_encode_pattern(const aa_pattern *p)
{
    /* A pattern from the engine's constructors (or the decoder): every count has its array, a
     * mirrored pattern keeps its source pixel and a tile pattern its tile. */
    assert(p);
    assert(p->kernels || !p->kernel_count);
    assert(p->form != AA_FORM_MIRRORED || p->source || !p->source_count);
    assert(p->form != AA_FORM_TILE ||
           (p->tile >= 1 && p->kernel_size >= 1 && (p->tile_samples || !p->tile_count)));
    json_t *o = json_pack("{s:s,s:o,s:s}", "family", p->family, "cost_spp", proto_real(p->cost_spp),
                          "form", form_name(p->form));
    if (!o)
        return NULL;
    json_t *kernels = encode_kernels(p);
    switch (p->form) {
    case AA_FORM_MIRRORED:
        json_object_set_new(o, "mirrored", encode_samples(p->source, p->source_count));
        json_object_set_new(o, "kernels_expanded", kernels);
        break;
    case AA_FORM_TILE:
        json_object_set_new(o, "tile", encode_tile(p));
        json_object_set_new(o, "kernels_expanded", kernels);
        break;
    default:
        json_object_set_new(o, "kernels", json_deep_copy(kernels));
        json_object_set_new(o, "kernels_expanded", kernels);
        break;
    }
    return o;
}
