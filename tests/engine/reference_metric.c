/* Independent slow reference evaluator (see reference_metric.h). Long double throughout. */
#include "reference_metric.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GL_MAX 64

/* ---------- Gauss-Legendre rules (Newton on P_m in long double) ---------- */

static void legendre_and_derivative(int m, long double x, long double *pm, long double *dpm)
{
    long double p0 = 1.0L, p1 = x;
    for (int k = 2; k <= m; k++) {
        long double p2 = ((2.0L * k - 1.0L) * x * p1 - (k - 1.0L) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    *pm = p1;
    *dpm = m * (x * p1 - p0) / (x * x - 1.0L);
}

static void compute_rule(int m, long double *node, long double *weight)
{
    for (int i = 0; i < m; i++) {
        /* Tricomi's initial guess, then Newton to long-double precision. */
        long double x = cosl(REF_PI * (i + 0.75L) / (m + 0.5L));
        long double pm, dpm;
        for (int it = 0; it < 100; it++) {
            legendre_and_derivative(m, x, &pm, &dpm);
            long double dx = pm / dpm;
            x -= dx;
            if (fabsl(dx) < 1e-21L)
                break;
        }
        legendre_and_derivative(m, x, &pm, &dpm);
        node[m - 1 - i] = x; /* ascending */
        weight[m - 1 - i] = 2.0L / ((1.0L - x * x) * dpm * dpm);
    }
}

static long double rule10_node[10], rule10_weight[10], rule20_node[20], rule20_weight[20];
static int rules_ready; /* tests are single-threaded */

static void ensure_rules(void)
{
    if (rules_ready)
        return;
    compute_rule(10, rule10_node, rule10_weight);
    compute_rule(20, rule20_node, rule20_weight);
    rules_ready = 1;
}

void ref_gauss_legendre(int m, long double *node, long double *weight)
{
    compute_rule(m, node, weight);
}

/* ---------- filters ---------- */

void ref_filter_mitchell(ref_filter *f, long double B, long double C, long double radius)
{
    memset(f, 0, sizeof *f);
    f->formula = REF_MITCHELL;
    f->B = B;
    f->C = C;
    f->radius = radius;
    f->norm = 1.0L;
}

void ref_filter_box(ref_filter *f, long double radius)
{
    memset(f, 0, sizeof *f);
    f->formula = REF_BOX;
    f->radius = radius;
    f->norm = 1.0L;
}

void ref_filter_tent(ref_filter *f, long double radius)
{
    memset(f, 0, sizeof *f);
    f->formula = REF_TENT;
    f->radius = radius;
    f->norm = 1.0L;
}

void ref_filter_gaussian(ref_filter *f, long double sigma, long double radius)
{
    memset(f, 0, sizeof *f);
    f->formula = REF_GAUSSIAN;
    f->sigma = sigma;
    f->radius = radius;
    f->norm = 1.0L / (sigma * sqrtl(2.0L * REF_PI) * erfl(radius / (sigma * sqrtl(2.0L))));
}

static long double sinc(long double x)
{
    if (x == 0.0L)
        return 1.0L;
    long double px = REF_PI * x;
    return sinl(px) / px;
}

static long double lanczos_unnormalised(const ref_filter *f, long double x)
{
    return sinc(x) * sinc(x / f->a);
}

static long double gl20_lanczos(const ref_filter *f, long double u, long double v)
{
    ensure_rules();
    long double mid = 0.5L * (u + v), half = 0.5L * (v - u), s = 0.0L;
    for (int i = 0; i < 20; i++)
        s += rule20_weight[i] * lanczos_unnormalised(f, mid + half * rule20_node[i]);
    return s * half;
}

void ref_filter_lanczos(ref_filter *f, long double a)
{
    memset(f, 0, sizeof *f);
    f->formula = REF_LANCZOS;
    f->a = a;
    f->radius = a;
    int cells = (int)ceill(2.0L * a / REF_LANCZOS_STEP);
    if (cells > REF_LANCZOS_MAX_CELLS)
        cells = REF_LANCZOS_MAX_CELLS; /* callers keep a <= 8 */
    long double acc = 0.0L;
    f->cell_cdf[0] = 0.0L;
    for (int k = 0; k < cells; k++) {
        long double u = -a + k * REF_LANCZOS_STEP;
        long double v = fminl(u + REF_LANCZOS_STEP, a);
        acc += gl20_lanczos(f, u, v);
        f->cell_cdf[k + 1] = acc;
    }
    f->norm = 1.0L / acc;
    for (int k = 0; k <= cells; k++)
        f->cell_cdf[k] *= f->norm;
}

/* The standard Mitchell-Netravali cubic k(t) on [-2, 2] and its CDF. */
static long double mitchell_k(long double B, long double C, long double t)
{
    t = fabsl(t);
    if (t < 1.0L)
        return ((12.0L - 9.0L * B - 6.0L * C) * t * t * t +
                (-18.0L + 12.0L * B + 6.0L * C) * t * t + (6.0L - 2.0L * B)) /
               6.0L;
    if (t < 2.0L)
        return ((-B - 6.0L * C) * t * t * t + (6.0L * B + 30.0L * C) * t * t +
                (-12.0L * B - 48.0L * C) * t + (8.0L * B + 24.0L * C)) /
               6.0L;
    return 0.0L;
}

/* Antiderivatives of the two cubics, zero at t = 0 (inner) and as polynomials (outer). */
static long double mitchell_inner_integral(long double B, long double C, long double t)
{
    return ((12.0L - 9.0L * B - 6.0L * C) * t * t * t * t / 4.0L +
            (-18.0L + 12.0L * B + 6.0L * C) * t * t * t / 3.0L + (6.0L - 2.0L * B) * t) /
           6.0L;
}

static long double mitchell_outer_poly(long double B, long double C, long double t)
{
    return ((-B - 6.0L * C) * t * t * t * t / 4.0L + (6.0L * B + 30.0L * C) * t * t * t / 3.0L +
            (-12.0L * B - 48.0L * C) * t * t / 2.0L + (8.0L * B + 24.0L * C) * t) /
           6.0L;
}

static long double mitchell_cdf_standard(long double B, long double C, long double t)
{
    if (t <= -2.0L)
        return 0.0L;
    if (t >= 2.0L)
        return 1.0L;
    long double u = fabsl(t), half;
    if (u < 1.0L)
        half = mitchell_inner_integral(B, C, u);
    else
        half = mitchell_inner_integral(B, C, 1.0L) + mitchell_outer_poly(B, C, u) -
               mitchell_outer_poly(B, C, 1.0L);
    return t < 0.0L ? 0.5L - half : 0.5L + half;
}

long double ref_filter_h(const ref_filter *f, long double x)
{
    long double r = f->radius;
    if (fabsl(x) >= r)
        return 0.0L;
    switch (f->formula) {
    case REF_MITCHELL: {
        long double s = 2.0L / r;
        return s * mitchell_k(f->B, f->C, s * x);
    }
    case REF_BOX:
        return 0.5L / r;
    case REF_TENT:
        return (1.0L - fabsl(x) / r) / r;
    case REF_GAUSSIAN:
        return f->norm * expl(-x * x / (2.0L * f->sigma * f->sigma));
    case REF_LANCZOS:
        return f->norm * lanczos_unnormalised(f, x);
    }
    return 0.0L;
}

long double ref_filter_cdf(const ref_filter *f, long double a)
{
    long double r = f->radius;
    if (a <= -r)
        return 0.0L;
    if (a >= r)
        return 1.0L;
    switch (f->formula) {
    case REF_MITCHELL:
        return mitchell_cdf_standard(f->B, f->C, a * 2.0L / r);
    case REF_BOX:
        return (a + r) / (2.0L * r);
    case REF_TENT:
        if (a <= 0.0L)
            return (a + r) * (a + r) / (2.0L * r * r);
        return 1.0L - (r - a) * (r - a) / (2.0L * r * r);
    case REF_GAUSSIAN: {
        long double q = sqrtl(2.0L) * f->sigma;
        return 0.5L + 0.5L * erfl(a / q) / erfl(r / q);
    }
    case REF_LANCZOS: {
        int k = (int)floorl((a + r) / REF_LANCZOS_STEP);
        if (k < 0)
            k = 0;
        long double u = -r + k * REF_LANCZOS_STEP;
        return f->cell_cdf[k] + f->norm * gl20_lanczos(f, u, a);
    }
    }
    return 0.0L;
}

size_t ref_filter_knots(const ref_filter *f, long double *out)
{
    long double r = f->radius;
    switch (f->formula) {
    case REF_MITCHELL:
        out[0] = -r, out[1] = -0.5L * r, out[2] = 0.0L, out[3] = 0.5L * r, out[4] = r;
        return 5;
    case REF_TENT:
        out[0] = -r, out[1] = 0.0L, out[2] = r;
        return 3;
    default:
        out[0] = -r, out[1] = r;
        return 2;
    }
}

static long double gl20_h(const ref_filter *f, long double u, long double v)
{
    ensure_rules();
    long double mid = 0.5L * (u + v), half = 0.5L * (v - u), s = 0.0L;
    for (int i = 0; i < 20; i++)
        s += rule20_weight[i] * ref_filter_h(f, mid + half * rule20_node[i]);
    return s * half;
}

long double ref_filter_cdf_by_quadrature(const ref_filter *f, long double a, long double cell)
{
    long double r = f->radius;
    if (a <= -r)
        return 0.0L;
    if (a > r)
        a = r;
    long double knots[8];
    size_t nk = ref_filter_knots(f, knots);
    long double acc = 0.0L, u = -r;
    for (size_t k = 1; k < nk && u < a; k++) {
        long double end = fminl(knots[k], a);
        while (u < end) {
            long double v = fminl(u + cell, end);
            acc += gl20_h(f, u, v);
            u = v;
        }
    }
    return acc;
}

/* ---------- E1 by adaptive quadrature ---------- */

typedef struct piece_ctx {
    const ref_filter *f;
    long double c; /* ghat on the interval */
    int squared;   /* integrand (c - g)^2, else (c - g) */
    long double abs_tol;
} piece_ctx;

static long double integrand(const piece_ctx *ctx, long double a)
{
    long double d = ctx->c - ref_filter_cdf(ctx->f, a);
    return ctx->squared ? d * d : d;
}

static void gl_pair(const piece_ctx *ctx, long double u, long double v, long double *g10,
                    long double *g20)
{
    long double mid = 0.5L * (u + v), half = 0.5L * (v - u), s10 = 0.0L, s20 = 0.0L;
    for (int i = 0; i < 10; i++)
        s10 += rule10_weight[i] * integrand(ctx, mid + half * rule10_node[i]);
    for (int i = 0; i < 20; i++)
        s20 += rule20_weight[i] * integrand(ctx, mid + half * rule20_node[i]);
    *g10 = s10 * half;
    *g20 = s20 * half;
}

static long double adaptive(const piece_ctx *ctx, long double u, long double v, int depth)
{
    long double g10, g20;
    gl_pair(ctx, u, v, &g10, &g20);
    long double diff = fabsl(g20 - g10);
    if (diff <= 1e-18L * fabsl(g20) || diff <= ctx->abs_tol || depth >= 48)
        return g20;
    long double m = 0.5L * (u + v);
    return adaptive(ctx, u, m, depth + 1) + adaptive(ctx, m, v, depth + 1);
}

static int cmp_ld(const void *a, const void *b)
{
    long double x = *(const long double *)a, y = *(const long double *)b;
    return (x > y) - (x < y);
}

typedef struct pw {
    long double p, w;
} pw;

static int cmp_pw(const void *a, const void *b)
{
    return cmp_ld(&((const pw *)a)->p, &((const pw *)b)->p);
}

/* Integrates (ghat - g)^2 (squared) or (ghat - g) over every interval between breakpoints,
 * writing per-interval results to out (if not NULL, with the breakpoints to bp). Returns the
 * total and the number of breakpoints. */
static long double integrate_pattern(const ref_filter *f, const long double *p,
                                     const long double *w, size_t n, int squared,
                                     long double abs_tol, long double **bp_out,
                                     long double **piece_out, size_t *nbp_out)
{
    ensure_rules();
    long double knots[8];
    size_t nk = ref_filter_knots(f, knots);
    pw *s = malloc((n ? n : 1) * sizeof *s);
    long double *bp = malloc((n + nk) * sizeof *bp);
    for (size_t i = 0; i < n; i++) {
        s[i].p = p[i];
        s[i].w = w[i];
        bp[i] = p[i];
    }
    for (size_t k = 0; k < nk; k++)
        bp[n + k] = knots[k];
    qsort(s, n, sizeof *s, cmp_pw);
    qsort(bp, n + nk, sizeof *bp, cmp_ld);
    size_t nbp = 0;
    for (size_t k = 0; k < n + nk; k++)
        if (nbp == 0 || bp[k] != bp[nbp - 1])
            bp[nbp++] = bp[k];
    long double *piece = piece_out ? calloc(nbp, sizeof *piece) : NULL;
    piece_ctx ctx = {f, 0.0L, squared, abs_tol};
    long double total = 0.0L;
    size_t j = 0;
    for (size_t k = 0; k + 1 < nbp; k++) {
        long double u = bp[k], v = bp[k + 1];
        while (j < n && s[j].p <= u)
            ctx.c += s[j++].w;
        long double r = adaptive(&ctx, u, v, 0);
        if (piece)
            piece[k] = r;
        total += r;
    }
    free(s);
    if (bp_out)
        *bp_out = bp;
    else
        free(bp);
    if (piece_out)
        *piece_out = piece;
    if (nbp_out)
        *nbp_out = nbp;
    return total;
}

long double ref_e1_squared(const ref_filter *f, const long double *p, const long double *w,
                           size_t n)
{
    /* First pass with a loose tolerance gives the scale for the absolute floor. */
    long double rough = integrate_pattern(f, p, w, n, 1, 1e300L, NULL, NULL, NULL);
    return integrate_pattern(f, p, w, n, 1, 1e-21L * rough, NULL, NULL, NULL);
}

void ref_project(const double *x, const double *y, size_t n, double theta, long double *p)
{
    long double c = cosl((long double)theta), s = sinl((long double)theta);
    for (size_t i = 0; i < n; i++)
        p[i] = (long double)x[i] * c + (long double)y[i] * s;
}

long double ref_e1_at_angle(const ref_filter *f, const double *x, const double *y, const double *w,
                            size_t n, double theta)
{
    long double *p = malloc((n ? n : 1) * sizeof *p), *wl = malloc((n ? n : 1) * sizeof *wl);
    ref_project(x, y, n, theta, p);
    for (size_t i = 0; i < n; i++)
        wl[i] = w[i];
    long double e2 = ref_e1_squared(f, p, wl, n);
    free(p);
    free(wl);
    return sqrtl(e2);
}

void ref_e1_gradient_1d(const ref_filter *f, const long double *p, const long double *w, size_t n,
                        long double *e1, long double *dp, long double *dw_raw)
{
    long double sq = ref_e1_squared(f, p, w, n);
    long double e = sqrtl(sq);
    *e1 = e;
    long double *bp, *piece;
    size_t nbp;
    long double rough = fabsl(integrate_pattern(f, p, w, n, 0, 1e300L, NULL, NULL, NULL));
    integrate_pattern(f, p, w, n, 0, 1e-21L * (rough + sq), &bp, &piece, &nbp);
    for (size_t i = 0; i < n; i++) {
        long double S = 0.0L;
        for (size_t j = 0; j < n; j++)
            if (p[j] < p[i])
                S += w[j];
        dp[i] = w[i] * (2.0L * ref_filter_cdf(f, p[i]) - 2.0L * S - w[i]) / (2.0L * e);
        long double tail = 0.0L;
        for (size_t k = 0; k + 1 < nbp; k++)
            if (bp[k] >= p[i])
                tail += piece[k];
        dw_raw[i] = tail / e;
    }
    free(bp);
    free(piece);
}
