/* Closed-form tables of the piecewise-polynomial filters (filter_closed.h, docs/metric.md 2b).
 *
 * From h (degree <= 3 on each piece) two exact polynomial integrations give gamma = g - 1/2
 * (degree <= 4) and Gamma = integral of gamma from -radius (degree <= 5), each piece continued
 * from the value at its left knot (gamma(-r) = -1/2, Gamma(-r) = 0). Everything is done in long
 * double on coefficients about the piece midpoint and rounded to double once, so a coefficient
 * is within half an ulp (plus a few long-double ulps) of the exact rational value. */
#include "filter_closed.h"

#include <math.h>
#include <string.h>

#define GAMMA_TERMS (AA_FILTER_CLOSED_DEGREE + 1)

static long double poly_eval(const long double *c, int terms, long double s)
{
    long double v = 0;
    for (int k = terms - 1; k >= 0; k--)
        v = v * s + c[k];
    return v;
}

void aa_filter_mitchell_coefficients(const aa_filter *f, long double (*h_coef)[4])
{
    long double B = f->B, C = f->C, r = f->radius, sigma = 2.0L / r;
    /* k(t) of the radius-2 cubic, t = 2|a|/r: inner |t| < 1, outer 1 <= |t| < 2. */
    const long double inner[4] = {(6 - 2 * B) / 6, 0, (-18 + 12 * B + 6 * C) / 6,
                                  (12 - 9 * B - 6 * C) / 6};
    const long double outer[4] = {(8 * B + 24 * C) / 6, (-12 * B - 48 * C) / 6,
                                  (6 * B + 30 * C) / 6, (-B - 6 * C) / 6};
    const long double *which[4] = {outer, inner, inner, outer};
    const long double sign[4] = {-1, -1, 1, 1};
    for (int j = 0; j < 4; j++) {
        long double scale = sigma; /* h_r(a) = (2/r) k(2a/r) */
        for (int m = 0; m < 4; m++) {
            h_coef[j][m] = which[j][m] * scale;
            scale *= sign[j] * sigma;
        }
    }
}

void aa_filter_build_closed(aa_filter *f, const long double (*h_coef)[4], int pieces)
{
    long double r = f->radius, width = 2 * r / pieces;
    long double gamma_lo = -0.5L, big_gamma_lo = 0, var = 0;
    for (int j = 0; j < pieces; j++) {
        long double lo = -r + width * j, mid = lo + width / 2, half = width / 2;
        /* h about the midpoint: q[k] = sum_{m >= k} h_m C(m, k) mid^(m-k). */
        long double q[4] = {0};
        for (int m = 0; m < 4; m++) {
            long double binom = 1, pw = 1;
            for (int k = m; k >= 0; k--) {
                /* term for k: C(m, k) mid^(m - k); walk k downwards */
                q[k] += h_coef[j][m] * binom * pw;
                binom = binom * k / (m - k + 1);
                pw *= mid;
            }
        }
        long double gm[5] = {0}, big[GAMMA_TERMS] = {0};
        for (int k = 0; k < 4; k++)
            gm[k + 1] = q[k] / (k + 1);
        gm[0] = gamma_lo - poly_eval(gm, 5, -half);
        for (int k = 0; k < 5; k++)
            big[k + 1] = gm[k] / (k + 1);
        big[0] = big_gamma_lo - poly_eval(big, GAMMA_TERMS, -half);
        /* integral over the piece of gamma^2: odd powers of s integrate to 0 on [-half, half]. */
        long double sq[9] = {0};
        for (int a = 0; a < 5; a++)
            for (int b = 0; b < 5; b++)
                sq[a + b] += gm[a] * gm[b];
        for (int k = 0; k < 9; k += 2)
            var += sq[k] * 2 * powl(half, k + 1) / (k + 1);
        gamma_lo = poly_eval(gm, 5, half);
        big_gamma_lo = poly_eval(big, GAMMA_TERMS, half);
        f->closed_mid[j] = (double)mid;
        for (int k = 0; k < GAMMA_TERMS; k++)
            f->closed_gamma[j][k] = (double)big[k];
    }
    f->closed_pieces = pieces;
    f->closed_inv_width = (double)(1 / width);
    f->closed_var = (double)var;
}
