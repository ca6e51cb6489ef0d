/* The POST /v1/predict request and answer (codec_predict.h). */
#include "codec_predict.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "codec_temporal.h"
#include "job_temporal_render.h"

static const char *const predict_keys[] = {
    "scene", "size", "pattern", "patterns", "reference", "e1_by_angle", "model", "phase", NULL};

static const struct {
    const char *name;
    unsigned flags;
} MODELS[] = {
    {"edge", 0},
    {"reference-profile", AA_PREDICT_REFERENCE_PROFILE},
    {"exact", AA_PREDICT_EXACT_REFERENCE},
};

const char *proto_predict_model_name(unsigned model)
{
    for (size_t i = 0; i < sizeof MODELS / sizeof MODELS[0]; i++)
        if (MODELS[i].flags == model)
            return MODELS[i].name;
    return NULL;
}

static int decode_model(const json_t *v, unsigned *out, aa_error *err)
{
    *out = 0;
    if (!v)
        return AA_OK;
    for (size_t i = 0; json_is_string(v) && i < sizeof MODELS / sizeof MODELS[0]; i++)
        if (!strcmp(json_string_value(v), MODELS[i].name)) {
            *out = MODELS[i].flags;
            return AA_OK;
        }
    return aa_error_set(err, AA_EINVAL, "model",
                        "model must be \"edge\", \"reference-profile\" or \"exact\"");
}

void proto_predict_request_free(proto_predict_request *r)
{
    for (size_t i = 0; r->patterns && i < r->pattern_count; i++)
        aa_pattern_free(&r->patterns[i]);
    free(r->patterns);
    free(r->names);
    free(r->source);
    free(r->phase);
    free(r->phase_count);
    r->patterns = NULL;
    r->names = NULL;
    r->source = NULL;
    r->phase = NULL;
    r->phase_count = NULL;
    r->pattern_count = 0;
}

void proto_predict_pattern_field(const proto_predict_request *r, size_t i, char *out, size_t cap)
{
    if (r->single)
        snprintf(out, cap, "pattern");
    else
        snprintf(out, cap, "patterns[%zu]", r->source ? r->source[i] : i);
}

/* Room for n more patterns. */
static int grow(proto_predict_request *out, size_t *cap, size_t n, aa_error *err)
{
    if (out->pattern_count + n <= *cap)
        return AA_OK;
    size_t c = (out->pattern_count + n) * 2;
    aa_pattern *p = realloc(out->patterns, c * sizeof *p);
    if (p)
        out->patterns = p;
    char(*names)[64] = p ? realloc(out->names, c * sizeof *names) : NULL;
    if (names)
        out->names = names;
    size_t *source = names ? realloc(out->source, c * sizeof *source) : NULL;
    if (source)
        out->source = source;
    long *phase = source ? realloc(out->phase, c * sizeof *phase) : NULL;
    if (phase)
        out->phase = phase;
    size_t *count = phase ? realloc(out->phase_count, c * sizeof *count) : NULL;
    if (!count)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    out->phase_count = count;
    *cap = c;
    return AA_OK;
}

/* A temporal pattern: one pattern per phase. samples: the phase patterns' kernel samples so
 * far over the request, bounded before anything is built. */
static int decode_temporal(const json_t *pj, size_t index, const char *field,
                           proto_predict_request *out, size_t *cap, double *samples, aa_error *err)
{
    proto_temporal spec;
    int rc = proto_decode_temporal(pj, &spec, field, err);
    if (rc)
        return rc;
    char tf[64];
    snprintf(tf, sizeof tf, "%s.temporal", field);
    double planned = proto_temporal_planned_samples(&spec) * (double)spec.count;
    *samples += planned;
    if (*samples > (double)PROTO_PREDICT_MAX_PHASE_SAMPLES) {
        proto_temporal_free(&spec);
        return aa_error_set(err, AA_ERANGE, tf,
                            "%.0f phase kernel samples is more than a prediction does (%ld); "
                            "send fewer phases or frame samples",
                            *samples, PROTO_PREDICT_MAX_PHASE_SAMPLES);
    }
    aa_temporal t = {0};
    rc = proto_temporal_build(&spec, tf, &t, err);
    if (!rc)
        rc = grow(out, cap, t.phase_count, err);
    for (size_t p = 0; !rc && p < t.phase_count; p++) {
        size_t i = out->pattern_count;
        rc = aa_taa_phase_pattern(&t, p, &out->patterns[i], err);
        if (rc) {
            /* More than AA_MAX_KERNEL_SAMPLES per output pixel over the frames. */
            char f[sizeof err->field];
            proto_join_field(f, sizeof f, tf, "jitter");
            memcpy(err->field, f, sizeof f);
            break;
        }
        snprintf(out->names[i], sizeof out->names[i], "%s", spec.preset ? spec.preset : "");
        out->source[i] = index;
        out->phase[i] = (long)p;
        out->phase_count[i] = t.phase_count;
        out->pattern_count = i + 1;
    }
    aa_temporal_free(&t);
    proto_temporal_free(&spec);
    return rc;
}

static int decode_patterns(const json_t *body, proto_predict_request *out, aa_error *err)
{
    json_t *one = json_object_get(body, "pattern"), *many = json_object_get(body, "patterns");
    if (one && many)
        return aa_error_set(err, AA_EINVAL, "patterns", "give either pattern or patterns");
    if (!one && !many)
        return aa_error_set(err, AA_EINVAL, "pattern", "a pattern (or patterns) is required");
    size_t n = 1;
    if (many) {
        if (!json_is_array(many) || json_array_size(many) == 0)
            return aa_error_set(err, AA_EINVAL, "patterns",
                                "patterns must be a non-empty array of patterns");
        n = json_array_size(many);
        if (n > PROTO_PREDICT_MAX_PATTERNS)
            return aa_error_set(err, AA_ERANGE, "patterns", "at most %d patterns per request",
                                PROTO_PREDICT_MAX_PATTERNS);
    }
    out->single = one != NULL;
    size_t cap = 0;
    double samples = 0;
    for (size_t j = 0; j < n; j++) {
        const json_t *pj = one ? one : json_array_get(many, j);
        char field[32];
        if (one)
            snprintf(field, sizeof field, "pattern");
        else
            snprintf(field, sizeof field, "patterns[%zu]", j);
        int rc;
        if (json_is_object(pj) && json_object_get(pj, "temporal")) {
            rc = decode_temporal(pj, j, field, out, &cap, &samples, err);
            if (rc)
                return rc;
            continue;
        }
        rc = grow(out, &cap, 1, err);
        if (rc)
            return rc;
        size_t i = out->pattern_count;
        rc = proto_decode_pattern_or_name(pj, 0, &out->patterns[i], field, err);
        if (rc)
            return rc;
        out->names[i][0] = 0;
        out->source[i] = j;
        out->phase[i] = -1;
        out->phase_count[i] = 0;
        out->pattern_count = i + 1;
        const json_t *name = json_is_object(pj) ? json_object_get(pj, "preset") : pj;
        if (json_is_string(name))
            snprintf(out->names[i], sizeof out->names[i], "%s", json_string_value(name));
    }
    return AA_OK;
}

/* "phase" (as in POST /v1/render): only that phase of the one temporal "pattern". */
static int keep_phase(const json_t *ph, proto_predict_request *out, aa_error *err)
{
    if (!ph)
        return AA_OK;
    size_t n = out->pattern_count;
    if (!out->single || out->phase[0] < 0)
        return aa_error_set(err, AA_EINVAL, "phase",
                            "phase is for one temporal pattern (\"pattern\") only");
    if (!json_is_integer(ph) || json_integer_value(ph) < 0 ||
        json_integer_value(ph) >= (json_int_t)n)
        return aa_error_set(err, AA_EINVAL, "phase", "phase must be an integer in [0, %zu]", n - 1);
    size_t keep = (size_t)json_integer_value(ph);
    for (size_t i = 0; i < n; i++)
        if (i != keep)
            aa_pattern_free(&out->patterns[i]);
    out->patterns[0] = out->patterns[keep];
    memcpy(out->names[0], out->names[keep], sizeof out->names[0]);
    out->source[0] = out->source[keep];
    out->phase[0] = out->phase[keep];
    out->phase_count[0] = out->phase_count[keep];
    out->pattern_count = 1;
    return AA_OK;
}

int proto_decode_predict_request(const json_t *body, proto_predict_request *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    if (!json_is_object(body))
        return aa_error_set(err, AA_EINVAL, "", "body must be a JSON object");
    int rc = proto_check_keys(body, predict_keys, err, "");
    if (!rc)
        rc = proto_decode_scene_request(body, &out->scene, err);
    if (!rc)
        rc = decode_patterns(body, out, err);
    if (!rc)
        rc = keep_phase(json_object_get(body, "phase"), out, err);
    if (!rc)
        rc = proto_decode_reference(json_object_get(body, "reference"), &out->reference,
                                    "reference", err);
    const json_t *by_angle = json_object_get(body, "e1_by_angle");
    if (!rc && by_angle && !json_is_boolean(by_angle))
        rc = aa_error_set(err, AA_EINVAL, "e1_by_angle", "must be true or false");
    out->e1_by_angle = json_is_true(by_angle);
    if (!rc)
        rc = decode_model(json_object_get(body, "model"), &out->model, err);
    if (rc)
        proto_predict_request_free(out);
    return rc;
}

/* The bin's whole length: binned plus locked edges on it. */
static double bin_length(const aa_edge_histogram *h, int d)
{
    double l = h->length[d];
    for (size_t k = 0; k < h->locked_count; k++)
        if (aa_locked_edge_bin(&h->locked[k]) == d)
            l += h->locked[k].length;
    return l;
}

static double locked_length(const aa_edge_histogram *h)
{
    double l = 0;
    for (size_t k = 0; k < h->locked_count; k++)
        l += h->locked[k].length;
    return l;
}

static json_t *encode_edges(const aa_edge_histogram *h)
{
    json_t *len = json_array();
    for (int d = 0; len && d < AA_EDGE_BINS; d++)
        if (json_array_append_new(len, json_real(bin_length(h, d))))
            return json_decref(len), NULL;
    if (!len)
        return NULL;
    double pixels = (double)h->width * (double)h->height;
    return json_pack("{s:s, s:o, s:f, s:f, s:I, s:f, s:f}", "angle_convention",
                     "normal angle in degrees, pixel coordinates (x right, y down), modulo 180; "
                     "bin d holds [d-0.5, d+0.5)",
                     "length", len, "total_length", h->total, "locked_length", locked_length(h),
                     "locked_edges", (json_int_t)h->locked_count, "locked_excess_length",
                     h->locked_excess, "subpixel_area_share", h->subpixel_area / pixels);
}

typedef struct bin_part {
    int d;
    double sq;
} bin_part;

static int by_share_desc(const void *a, const void *b)
{
    const bin_part *x = a, *y = b;
    if (x->sq != y->sq)
        return x->sq < y->sq ? 1 : -1;
    return x->d - y->d;
}

static json_t *encode_angles(const aa_edge_histogram *h, const aa_prediction *p)
{
    bin_part parts[AA_EDGE_BINS];
    size_t n = 0;
    for (int d = 0; d < AA_EDGE_BINS; d++)
        if (bin_length(h, d) > 0)
            parts[n++] = (bin_part){d, p->bin_sq[d]};
    qsort(parts, n, sizeof parts[0], by_share_desc);
    json_t *a = json_array();
    for (size_t i = 0; a && i < n; i++) {
        int d = parts[i].d;
        json_t *o = json_pack("{s:I, s:f, s:f, s:o}", "angle", (json_int_t)d, "length",
                              bin_length(h, d), "e1_rms", p->e1_rms[d], "share",
                              proto_real(p->sum_sq > 0 ? parts[i].sq / p->sum_sq : 0.0));
        if (!o || json_array_append_new(a, o))
            return json_decref(a), NULL;
    }
    return a;
}

static json_t *encode_bins(const double v[AA_EDGE_BINS])
{
    json_t *a = json_array();
    for (int d = 0; a && d < AA_EDGE_BINS; d++)
        if (json_array_append_new(a, json_real(v[d])))
            return json_decref(a), NULL;
    return a;
}

json_t *proto_encode_predictions(const proto_predict_request *r, const aa_edge_histogram *h,
                                 const aa_prediction *pred,
                                 const double (*e1_by_angle)[AA_EDGE_BINS])
{
    json_t *list = json_array();
    for (size_t i = 0; list && i < r->pattern_count; i++) {
        const aa_pattern *p = &r->patterns[i];
        const aa_prediction *q = &pred[i];
        json_t *o = json_pack("{s:{s:s, s:s, s:f, s:I}, s:f, s:f, s:o, s:f, s:b, s:o}", "pattern",
                              "name", r->names[i], "family", p->family, "samples_per_pixel",
                              p->cost_spp, "kernels", (json_int_t)p->kernel_count, "predicted_rmse",
                              q->rmse, "sum_squared_error", q->sum_sq, "locked_share",
                              proto_real(q->sum_sq > 0 ? q->locked_sq / q->sum_sq : 0.0),
                              "subpixel_area_share", q->subpixel_area_share,
                              "subpixel_error_estimated", false, "angles", encode_angles(h, q));
        if (o && r->phase && r->phase[i] >= 0 &&
            json_object_set_new(o, "temporal",
                                json_pack("{s:I, s:I, s:I}", "index", (json_int_t)r->source[i],
                                          "phase", (json_int_t)r->phase[i], "phase_count",
                                          (json_int_t)r->phase_count[i])))
            o = (json_decref(o), NULL);
        if (o && e1_by_angle && json_object_set_new(o, "e1_by_angle", encode_bins(e1_by_angle[i])))
            o = (json_decref(o), NULL);
        if (!o || json_array_append_new(list, o))
            return json_decref(list), NULL;
    }
    if (!list)
        return NULL;
    const aa_filter *f = r->reference.params.filter;
    const char *model = proto_predict_model_name(r->model);
    return json_pack("{s:o, s:{s:s}, s:s, s:o, s:o}", "scene", proto_encode_scene(&r->scene),
                     "reference", "filter", f ? f->name : "mitchell", "model",
                     model ? model : "edge", "edges", encode_edges(h), "predictions", list);
}
