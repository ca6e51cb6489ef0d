/* The periodogram of a point set on the unit torus at integer frequencies, its radial average
 * and anisotropy (Schlömer & Deussen, "Accurate spectral analysis of two-dimensional point
 * sets", JGT 2011: PSA), and the effective Nyquist frequency and oscillation figures after
 * Heck, Schlömer & Deussen, "Blue noise sampling with controlled aliasing", TOG 2013, computed
 * here from the periodogram's annuli (docs/analysis.md states how they differ from PSA's).
 * The sum over points is one pass per point over the half-plane kx >= 0 (P(-k) = P(k)), from
 * cos/sin tables of the point's two coordinates (trig_table: each entry within 16 eps). */
#include "point_set.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#define TWO_PI 6.28318530717958647692
#define PI_D 3.14159265358979323846

/* c[k] = cos(2 pi k x), s[k] = sin(2 pi k x) for k = 0..radius: exact sin/cos of the reduced
 * argument every ANCHOR steps, the angle-addition recurrence between (its rounding grows by
 * about 2 eps a step, so at most 2 ANCHOR eps), which saves most of the libm calls. */
#define ANCHOR 8

static void trig_table(double x, int radius, double *c, double *s)
{
    double t1 = x - floor(x), c1 = cos(TWO_PI * t1), s1 = sin(TWO_PI * t1);
    for (int k = 0; k <= radius; k++) {
        if (k % ANCHOR == 0) {
            double t = (double)k * x;
            t -= floor(t);
            c[k] = cos(TWO_PI * t);
            s[k] = sin(TWO_PI * t);
        } else {
            c[k] = c[k - 1] * c1 - s[k - 1] * s1;
            s[k] = s[k - 1] * c1 + c[k - 1] * s1;
        }
    }
}

void aa_spectrum_free(aa_spectrum *s)
{
    if (!s)
        return;
    free(s->power);
    free(s->radial);
    free(s->anisotropy_db);
    free(s->annulus_count);
    memset(s, 0, sizeof *s);
}

/* The half-plane sums: re/im[(kx) * side + (ky + R)] for kx = 0..R. Per point, the y table is
 * laid out over ky = -R..R (cos even, sin odd), so each kx row is one contiguous loop that the
 * compiler vectorises. */
static void half_plane_sums(const aa_point *pts, size_t n, int R, double *re, double *im,
                            double *cx, double *sx, double *cy, double *sy)
{
    size_t side = (size_t)(2 * R + 1);
    double *cyf = cy + R, *syf = sy + R; /* [-R, R] */
    for (size_t j = 0; j < n; j++) {
        trig_table(pts[j].x, R, cx, sx);
        trig_table(pts[j].y, R, cyf, syf);
        for (int k = 1; k <= R; k++) {
            cyf[-k] = cyf[k];
            syf[-k] = -syf[k];
        }
        /* e^{-i(a+b)} = (ca cb - sa sb) - i (sa cb + ca sb) */
        for (int kx = 0; kx <= R; kx++) {
            double ca = cx[kx], sa = sx[kx];
            double *restrict r = re + (size_t)kx * side, *restrict m = im + (size_t)kx * side;
            const double *restrict c = cy, *restrict s = sy;
            for (size_t i = 0; i < side; i++) {
                r[i] += ca * c[i] - sa * s[i];
                m[i] -= sa * c[i] + ca * s[i];
            }
        }
    }
}

static void radial_figures(aa_spectrum *s, size_t n)
{
    int R = s->radius;
    double *sum = calloc((size_t)R + 1, sizeof *sum), *sumsq = calloc((size_t)R + 1, sizeof *sumsq);
    if (!sum || !sumsq) {
        free(sum);
        free(sumsq);
        return;
    }
    for (int ky = -R; ky <= R; ky++) {
        for (int kx = -R; kx <= R; kx++) {
            double r = sqrt((double)kx * kx + (double)ky * ky);
            long b = lround(r);
            if (b > R)
                continue;
            double p = s->power[(size_t)(ky + R) * s->side + (size_t)(kx + R)];
            sum[b] += p;
            sumsq[b] += p * p;
            s->annulus_count[b]++;
        }
    }
    for (int b = 0; b <= R; b++) {
        double c = (double)s->annulus_count[b], mean = sum[b] / c;
        s->radial[b] = mean;
        double var = c > 1 ? (sumsq[b] - c * mean * mean) / (c - 1) : NAN;
        /* Below the periodogram's rounding (about 32 n eps) the power is zero and its
         * variance is noise: no anisotropy. */
        bool zero = mean <= 64 * (double)n * 0x1.0p-52;
        s->anisotropy_db[b] = c > 1 && !zero && var > 0 ? 10 * log10(var / (mean * mean))
                              : c > 1 && !zero          ? -INFINITY
                                                        : NAN;
    }
    /* Effective Nyquist: the mean power over the disc 0 < |k| <= b stays below 0.1. */
    double disc = 0, count = 0;
    s->effective_nyquist = 0;
    for (int b = 1; b <= R; b++) {
        disc += sum[b];
        count += (double)s->annulus_count[b];
        if (disc / count >= 0.1)
            break;
        s->effective_nyquist = b;
    }
    /* Oscillation: from where the radial power first reaches 0.98 (its running maximum
     * then
     * PSA's lowest frequency with P ~ 1), over 10 peaks' width sqrt(n)/2 each. */
    int x0 = 0;
    double running = 0;
    for (int b = 1; b <= R && running < 0.98; b++) {
        if (s->radial[b] > running) {
            running = s->radial[b];
            x0 = b;
        }
    }
    double x1 = fmin((double)x0 + 10 * sqrt((double)n) / 2, (double)R);
    double acc = 0;
    for (int b = x0; b <= (int)x1; b++) {
        double d = s->radial[b] - 1;
        acc += d * d * (double)b;
    }
    s->oscillation =
        x0 > 0 && x1 > x0 ? 10 * sqrt(TWO_PI * acc / (PI_D * (x1 * x1 - (double)x0 * x0))) : NAN;
    free(sum);
    free(sumsq);
}

int aa_point_set_spectrum(const aa_point *pts, size_t n, int radius, aa_spectrum *out,
                          aa_error *err)
{
    memset(out, 0, sizeof *out);
    int rc = aa_point_set_check(pts, n, err);
    if (rc)
        return rc;
    if (radius < 1 || radius > AA_SPECTRUM_MAX_RADIUS)
        return aa_error_set(err, AA_EINVAL, "radius", "must be 1 to %d", AA_SPECTRUM_MAX_RADIUS);
    int R = radius;
    size_t side = (size_t)(2 * R + 1), half = (size_t)(R + 1) * side;
    double *re = calloc(half, sizeof *re), *im = calloc(half, sizeof *im);
    double *tab = malloc((2 * (size_t)(R + 1) + 2 * side) * sizeof *tab);
    out->radius = R;
    out->side = side;
    out->power = malloc(side * side * sizeof *out->power);
    out->radial = malloc((size_t)(R + 1) * sizeof *out->radial);
    out->anisotropy_db = malloc((size_t)(R + 1) * sizeof *out->anisotropy_db);
    out->annulus_count = calloc((size_t)R + 1, sizeof *out->annulus_count);
    if (!re || !im || !tab || !out->power || !out->radial || !out->anisotropy_db ||
        !out->annulus_count) {
        free(re);
        free(im);
        free(tab);
        aa_spectrum_free(out);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    size_t r1 = (size_t)R + 1;
    half_plane_sums(pts, n, R, re, im, tab, tab + r1, tab + 2 * r1, tab + 2 * r1 + side);
    double inv_n = 1.0 / (double)n;
    for (int kx = 0; kx <= R; kx++) {
        for (int ky = -R; ky <= R; ky++) {
            size_t h = (size_t)kx * side + (size_t)(ky + R);
            double p = (re[h] * re[h] + im[h] * im[h]) * inv_n;
            out->power[(size_t)(ky + R) * side + (size_t)(kx + R)] = p;
            out->power[(size_t)(-ky + R) * side + (size_t)(-kx + R)] = p;
        }
    }
    free(re);
    free(im);
    free(tab);
    radial_figures(out, n);
    return AA_OK;
}

int aa_spectrum_mean(const aa_spectrum *s, size_t m, size_t n, aa_spectrum *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    if (m < 1)
        return aa_error_set(err, AA_EINVAL, "sets", "no spectra to average");
    int R = s[0].radius;
    for (size_t i = 1; i < m; i++)
        if (s[i].radius != R)
            return aa_error_set(err, AA_EINVAL, "sets", "spectra of different radii");
    size_t side = (size_t)(2 * R + 1);
    out->radius = R;
    out->side = side;
    out->power = calloc(side * side, sizeof *out->power);
    out->radial = malloc((size_t)(R + 1) * sizeof *out->radial);
    out->anisotropy_db = malloc((size_t)(R + 1) * sizeof *out->anisotropy_db);
    out->annulus_count = calloc((size_t)R + 1, sizeof *out->annulus_count);
    if (!out->power || !out->radial || !out->anisotropy_db || !out->annulus_count) {
        aa_spectrum_free(out);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    for (size_t i = 0; i < m; i++)
        for (size_t k = 0; k < side * side; k++)
            out->power[k] += s[i].power[k];
    for (size_t k = 0; k < side * side; k++)
        out->power[k] /= (double)m;
    radial_figures(out, n);
    return AA_OK;
}
