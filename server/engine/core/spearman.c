#include "spearman.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "aa_error.h"

typedef struct ranked {
    double v;
    size_t i;
} ranked;

/* By value, then index: a total order, so the sort's result does not depend on qsort. */
static int cmp_ranked(const void *a, const void *b)
{
    const ranked *x = a, *y = b;
    if (x->v != y->v)
        return x->v < y->v ? -1 : 1;
    return x->i < y->i ? -1 : x->i > y->i;
}

int aa_rank_average(const double *v, size_t n, double *ranks)
{
    assert((v && ranks) || !n);
    ranked *r = malloc((n ? n : 1) * sizeof *r);
    if (!r)
        return AA_ENOMEM;
    for (size_t i = 0; i < n; i++)
        r[i] = (ranked){v[i], i};
    qsort(r, n, sizeof *r, cmp_ranked);
    for (size_t i = 0; i < n;) {
        size_t j = i;
        while (j + 1 < n && r[j + 1].v == r[i].v)
            j++;
        /* ranks i+1 .. j+1: their mean, exact in double for n < 2^52 */
        double mean = 0.5 * (double)(i + j) + 1.0;
        for (size_t k = i; k <= j; k++)
            ranks[r[k].i] = mean;
        i = j + 1;
    }
    free(r);
    return AA_OK;
}

/* Lentz's continued fraction for I_x(a, b), used where x < (a + 1) / (a + b + 2) (Numerical
 * Recipes 6.4). */
static double beta_fraction(double a, double b, double x)
{
    const double tiny = 1e-300;
    double qab = a + b, qap = a + 1, qam = a - 1, c = 1, d = 1 - qab * x / qap;
    if (fabs(d) < tiny)
        d = tiny;
    d = 1 / d;
    double h = d;
    for (int m = 1; m <= 100000; m++) {
        int m2 = 2 * m;
        double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1 + aa * d;
        d = fabs(d) < tiny ? tiny : d;
        c = 1 + aa / c;
        c = fabs(c) < tiny ? tiny : c;
        d = 1 / d;
        h *= d * c;
        aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1 + aa * d;
        d = fabs(d) < tiny ? tiny : d;
        c = 1 + aa / c;
        c = fabs(c) < tiny ? tiny : c;
        d = 1 / d;
        double del = d * c;
        h *= del;
        if (fabs(del - 1) < 4 * DBL_EPSILON)
            break;
    }
    return h;
}

double aa_incomplete_beta(double a, double b, double x)
{
    if (!(a > 0 && b > 0 && x >= 0 && x <= 1))
        return NAN;
    if (x == 0 || x == 1)
        return x;
    double front = exp(lgamma(a + b) - lgamma(a) - lgamma(b) + a * log(x) + b * log1p(-x));
    if (x < (a + 1) / (a + b + 2))
        return front * beta_fraction(a, b, x) / a;
    return 1 - front * beta_fraction(b, a, 1 - x) / b;
}

int aa_spearman_of(const double *x, const double *y, size_t n, aa_spearman_result *out)
{
    *out = (aa_spearman_result){0, NAN, NAN};
    double *buf = malloc((n ? n : 1) * 4 * sizeof *buf);
    if (!buf)
        return AA_ENOMEM;
    double *fx = buf, *fy = buf + n, *rx = buf + 2 * n, *ry = buf + 3 * n;
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (isfinite(x[i]) && isfinite(y[i])) {
            fx[m] = x[i];
            fy[m] = y[i];
            m++;
        }
    out->n = m;
    int rc = AA_OK;
    if (m >= 3) {
        rc = aa_rank_average(fx, m, rx);
        if (!rc)
            rc = aa_rank_average(fy, m, ry);
    }
    if (m >= 3 && !rc) {
        /* The mean rank is (m + 1) / 2 exactly; centred sums as numpy's corrcoef takes them. */
        double mean = 0.5 * ((double)m + 1.0), sxy = 0, sxx = 0, syy = 0;
        for (size_t i = 0; i < m; i++) {
            double dx = rx[i] - mean, dy = ry[i] - mean;
            sxy += dx * dy;
            sxx += dx * dx;
            syy += dy * dy;
        }
        if (sxx > 0 && syy > 0) {
            double rho = sxy / sqrt(sxx * syy);
            rho = rho > 1 ? 1 : rho < -1 ? -1 : rho;
            out->rho = rho;
            /* P(|T| >= |t|) with n - 2 df is I_{1 - rho^2}((n - 2) / 2, 1 / 2). */
            double df = (double)m - 2, one_minus = (1 - rho) * (1 + rho);
            out->p_value = one_minus <= 0 ? 0 : aa_incomplete_beta(0.5 * df, 0.5, one_minus);
        }
    }
    free(buf);
    return rc;
}
