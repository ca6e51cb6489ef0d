/* Exact E1 by a sweep over breakpoints; see metric.h for the formulas and precision. */
#include "metric.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct aa_projection {
    double p, w;
    uint32_t index; /* position in the input, for scattering gradients and stable ties */
} aa_projection;

void aa_metric_workspace_init(aa_metric_workspace *ws)
{
    memset(ws, 0, sizeof *ws);
}

void aa_metric_workspace_free(aa_metric_workspace *ws)
{
    free(ws->proj);
    free(ws->tail);
    memset(ws, 0, sizeof *ws);
}

static int reserve(aa_metric_workspace *ws, size_t n)
{
    if (n <= ws->capacity)
        return AA_OK;
    size_t cap = ws->capacity ? ws->capacity : 16;
    while (cap < n)
        cap *= 2;
    aa_projection *p = realloc(ws->proj, cap * sizeof *p);
    if (!p)
        return AA_ENOMEM;
    ws->proj = p;
    double *t = realloc(ws->tail, cap * sizeof *t);
    if (!t)
        return AA_ENOMEM;
    ws->tail = t;
    ws->capacity = cap;
    return AA_OK;
}

/* cos and sin with the axis and diagonal directions exact, so that samples that tie at
 * 0, 45, 90 ... degrees tie in floating point too. */
static void direction(double theta, double *c, double *s)
{
    double cc = cos(theta), ss = sin(theta);
    if (fabs(cc) < 1e-15) {
        cc = 0;
        ss = ss > 0 ? 1 : -1;
    } else if (fabs(ss) < 1e-15) {
        ss = 0;
        cc = cc > 0 ? 1 : -1;
    } else if (fabs(fabs(cc) - fabs(ss)) < 1e-15) {
        cc = copysign(0.70710678118654752440, cc);
        ss = copysign(0.70710678118654752440, ss);
    }
    *c = cc;
    *s = ss;
}

static int projection_less(const aa_projection *a, const aa_projection *b)
{
    return a->p < b->p || (a->p == b->p && a->index < b->index);
}

static int projection_cmp(const void *pa, const void *pb)
{
    const aa_projection *a = pa, *b = pb;
    return projection_less(b, a) - projection_less(a, b);
}

static void sort_projections(aa_projection *v, size_t n)
{
    if (n > 160) {
        qsort(v, n, sizeof *v, projection_cmp);
        return;
    }
    for (size_t i = 1; i < n; i++) {
        aa_projection x = v[i];
        size_t j = i;
        while (j > 0 && projection_less(&x, &v[j - 1])) {
            v[j] = v[j - 1];
            j--;
        }
        v[j] = x;
    }
}

/* Integral over [u, v] of (c - g)^2 (and of (c - g) when want_linear) where g is filter
 * piece j, or the constant 0 (j < 0) / 1 (j >= pieces). */
static void segment_integral(const aa_filter *f, int j, double c, double u, double v, double *sq,
                             double *lin)
{
    double len = v - u;
    if (j < 0 || j >= f->pieces) {
        double d = j < 0 ? c : c - 1;
        *sq += d * d * len;
        *lin += d * len;
        return;
    }
    /* Map the rule's nodes straight into the piece's Chebyshev variable: t = alpha + beta*x. */
    double lo = f->knot[j], hi = f->knot[j + 1], inv = 1.0 / (hi - lo);
    double alpha = (u + v - lo - hi) * inv, beta = len * inv;
    const double *cf = f->cheb[j];
    int deg = f->degree;
    double s2 = 0, s1 = 0;
    for (int k = 0; k <= deg; k++) {
        double t = alpha + beta * f->rule_node[k], t2 = 2 * t, b1 = 0, b2 = 0;
        for (int m = deg; m >= 1; m--) {
            double b0 = t2 * b1 - b2 + cf[m];
            b2 = b1;
            b1 = b0;
        }
        double d = c - (t * b1 - b2 + cf[0]);
        s2 += f->rule_weight[k] * d * d;
        s1 += f->rule_weight[k] * d;
    }
    *sq += s2 * 0.5 * len;
    *lin += s1 * 0.5 * len;
}

/* The sweep. Fills ws->proj (sorted) and, when tail is wanted, ws->tail[k] = integral of
 * (ghat - g) from the k-th sorted projection to +inf. Returns E1^2. */
static double sweep(const aa_filter *f, const aa_sample *s, size_t n, double theta,
                    aa_metric_workspace *ws, bool want_tail)
{
    double ct, st;
    direction(theta, &ct, &st);
    aa_projection *pr = ws->proj;
    for (size_t i = 0; i < n; i++) {
        pr[i].p = s[i].x * ct + s[i].y * st;
        pr[i].w = s[i].w;
        pr[i].index = (uint32_t)i;
    }
    sort_projections(pr, n);

    const double *knot = f->knot;
    int pieces = f->pieces;
    double lo = fmin(pr[0].p, knot[0]), hi = fmax(pr[n - 1].p, knot[pieces]);
    /* j: piece of the filter that the current point a lies in (-1 before the support). */
    int j = lo < knot[0] ? -1 : 0;
    double a = lo, c = 0, sq = 0, lin = 0;
    size_t i = 0;
    while (i < n && pr[i].p <= a) {
        if (want_tail)
            ws->tail[i] = lin;
        c += pr[i++].w;
    }
    while (a < hi) {
        double next_knot = j + 1 <= pieces ? knot[j + 1] : INFINITY;
        double b = i < n ? fmin(pr[i].p, next_knot) : next_knot;
        if (b > hi)
            b = hi;
        if (b > a)
            segment_integral(f, j, c, a, b, &sq, &lin);
        a = b;
        while (j + 1 <= pieces && knot[j + 1] <= a)
            j++;
        while (i < n && pr[i].p <= a) {
            if (want_tail)
                ws->tail[i] = lin; /* prefix so far; turned into a suffix below */
            c += pr[i++].w;
        }
        if (i >= n && j >= pieces)
            break; /* beyond both: ghat = 1 = g (weights sum to 1) */
    }
    if (want_tail) {
        /* Beyond hi the integrand is c - 1, zero when the weights sum to 1. */
        for (size_t k = 0; k < n; k++)
            ws->tail[k] = lin - ws->tail[k];
    }
    return sq;
}

int aa_e1_at_angle(const aa_filter *f, const aa_sample *s, size_t n, double theta,
                   aa_metric_workspace *ws, double *e1)
{
    if (n == 0 || !isfinite(theta))
        return AA_EINVAL;
    if (reserve(ws, n))
        return AA_ENOMEM;
    *e1 = sqrt(sweep(f, s, n, theta, ws, false));
    return AA_OK;
}

int aa_e1_gradient_at_angle(const aa_filter *f, const aa_sample *s, size_t n, double theta,
                            aa_metric_workspace *ws, double *e1, double *dx, double *dy, double *dw)
{
    if (n == 0)
        return AA_EINVAL;
    if (reserve(ws, n))
        return AA_ENOMEM;
    double e = sqrt(sweep(f, s, n, theta, ws, dw != NULL));
    *e1 = e;
    double inv = e > 0 ? 1.0 / e : 0;
    double ct, st;
    direction(theta, &ct, &st);
    const aa_projection *pr = ws->proj;
    if (dx || dy) {
        double before = 0; /* S_i: weight sorted before i */
        for (size_t k = 0; k < n; k++) {
            double w = pr[k].w;
            double dp = w * (2 * aa_filter_cdf(f, pr[k].p) - 2 * before - w) * 0.5 * inv;
            if (dx)
                dx[pr[k].index] = dp * ct;
            if (dy)
                dy[pr[k].index] = dp * st;
            before += w;
        }
    }
    if (dw) {
        double mean = 0;
        for (size_t k = 0; k < n; k++)
            mean += ws->tail[k];
        mean /= (double)n;
        for (size_t k = 0; k < n; k++)
            dw[pr[k].index] = (ws->tail[k] - mean) * inv;
    }
    return AA_OK;
}
