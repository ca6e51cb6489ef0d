/* Reference filters stored as piecewise Chebyshev series of their CDF (see filter.h).
 *
 * Construction: on each piece the CDF is sampled at Chebyshev points of the first kind,
 * g(a) = g(knot_j) + integral_{knot_j}^{a} h, with the integral done by 32-point
 * Gauss-Legendre (exact for the piecewise-cubic filters, and converged to rounding for the
 * Gaussian and Lanczos pieces, which are analytic and short). The values are turned into
 * Chebyshev coefficients by the discrete cosine sum. For the Gaussian the exact CDF (erf) is
 * used instead of quadrature. The table error is then measured at off-node points. */
#include "filter.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "aa_core.h"
#include "filter_closed.h"

#define PI 3.14159265358979323846

const char *const aa_filter_names[] = {"mitchell", "catmull-rom", "bspline", "notch", "box",
                                       "tent",     "gaussian",    "lanczos", NULL};

/* Raw (unnormalised) impulse response of each formula. */
static double mitchell_raw(const aa_filter *f, double x)
{
    double B = f->B, C = f->C;
    x = fabs(x) * 2.0 / f->radius; /* the classic kernel has support 2 */
    double v;
    if (x < 1)
        v = ((12 - 9 * B - 6 * C) * x * x * x + (-18 + 12 * B + 6 * C) * x * x + (6 - 2 * B)) / 6;
    else if (x < 2)
        v = ((-B - 6 * C) * x * x * x + (6 * B + 30 * C) * x * x + (-12 * B - 48 * C) * x +
             (8 * B + 24 * C)) /
            6;
    else
        v = 0;
    return v * 2.0 / f->radius;
}

static double sinc(double x)
{
    if (fabs(x) < 1e-8)
        return 1 - (PI * x) * (PI * x) / 6;
    return sin(PI * x) / (PI * x);
}

static double raw_eval(const aa_filter *f, double x)
{
    if (!(fabs(x) < f->radius))
        return 0;
    switch (f->formula) {
    case AA_FILTER_MITCHELL:
        return mitchell_raw(f, x);
    case AA_FILTER_BOX:
        return 1;
    case AA_FILTER_TENT:
        return 1 - fabs(x) / f->radius;
    case AA_FILTER_GAUSSIAN:
        return exp(-x * x / (2 * f->sigma * f->sigma));
    case AA_FILTER_LANCZOS:
        return sinc(x) * sinc(x / f->lanczos_a);
    }
    return 0;
}

/* The raw response in long double, for building the tables a few bits beyond double. */
static long double raw_eval_long(const aa_filter *f, long double x)
{
    if (!(fabsl(x) < f->radius))
        return 0;
    const long double pi = 3.141592653589793238462643383279502884L;
    switch (f->formula) {
    case AA_FILTER_MITCHELL: {
        long double B = f->B, C = f->C, t = fabsl(x) * 2 / f->radius, v;
        if (t < 1)
            v = ((12 - 9 * B - 6 * C) * t * t * t + (-18 + 12 * B + 6 * C) * t * t + (6 - 2 * B)) /
                6;
        else
            v = ((-B - 6 * C) * t * t * t + (6 * B + 30 * C) * t * t + (-12 * B - 48 * C) * t +
                 (8 * B + 24 * C)) /
                6;
        return v * 2 / f->radius;
    }
    case AA_FILTER_BOX:
        return 1;
    case AA_FILTER_TENT:
        return 1 - fabsl(x) / f->radius;
    case AA_FILTER_GAUSSIAN:
        return expl(-x * x / (2.0L * f->sigma * f->sigma));
    case AA_FILTER_LANCZOS: {
        long double a = f->lanczos_a, px = pi * x;
        if (fabsl(x) < 1e-10L)
            return 1;
        return sinl(px) / px * (sinl(px / a) / (px / a));
    }
    }
    return 0;
}

/* Integral of the raw response over [u, v] within one smooth piece. */
static long double raw_integral(const aa_filter *f, double u, double v, const double *gn,
                                const double *gw, int m)
{
    long double half = 0.5L * ((long double)v - u), mid = 0.5L * ((long double)u + v), s = 0;
    for (int k = 0; k < m; k++)
        s += gw[k] * raw_eval_long(f, mid + half * gn[k]);
    return s * half;
}

static long double gaussian_cdf_raw(const aa_filter *f, double a)
{
    /* integral_{-r}^{a} exp(-x^2/2s^2) dx, divided by s*sqrt(2 pi) */
    long double k = 1.0L / (f->sigma * sqrtl(2.0L));
    return 0.5L * (erfl(a * k) - erfl(-f->radius * k));
}

/* Fills the Chebyshev coefficients of one piece from CDF values at Chebyshev nodes. */
static void chebyshev_fit(const double *values, int n, double *coef)
{
    for (int k = 0; k < n; k++) {
        double s = 0;
        for (int i = 0; i < n; i++)
            s += values[i] * cos(PI * k * (i + 0.5) / n);
        coef[k] = s * (k == 0 ? 1.0 : 2.0) / n;
    }
}

static double clenshaw(const double *c, int degree, double t)
{
    double b1 = 0, b2 = 0;
    for (int k = degree; k >= 1; k--) {
        double b0 = 2 * t * b1 - b2 + c[k];
        b2 = b1;
        b1 = b0;
    }
    return t * b1 - b2 + c[0];
}

double aa_filter_cdf_in_piece(const aa_filter *f, int j, double a)
{
    double lo = f->knot[j], hi = f->knot[j + 1];
    double t = (2 * a - lo - hi) / (hi - lo);
    return clenshaw(f->cheb[j], f->degree, t);
}

int aa_filter_piece(const aa_filter *f, double a)
{
    if (a <= f->knot[0])
        return -1;
    if (a >= f->knot[f->pieces])
        return f->pieces;
    int lo = 0, hi = f->pieces; /* knot[lo] < a < knot[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (f->knot[mid] <= a)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

double aa_filter_cdf(const aa_filter *f, double a)
{
    int j = aa_filter_piece(f, a);
    if (j < 0)
        return 0;
    if (j >= f->pieces)
        return 1;
    return aa_filter_cdf_in_piece(f, j, a);
}

/* Builds knots and Chebyshev tables once the formula and parameters are set. The raw response
 * is integrated to a total which normalises it. */
static void build_table(aa_filter *f, const double *knots, int pieces, int degree)
{
    double gn[AA_GL_MAX_POINTS], gw[AA_GL_MAX_POINTS];
    aa_gauss_legendre(AA_GL_MAX_POINTS, gn, gw);
    f->pieces = pieces;
    f->degree = degree;
    memcpy(f->knot, knots, sizeof(double) * (size_t)(pieces + 1));

    /* Piece integrals and the total in long double; raw CDF at each knot. */
    long double start[AA_FILTER_MAX_PIECES + 1], total;
    start[0] = 0;
    for (int j = 0; j < pieces; j++)
        start[j + 1] =
            f->formula == AA_FILTER_GAUSSIAN
                ? gaussian_cdf_raw(f, knots[j + 1])
                : start[j] + raw_integral(f, knots[j], knots[j + 1], gn, gw, AA_GL_MAX_POINTS);
    total = start[pieces];
    if (f->formula == AA_FILTER_GAUSSIAN)
        f->scale = (double)(1.0L / (f->sigma * sqrtl(2 * 3.141592653589793238462643383279502884L) *
                                    erfl(f->radius / (f->sigma * sqrtl(2.0L)))));
    else
        f->scale = (double)(1.0L / total);

    int n = degree + 1;
    double err = 0;
    for (int j = 0; j < pieces; j++) {
        double lo = knots[j], hi = knots[j + 1], values[AA_FILTER_MAX_DEGREE + 1];
        long double exact[AA_FILTER_MAX_DEGREE + 1];
        for (int i = 0; i < n; i++) {
            double t = cos(PI * (i + 0.5) / n);
            double a = 0.5 * (lo + hi) + 0.5 * (hi - lo) * t;
            long double raw = f->formula == AA_FILTER_GAUSSIAN
                                  ? gaussian_cdf_raw(f, a)
                                  : start[j] + raw_integral(f, lo, a, gn, gw, AA_GL_MAX_POINTS);
            exact[i] = raw / total;
        }
        /* Fit the residual about a base value: the DCT's rounding then scales with the CDF's
         * variation over the piece, not with its magnitude (which is up to 1). */
        long double base = exact[n / 2];
        for (int i = 0; i < n; i++)
            values[i] = (double)(exact[i] - base);
        chebyshev_fit(values, n, f->cheb[j]);
        f->cheb[j][0] = (double)(f->cheb[j][0] + base);

        /* Measured table error against the long-double CDF at off-node points. */
        for (int i = 1; i < 16; i++) {
            double a = lo + (hi - lo) * i / 16.0;
            long double raw = f->formula == AA_FILTER_GAUSSIAN
                                  ? gaussian_cdf_raw(f, a)
                                  : start[j] + raw_integral(f, lo, a, gn, gw, AA_GL_MAX_POINTS);
            double e = (double)fabsl(raw / total - aa_filter_cdf_in_piece(f, j, a));
            if (e > err)
                err = e;
        }
    }
    f->cdf_error_bound = err;
    aa_gauss_legendre(degree + 1, f->rule_node, f->rule_weight);
}

static int check_positive(double v, const char *field, aa_error *err)
{
    if (!isfinite(v) || v <= 0)
        return aa_error_set(err, AA_EINVAL, field, "%s must be a finite number > 0", field);
    return AA_OK;
}

static void reset(aa_filter *f, aa_filter_formula formula, const char *name)
{
    memset(f, 0, sizeof *f);
    f->formula = formula;
    snprintf(f->name, sizeof f->name, "%s", name);
    f->B = f->C = f->sigma = f->lanczos_a = NAN;
}

int aa_filter_mitchell(aa_filter *f, double B, double C, double radius, aa_error *err)
{
    /* Beyond |B|, |C| = 100 the cubic's coefficients dwarf its unit integral and the CDF table
     * loses all precision; such filters are not useful references. */
    if (!isfinite(B) || fabs(B) > 100)
        return aa_error_set(err, AA_EINVAL, "B", "B must be a finite number in [-100, 100]");
    if (!isfinite(C) || fabs(C) > 100)
        return aa_error_set(err, AA_EINVAL, "C", "C must be a finite number in [-100, 100]");
    int rc = check_positive(radius, "radius", err);
    if (rc)
        return rc;
    if (radius > 64)
        return aa_error_set(err, AA_EINVAL, "radius", "radius must be at most 64");
    /* The integral is 1 for every (B, C); a filter that is zero everywhere cannot be. */
    reset(f, AA_FILTER_MITCHELL, "mitchell");
    f->B = B;
    f->C = C;
    f->radius = radius;
    double h = radius / 2, knots[5] = {-2 * h, -h, 0, h, 2 * h};
    build_table(f, knots, 4, 4);
    long double h_coef[4][4];
    aa_filter_mitchell_coefficients(f, h_coef);
    aa_filter_build_closed(f, (const long double(*)[4])h_coef, 4);
    return AA_OK;
}

int aa_filter_box(aa_filter *f, double radius, aa_error *err)
{
    int rc = check_positive(radius, "radius", err);
    if (rc)
        return rc;
    if (radius > 64)
        return aa_error_set(err, AA_EINVAL, "radius", "radius must be at most 64");
    reset(f, AA_FILTER_BOX, "box");
    f->radius = radius;
    double knots[2] = {-radius, radius};
    build_table(f, knots, 1, 1);
    const long double h_coef[1][4] = {{0.5L / radius, 0, 0, 0}};
    aa_filter_build_closed(f, h_coef, 1);
    return AA_OK;
}

int aa_filter_tent(aa_filter *f, double radius, aa_error *err)
{
    int rc = check_positive(radius, "radius", err);
    if (rc)
        return rc;
    if (radius > 64)
        return aa_error_set(err, AA_EINVAL, "radius", "radius must be at most 64");
    reset(f, AA_FILTER_TENT, "tent");
    f->radius = radius;
    double knots[3] = {-radius, 0, radius};
    build_table(f, knots, 2, 2);
    long double r = radius;
    const long double h_coef[2][4] = {{1 / r, 1 / (r * r), 0, 0}, {1 / r, -1 / (r * r), 0, 0}};
    aa_filter_build_closed(f, h_coef, 2);
    return AA_OK;
}

int aa_filter_gaussian(aa_filter *f, double sigma, double radius, aa_error *err)
{
    int rc = check_positive(sigma, "sigma", err);
    if (!rc)
        rc = check_positive(radius, "radius", err);
    if (rc)
        return rc;
    if (radius > 64)
        return aa_error_set(err, AA_EINVAL, "radius", "radius must be at most 64");
    if (sigma < 1e-3 * radius)
        return aa_error_set(err, AA_EINVAL, "sigma",
                            "sigma must be at least radius/1000 (the filter degenerates to an "
                            "impulse)");
    reset(f, AA_FILTER_GAUSSIAN, "gaussian");
    f->sigma = sigma;
    f->radius = radius;
    /* Beyond 9 sigma the CDF is 0 or 1 to 1e-19: one flat piece each side; the core gets
     * pieces of at most sigma/4, within the piece budget. */
    double core = fmin(radius, 9 * sigma);
    int inner = (int)ceil(2 * core / (sigma / 4));
    int max_inner = AA_FILTER_MAX_PIECES - 2;
    if (inner > max_inner)
        inner = max_inner;
    double knots[AA_FILTER_MAX_PIECES + 1];
    int k = 0;
    if (core < radius)
        knots[k++] = -radius;
    for (int i = 0; i <= inner; i++)
        knots[k++] = -core + 2 * core * i / inner;
    if (core < radius)
        knots[k++] = radius;
    build_table(f, knots, k - 1, 15);
    return AA_OK;
}

int aa_filter_lanczos(aa_filter *f, double a, aa_error *err)
{
    if (!isfinite(a) || a < 1 || a > 16 || a != floor(a))
        return aa_error_set(err, AA_EINVAL, "a", "a must be an integer from 1 to 16");
    reset(f, AA_FILTER_LANCZOS, "lanczos");
    f->lanczos_a = a;
    f->radius = a;
    /* Pieces of 1/4: the response is entire, so degree 15 on each is exact to rounding. */
    int pieces = (int)(8 * a);
    double knots[AA_FILTER_MAX_PIECES + 1];
    for (int i = 0; i <= pieces; i++)
        knots[i] = -a + 2 * a * i / pieces;
    build_table(f, knots, pieces, 15);
    return AA_OK;
}

aa_filter_params aa_filter_params_default(void)
{
    aa_filter_params p = {NAN, NAN, NAN, NAN, NAN};
    return p;
}

static double or_default(double v, double d)
{
    return isnan(v) ? d : v;
}

int aa_filter_by_name(aa_filter *f, const char *name, const aa_filter_params *p, aa_error *err)
{
    aa_filter_params d = aa_filter_params_default();
    if (!p)
        p = &d;
    if (!name || !strcmp(name, "mitchell"))
        return aa_filter_mitchell(f, or_default(p->B, 1.0 / 3), or_default(p->C, 1.0 / 3),
                                  or_default(p->radius, 2), err);
    struct {
        const char *name;
        double B, C;
    } mn[] = {{"catmull-rom", 0, 0.5}, {"bspline", 1, 0}, {"notch", 1.5, -0.25}};
    for (size_t i = 0; i < sizeof mn / sizeof mn[0]; i++) {
        if (!strcmp(name, mn[i].name)) {
            int rc = aa_filter_mitchell(f, mn[i].B, mn[i].C, or_default(p->radius, 2), err);
            if (!rc)
                snprintf(f->name, sizeof f->name, "%s", mn[i].name);
            return rc;
        }
    }
    if (!strcmp(name, "box"))
        return aa_filter_box(f, or_default(p->radius, 0.5), err);
    if (!strcmp(name, "tent"))
        return aa_filter_tent(f, or_default(p->radius, 1), err);
    if (!strcmp(name, "gaussian"))
        return aa_filter_gaussian(f, or_default(p->sigma, 0.5), or_default(p->radius, 2), err);
    if (!strcmp(name, "lanczos"))
        return aa_filter_lanczos(f, or_default(p->a, 2), err);
    return aa_error_set(err, AA_EINVAL, "name", "unknown filter '%.40s'", name);
}

void aa_filter_default(aa_filter *f)
{
    aa_filter_mitchell(f, 1.0 / 3, 1.0 / 3, 2, NULL);
}

double aa_filter_eval(const aa_filter *f, double x)
{
    return raw_eval(f, x) * f->scale;
}
