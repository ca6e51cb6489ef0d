/* POST /v1/analyze: decoding the request and encoding the figures (codec_analyze.h). */
#include "codec_analyze.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "codec_internal.h"
#include "codec_temporal.h"

static const char *const metric_names[] = {"discrepancy", "star_discrepancy", "spacing", "spectrum",
                                           "pcf"};
#define METRIC_COUNT (sizeof metric_names / sizeof metric_names[0])

static int decode_metrics(const json_t *j, unsigned *out, aa_error *err)
{
    if (!j) {
        *out = PROTO_ANALYZE_ALL;
        return AA_OK;
    }
    if (!json_is_array(j) || !json_array_size(j))
        return aa_error_set(err, AA_EINVAL, "metrics", "must be a non-empty array of names");
    *out = 0;
    size_t i;
    json_t *v;
    json_array_foreach(j, i, v)
    {
        const char *name = json_string_value(v);
        size_t m = 0;
        while (name && m < METRIC_COUNT && strcmp(name, metric_names[m]))
            m++;
        if (!name || m == METRIC_COUNT) {
            char field[32];
            snprintf(field, sizeof field, "metrics[%zu]", i);
            return aa_error_set(err, AA_EINVAL, field,
                                "must be discrepancy, star_discrepancy, spacing, spectrum or pcf");
        }
        *out |= 1u << m;
    }
    return AA_OK;
}

/* A number in (lo, hi] (or [lo, hi] when lo_closed) from an optional key. */
static int decode_real(const json_t *obj, const char *key, const char *field, double lo, double hi,
                       double *out, aa_error *err)
{
    json_t *v = json_object_get(obj, key);
    if (!v)
        return AA_OK;
    double x = json_number_value(v);
    if (!json_is_number(v) || !(x > lo && x <= hi))
        return aa_error_set(err, AA_EINVAL, field, "must be a number in (%g, %g]", lo, hi);
    *out = x;
    return AA_OK;
}

static int decode_int(const json_t *obj, const char *key, const char *field, long lo, long hi,
                      long *out, aa_error *err)
{
    json_t *v = json_object_get(obj, key);
    if (!v)
        return AA_OK;
    if (!json_is_integer(v) || json_integer_value(v) < lo || json_integer_value(v) > hi)
        return aa_error_set(err, AA_EINVAL, field, "must be an integer from %ld to %ld", lo, hi);
    *out = (long)json_integer_value(v);
    return AA_OK;
}

/* "set": "all": every set of the points form's file as its own pattern (set i decoded as
 * "set": i), all of one point count so that their periodograms average. */
static int decode_all_sets(const json_t *pat, const aa_filter *filter, proto_analyze_request *out,
                           aa_error *err)
{
    size_t m = 0;
    int rc = proto_points_form_set_count(json_object_get(pat, "points"), &m, "pattern", err);
    if (rc)
        return rc;
    if (m == 0)
        return aa_error_set(err, AA_EINVAL, "pattern.points.set",
                            "the file holds no set of points");
    if (m > PROTO_ANALYZE_MAX_SETS)
        return aa_error_set(err, AA_ERANGE, "pattern.points.set",
                            "the file holds %zu sets; \"all\" analyses at most %d", m,
                            PROTO_ANALYZE_MAX_SETS);
    out->more_sets = m > 1 ? calloc(m - 1, sizeof *out->more_sets) : NULL;
    if (m > 1 && !out->more_sets)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    json_t *copy = json_deep_copy(pat);
    if (!copy)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    size_t total = 0;
    for (size_t i = 0; i < m && !rc; i++) {
        json_object_set_new(json_object_get(copy, "points"), "set", json_integer((json_int_t)i));
        aa_pattern *p = i ? &out->more_sets[i - 1] : &out->pattern;
        rc = proto_decode_pattern_filtered(copy, 0, filter, p, "pattern", err);
        if (rc)
            break;
        out->set_count = i + 1; /* decoded so far: freed on error */
        total += p->tile_count;
        if (p->tile_count != out->pattern.tile_count)
            rc = aa_error_set(err, AA_EINVAL, "pattern.points.set",
                              "set %zu has %zu points but set 0 has %zu; \"all\" averages the "
                              "spectra of sets of one size",
                              i, p->tile_count, out->pattern.tile_count);
        else if (total > PROTO_ANALYZE_MAX_SET_POINTS)
            rc = aa_error_set(err, AA_ERANGE, "pattern.points.set",
                              "more than %d points over the sets", PROTO_ANALYZE_MAX_SET_POINTS);
    }
    json_decref(copy);
    if (!out->set_count)
        out->set_count = 1; /* set 0 failed: nothing decoded, the free loop must not run */
    return rc;
}

/* A temporal pattern as a point set: every frame's samples shifted by its jitter offset, over
 * the N frames of a period, on the frame pattern's tile (one pixel by default) as the torus:
 * the positions a static pixel accumulates in its history, whatever their blend weights (which
 * the point-set figures do not read). Offsets are in pixels, so on a tile of T pixels a shift
 * is o / T of the torus; positions outside the tile wrap (the pixel grid repeats). Built as a
 * tile pattern of kernel size 1 so the rest of the analysis is the spatial one. */
static int decode_temporal_points(const json_t *pat, const aa_filter *filter, aa_pattern *out,
                                  aa_error *err)
{
    proto_temporal t;
    int rc = proto_decode_temporal(pat, &t, "pattern", err);
    if (rc)
        return rc;
    aa_point *frame = NULL, *pts = NULL;
    size_t per_frame = 1;
    int tile = 1;
    if (t.has_frame) {
        rc = aa_pattern_unit_points(&t.frame, &frame, &per_frame, err);
        if (rc)
            snprintf(err->field, sizeof err->field, "pattern.temporal.frame_pattern");
        tile = t.frame.tile;
    }
    size_t n = t.count * per_frame;
    if (!rc && (per_frame > AA_POINT_SET_MAX || n > AA_POINT_SET_MAX))
        rc = aa_error_set(err, AA_ERANGE, "pattern.temporal",
                          "%zu frames of %zu samples: the analysis takes at most %d points",
                          t.count, per_frame, AA_POINT_SET_MAX);
    if (!rc && !(pts = malloc(n * sizeof *pts)))
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t f = 0; !rc && f < t.count; f++)
        for (size_t i = 0; i < per_frame; i++) {
            double u = frame ? frame[i].x : 0.5, v = frame ? frame[i].y : 0.5;
            u += t.jitter[f].x / tile;
            v += t.jitter[f].y / tile;
            pts[f * per_frame + i] = (aa_point){(u - floor(u)) * tile, (v - floor(v)) * tile};
        }
    if (!rc) {
        aa_tile_spec spec = {
            .tile = tile, .kernel_size = 1, .count = n, .samples = pts, .weight_filter = filter};
        rc = aa_pattern_from_tile(out, &spec, 0, err);
        if (rc)
            snprintf(err->field, sizeof err->field, "pattern.temporal");
    }
    free(pts);
    free(frame);
    proto_temporal_free(&t);
    return rc;
}

int proto_decode_analyze_request(const json_t *body, proto_analyze_request *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    static const char *const keys[] = {"pattern", "metrics", "spectrum", "pcf", NULL};
    static const char *const spectrum_keys[] = {"radius", NULL};
    static const char *const pcf_keys[] = {"bins", "r_max", "sigma", NULL};
    int rc = proto_check_keys(body, keys, err, "");
    json_t *sj = json_object_get(body, "spectrum"), *pj = json_object_get(body, "pcf");
    if (!rc && sj && !json_is_object(sj))
        rc = aa_error_set(err, AA_EINVAL, "spectrum", "must be an object");
    if (!rc && pj && !json_is_object(pj))
        rc = aa_error_set(err, AA_EINVAL, "pcf", "must be an object");
    if (!rc && sj)
        rc = proto_check_keys(sj, spectrum_keys, err, "spectrum");
    if (!rc && pj)
        rc = proto_check_keys(pj, pcf_keys, err, "pcf");
    if (!rc)
        rc = decode_metrics(json_object_get(body, "metrics"), &out->metrics, err);
    long radius = 32, bins = 64;
    if (!rc && sj)
        rc = decode_int(sj, "radius", "spectrum.radius", 1, PROTO_ANALYZE_MAX_RADIUS, &radius, err);
    if (!rc && pj)
        rc = decode_int(pj, "bins", "pcf.bins", 1, PROTO_ANALYZE_MAX_BINS, &bins, err);
    if (!rc && pj)
        rc = decode_real(pj, "r_max", "pcf.r_max", 0, 0.5, &out->r_max, err);
    if (!rc && pj)
        rc = decode_real(pj, "sigma", "pcf.sigma", 0, 0.5, &out->sigma, err);
    out->radius = (int)radius;
    out->bins = (size_t)bins;
    json_t *pat = json_object_get(body, "pattern");
    if (!rc && !pat)
        rc = aa_error_set(err, AA_EINVAL, "pattern", "pattern is required");
    aa_filter filter; /* the default: a "points" pattern takes its weights from it */
    if (!rc)
        rc = proto_decode_filter(NULL, &filter, "filter", err);
    const json_t *form = json_is_object(pat) ? json_object_get(pat, "points") : NULL;
    const json_t *set = json_is_object(form) ? json_object_get(form, "set") : NULL;
    if (!rc && json_is_string(set) && !strcmp(json_string_value(set), "all"))
        rc = decode_all_sets(pat, &filter, out, err);
    else if (!rc && json_is_object(pat) && json_object_get(pat, "temporal"))
        rc = decode_temporal_points(pat, &filter, &out->pattern, err);
    else if (!rc)
        rc = proto_decode_pattern_filtered(pat, 0, &filter, &out->pattern, "pattern", err);
    if (rc)
        proto_analyze_request_free(out);
    return rc;
}

void proto_analyze_request_free(proto_analyze_request *r)
{
    aa_pattern_free(&r->pattern);
    for (size_t i = 0; i + 1 < r->set_count && r->more_sets; i++)
        aa_pattern_free(&r->more_sets[i]);
    free(r->more_sets);
    r->more_sets = NULL;
    r->set_count = 0;
}

void proto_analysis_free(proto_analysis *a)
{
    aa_spectrum_free(&a->spectrum);
    free(a->pcf);
    a->pcf = NULL;
    for (size_t i = 0; a->per_set && i < a->set_count; i++)
        proto_analysis_free(&a->per_set[i]);
    free(a->per_set);
    a->per_set = NULL;
}

/* arrays false: the figures alone (a set of several). */
static json_t *encode_spectrum(const aa_spectrum *s, size_t points, bool arrays)
{
    double unit = sqrt((double)points);
    json_t *o =
        json_pack("{s:I, s:o, s:o, s:o, s:o}", "radius", (json_int_t)s->radius, "effective_nyquist",
                  proto_real(s->effective_nyquist), "effective_nyquist_normalized",
                  proto_real(s->effective_nyquist / unit), "oscillation",
                  proto_real(s->oscillation), "frequency_unit", json_real(unit));
    if (!o || !arrays)
        return o;
    json_t *rows = json_array();
    for (size_t r = 0; rows && r < s->side; r++)
        if (json_array_append_new(rows, proto_real_array(s->power + r * s->side, s->side))) {
            json_decref(rows);
            rows = NULL;
        }
    json_t *counts = json_array();
    for (int b = 0; counts && b <= s->radius; b++)
        json_array_append_new(counts, json_integer((json_int_t)s->annulus_count[b]));
    json_t *radial = proto_real_array(s->radial, (size_t)s->radius + 1);
    json_t *aniso = proto_real_array(s->anisotropy_db, (size_t)s->radius + 1);
    if (!rows || !counts || !radial || !aniso) {
        json_decref(rows);
        json_decref(counts);
        json_decref(radial);
        json_decref(aniso);
        json_decref(o);
        return NULL;
    }
    json_object_set_new(o, "power", rows);
    json_object_set_new(o, "radial", radial);
    json_object_set_new(o, "anisotropy_db", aniso);
    json_object_set_new(o, "annulus_count", counts);
    return o;
}

/* arrays false: a set of several, its figures without the spectrum's arrays and the PCF. */
static json_t *encode_figures(const proto_analyze_request *r, const aa_pattern *p,
                              const proto_analysis *a, bool arrays)
{
    json_t *o = json_pack("{s:I, s:i, s:s}", "points", (json_int_t)a->points, "tile", p->tile,
                          "family", p->family);
    if (!o)
        return NULL;
    if (r->metrics & (PROTO_ANALYZE_DISCREPANCY | PROTO_ANALYZE_STAR)) {
        const aa_discrepancy *d = &a->discrepancy;
        json_t *dj = json_object();
        if (r->metrics & PROTO_ANALYZE_DISCREPANCY) {
            json_object_set_new(dj, "l2_star", proto_real(d->l2_star));
            json_object_set_new(dj, "l2_star_squared", proto_real(d->l2_star_sq));
            json_object_set_new(dj, "centered", proto_real(d->centered));
            json_object_set_new(dj, "centered_squared", proto_real(d->centered_sq));
            json_object_set_new(dj, "wrap_around", proto_real(d->wrap_around));
            json_object_set_new(dj, "wrap_around_squared", proto_real(d->wrap_around_sq));
            json_object_set_new(dj, "mixture", proto_real(d->mixture));
            json_object_set_new(dj, "mixture_squared", proto_real(d->mixture_sq));
        }
        if (r->metrics & PROTO_ANALYZE_STAR)
            json_object_set_new(dj, "star_linf", proto_real(a->star_discrepancy));
        json_object_set_new(o, "discrepancy", dj);
    }
    if (r->metrics & PROTO_ANALYZE_SPACING) {
        const aa_spacing *s = &a->spacing;
        json_object_set_new(
            o, "spacing",
            json_pack("{s:o, s:o, s:o, s:o, s:o}", "min_distance", proto_real(s->min_distance),
                      "mean_nn_distance", proto_real(s->mean_nn_distance), "packing_distance",
                      proto_real(s->packing_distance), "min_distance_normalized",
                      proto_real(s->min_distance_normalized), "mean_nn_distance_normalized",
                      proto_real(s->mean_nn_distance_normalized)));
    }
    if (r->metrics & PROTO_ANALYZE_SPECTRUM)
        json_object_set_new(o, "spectrum", encode_spectrum(&a->spectrum, a->points, arrays));
    if ((r->metrics & PROTO_ANALYZE_PCF) && arrays) {
        double *rr = malloc(r->bins * sizeof *rr);
        for (size_t b = 0; rr && b < r->bins; b++)
            rr[b] = ((double)b + 0.5) * a->r_max / (double)r->bins;
        json_object_set_new(o, "pcf",
                            json_pack("{s:f, s:f, s:o*, s:o*}", "r_max", a->r_max, "sigma",
                                      a->sigma, "r", rr ? proto_real_array(rr, r->bins) : NULL, "g",
                                      proto_real_array(a->pcf, r->bins)));
        free(rr);
    }
    return o;
}

json_t *proto_encode_analysis(const proto_analyze_request *r, const proto_analysis *a)
{
    json_t *o = encode_figures(r, &r->pattern, a, true);
    if (!o || !a->set_count)
        return o;
    /* "set": "all": the figures above are the means; each set's own follow. */
    json_t *per = json_array();
    for (size_t i = 0; per && i < a->set_count; i++) {
        const aa_pattern *p = i ? &r->more_sets[i - 1] : &r->pattern;
        if (json_array_append_new(per, encode_figures(r, p, &a->per_set[i], false))) {
            json_decref(per);
            per = NULL;
        }
    }
    if (!per || json_object_set_new(
                    o, "sets",
                    json_pack("{s:I, s:o}", "count", (json_int_t)a->set_count, "per_set", per))) {
        json_decref(o);
        return NULL;
    }
    return o;
}
