/* POST /v1/analyze: point-set analysis of a pattern's tile (proto/codec_analyze.h -> engine
 * pattern/point_set.h -> encode). On the compute pool in the caller's evaluate share
 * (api_classify). Its work is bounded by the point count (at most 4,096, O(n^2) pair sums:
 * about 0.1 s for all metrics at 4,096 points; bench_analysis); "set": "all" by the points
 * over all sets (at most 65,536). */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "codec_analyze.h"
#include "handlers.h"

static int run_analysis(const proto_analyze_request *r, const aa_pattern *p, proto_analysis *a,
                        aa_error *err)
{
    memset(a, 0, sizeof *a);
    aa_point *pts;
    size_t n;
    int rc = aa_pattern_unit_points(p, &pts, &n, err);
    if (rc)
        return rc;
    a->points = n;
    rc = aa_point_set_check(pts, n, err);
    if (!rc && (r->metrics & PROTO_ANALYZE_DISCREPANCY))
        rc = aa_point_set_discrepancy(pts, n, &a->discrepancy, err);
    if (!rc && (r->metrics & PROTO_ANALYZE_STAR))
        rc = aa_point_set_star_discrepancy(pts, n, &a->star_discrepancy, err);
    if (!rc && (r->metrics & PROTO_ANALYZE_SPACING))
        rc = aa_point_set_spacing(pts, n, &a->spacing, err);
    if (!rc && (r->metrics & PROTO_ANALYZE_SPECTRUM))
        rc = aa_point_set_spectrum(pts, n, r->radius, &a->spectrum, err);
    if (!rc && (r->metrics & PROTO_ANALYZE_PCF)) {
        double packing = sqrt(2.0 / (sqrt(3.0) * (double)n));
        a->r_max = r->r_max > 0 ? r->r_max : fmin(0.5, 4 * packing);
        a->sigma = r->sigma > 0 ? r->sigma : packing / 8;
        a->pcf = malloc(r->bins * sizeof *a->pcf);
        rc = a->pcf ? aa_point_set_pcf(pts, n, a->r_max, r->bins, a->sigma, a->pcf, err)
                    : aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    free(pts);
    /* The engine names the point set "points": on the wire that is the pattern's tile. */
    if (rc && !strcmp(err->field, "points"))
        snprintf(err->field, sizeof err->field, "pattern");
    if (rc)
        proto_analysis_free(a);
    return rc;
}

/* "set": "all": each set analysed, then the means: the spectrum of the mean periodogram (as
 * pbrt's pspec), the mean PCF and the mean of every scalar figure. */
static int run_sets(const proto_analyze_request *r, proto_analysis *a, aa_error *err)
{
    memset(a, 0, sizeof *a);
    size_t m = r->set_count;
    a->per_set = calloc(m, sizeof *a->per_set);
    aa_spectrum *spectra = calloc(m, sizeof *spectra);
    int rc = a->per_set && spectra ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
    if (!rc)
        a->set_count = m;
    for (size_t i = 0; i < m && !rc; i++) {
        proto_analysis *s = &a->per_set[i];
        rc = run_analysis(r, i ? &r->more_sets[i - 1] : &r->pattern, s, err);
        if (rc) {
            aa_error e = *err;
            aa_error_set(err, e.code, e.field, "set %zu: %.170s", i, e.message);
            break;
        }
        double w = 1.0 / (double)m;
        a->points = s->points;
        a->r_max = s->r_max;
        a->sigma = s->sigma;
        aa_discrepancy *d = &a->discrepancy;
        const aa_discrepancy *e = &s->discrepancy;
        double *dd[] = {&d->l2_star,     &d->l2_star_sq,     &d->centered, &d->centered_sq,
                        &d->wrap_around, &d->wrap_around_sq, &d->mixture,  &d->mixture_sq};
        const double *ee[] = {&e->l2_star,     &e->l2_star_sq,     &e->centered, &e->centered_sq,
                              &e->wrap_around, &e->wrap_around_sq, &e->mixture,  &e->mixture_sq};
        for (size_t k = 0; k < sizeof dd / sizeof dd[0]; k++)
            *dd[k] += w * *ee[k];
        a->star_discrepancy += w * s->star_discrepancy;
        a->spacing.min_distance += w * s->spacing.min_distance;
        a->spacing.mean_nn_distance += w * s->spacing.mean_nn_distance;
        a->spacing.packing_distance += w * s->spacing.packing_distance;
        a->spacing.min_distance_normalized += w * s->spacing.min_distance_normalized;
        a->spacing.mean_nn_distance_normalized += w * s->spacing.mean_nn_distance_normalized;
        if (s->pcf && !a->pcf && !(a->pcf = calloc(r->bins, sizeof *a->pcf)))
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
        for (size_t b = 0; s->pcf && a->pcf && b < r->bins; b++)
            a->pcf[b] += w * s->pcf[b];
        spectra[i] = s->spectrum;
    }
    if (!rc && (r->metrics & PROTO_ANALYZE_SPECTRUM))
        rc = aa_spectrum_mean(spectra, m, a->points, &a->spectrum, err);
    free(spectra); /* borrowed from per_set */
    if (rc)
        proto_analysis_free(a);
    return rc;
}

void handle_analyze(api_context *ctx, const api_request *req, api_response *resp)
{
    aa_error err = {0};
    json_t *body = api_request_body(ctx, req, resp, &err, NULL);
    if (!body)
        return;
    proto_analyze_request r;
    proto_analysis a;
    int rc = err.code;
    if (!rc)
        rc = proto_decode_analyze_request(body, &r, &err);
    json_decref(body);
    bool decoded = rc == AA_OK;
    if (!rc)
        rc = r.set_count ? run_sets(&r, &a, &err) : run_analysis(&r, &r.pattern, &a, &err);
    if (rc) {
        api_reply_aa_error(resp, &err);
    } else {
        api_reply_json(resp, 200, proto_encode_analysis(&r, &a));
        proto_analysis_free(&a);
    }
    if (decoded)
        proto_analyze_request_free(&r);
}
