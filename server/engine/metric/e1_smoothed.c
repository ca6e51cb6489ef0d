/* E1 with the kinks of its sample crossings smoothed, for the optimizer's descent.
 *
 * E1^2 = integral (ghat - g)^2 with ghat = sum_i w_i H(a - p_i). Expanding the square, the only
 * part that is not continuously differentiable in the projections is the pairwise one:
 *   E1^2 = S(p, w) - sum_{i<j} w_i w_j |p_i - p_j|,
 * S smooth (docs/metric.md section 7). Where two projections cross, E1^2 has a kink of slope
 * jump 2 |w_i w_j|: a V (a valley that holds the pair aligned) when the weights have opposite
 * signs, a ridge when they have the same sign. Optimised P(16,16,4) patterns have dozens of
 * pairs within 1e-6 px of such a crossing, mostly of opposite signs, and a quasi-Newton descent
 * stalls on them. Replacing each |d| below the width h by the Huber function d^2/(2h) + h/2
 * (equal value and slope at |d| = h) adds
 *   C = -sum_{i<j, |d_ij| < h} w_i w_j (h - |d_ij|)^2 / (2h)
 * and makes E1^2 continuously differentiable in the positions; h = 0 gives E1 exactly.
 * Precision: the exact E1's (metric.h) plus a few ulp of C per pair. */
#include <math.h>

#include "metric.h"

/* One pass over the pairs within h of the sorted arrays ws->p, ws->w (left by the exact call;
 * pairs within h are neighbours in sorted order, so the inner loop stops at the first projection
 * h or more away). Returns C; when dx, dy, dw are given (input order, each may be NULL), adds
 * half of C's gradient to them: dC/dd = w_k w_m r / h for d = p_m - p_k >= 0, r = h - d, and
 * dC/dw_k = -w_m r^2 / (2h), the weight part projected onto sum(w) = 1. */
static double kink_pairs(const aa_metric_workspace *ws, size_t n, double h, double ct, double st,
                         double *dx, double *dy, double *dw)
{
    const double *p = ws->p, *w = ws->w;
    const uint32_t *ix = ws->index;
    double c = 0, dw_sum = 0;
    for (size_t k = 0; k + 1 < n; k++)
        for (size_t m = k + 1; m < n && p[m] - p[k] < h; m++) {
            double r = h - (p[m] - p[k]), rr = r * r / (2 * h), g = 0.5 * w[k] * w[m] * r / h;
            c -= w[k] * w[m] * rr;
            if (dx) {
                dx[ix[m]] += g * ct;
                dx[ix[k]] -= g * ct;
            }
            if (dy) {
                dy[ix[m]] += g * st;
                dy[ix[k]] -= g * st;
            }
            if (dw) {
                dw[ix[k]] -= 0.5 * rr * w[m];
                dw[ix[m]] -= 0.5 * rr * w[k];
                dw_sum -= 0.5 * rr * (w[m] + w[k]);
            }
        }
    if (dw)
        for (size_t i = 0; i < n; i++)
            dw[i] -= dw_sum / (double)n;
    return c;
}

/* dx, dy, dw (each may be NULL) times s. */
static void scale_gradient(size_t n, double s, double *dx, double *dy, double *dw)
{
    for (size_t i = 0; i < n; i++) {
        if (dx)
            dx[i] *= s;
        if (dy)
            dy[i] *= s;
        if (dw)
            dw[i] *= s;
    }
}

static int check_width(double h)
{
    return isfinite(h) && h >= 0 ? AA_OK : AA_EINVAL;
}

int aa_e1_smoothed_at_direction(const aa_filter *f, const aa_sample *s, size_t n, double ct,
                                double st, double kink_width, aa_metric_workspace *ws, double *e1,
                                double *e1_smoothed)
{
    if (check_width(kink_width))
        return AA_EINVAL;
    int rc = aa_e1_sorted_at_direction(f, s, n, ct, st, AA_E1_AUTO, ws, e1);
    if (rc)
        return rc;
    double sq = *e1 * *e1;
    if (kink_width > 0)
        sq += kink_pairs(ws, n, kink_width, ct, st, NULL, NULL, NULL);
    *e1_smoothed = kink_width > 0 ? sqrt(sq > 0 ? sq : 0) : *e1;
    return AA_OK;
}

int aa_e1_smoothed_gradient_at_direction(const aa_filter *f, const aa_sample *s, size_t n,
                                         double ct, double st, double kink_width,
                                         aa_metric_workspace *ws, double *e1, double *e1_smoothed,
                                         double *dx, double *dy, double *dw)
{
    if (check_width(kink_width))
        return AA_EINVAL;
    int rc = aa_e1_gradient_at_direction(f, s, n, ct, st, AA_E1_AUTO, ws, e1, dx, dy, dw);
    if (rc || kink_width == 0) {
        *e1_smoothed = *e1;
        return rc;
    }
    /* dE_s = (dE1^2 + dC) / (2 E_s) and dE1^2 = 2 E dE: the exact gradient times E, plus dC / 2
     * (kink_pairs), all over E_s. At E_s = 0 the gradient is not defined (as the exact one at
     * E1 = 0): zeros. */
    double e = *e1;
    scale_gradient(n, e, dx, dy, dw);
    double sq = e * e + kink_pairs(ws, n, kink_width, ct, st, dx, dy, dw);
    double es = sqrt(sq > 0 ? sq : 0), inv = es > 0 ? 1 / es : 0;
    *e1_smoothed = es;
    scale_gradient(n, inv, dx, dy, dw);
    return AA_OK;
}
