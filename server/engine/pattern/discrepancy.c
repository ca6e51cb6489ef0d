/* Hickernell's L2 discrepancies (centred, wrap-around, mixture) and the L2-star discrepancy in
 * closed form for d = 2, term for term as scipy.stats.qmc.discrepancy (Fang, Li & Sudjianto,
 * "Design and Modeling for Computer Experiments", 2006, and Zhou, Fang & Ning, "Mixture
 * discrepancy for quasi-random point sets", 2013). One pass over the pairs i < j (each
 * counted twice) and the diagonal; sums compensated (Neumaier), combined in long double. */
#include "point_set.h"

#include <math.h>

typedef struct compensated {
    double sum, c;
} compensated;

static inline void add(compensated *a, double t)
{
    double s = a->sum + t;
    a->c += fabs(a->sum) >= fabs(t) ? (a->sum - s) + t : (t - s) + a->sum;
    a->sum = s;
}

/* The compensated pair (sum, c) is good to far more than a double (Neumaier: the error is
 * O(n eps^2) of the terms); it is kept in long double for the final combination. */
static inline long double total(const compensated *a)
{
    return (long double)a->sum + (long double)a->c;
}

/* The pair terms of the four discrepancies for points a and b (products over x and y). */
typedef struct pair_terms {
    double cd, wd, md, l2;
} pair_terms;

static inline pair_terms pair_term(aa_point a, aa_point b)
{
    double ax = fabs(a.x - 0.5), ay = fabs(a.y - 0.5), bx = fabs(b.x - 0.5), by = fabs(b.y - 0.5);
    double dx = fabs(a.x - b.x), dy = fabs(a.y - b.y);
    pair_terms t;
    t.cd = (1 + 0.5 * ax + 0.5 * bx - 0.5 * dx) * (1 + 0.5 * ay + 0.5 * by - 0.5 * dy);
    t.wd = (1.5 - dx + dx * dx) * (1.5 - dy + dy * dy);
    t.md = (15.0 / 8 - 0.25 * ax - 0.25 * bx - 0.75 * dx + 0.5 * dx * dx) *
           (15.0 / 8 - 0.25 * ay - 0.25 * by - 0.75 * dy + 0.5 * dy * dy);
    t.l2 = (1 - fmax(a.x, b.x)) * (1 - fmax(a.y, b.y));
    return t;
}

static double root(double sq)
{
    return sq > 0 ? sqrt(sq) : 0;
}

int aa_point_set_discrepancy(const aa_point *pts, size_t n, aa_discrepancy *out, aa_error *err)
{
    int rc = aa_point_set_check(pts, n, err);
    if (rc)
        return rc;
    compensated cd1 = {0}, md1 = {0}, l21 = {0}, cd2 = {0}, wd2 = {0}, md2 = {0}, l22 = {0};
    for (size_t i = 0; i < n; i++) {
        aa_point a = pts[i];
        double ax = fabs(a.x - 0.5), ay = fabs(a.y - 0.5);
        add(&cd1, (1 + 0.5 * ax - 0.5 * ax * ax) * (1 + 0.5 * ay - 0.5 * ay * ay));
        /* 5/3 is not a double: rounded once, it would bias every term alike (1e-12 of MD^2 at
         * 1,024 points); this O(n) sum is taken in long double. */
        add(&md1, (double)((5.0L / 3 - 0.25L * ax - 0.25L * ax * ax) *
                           (5.0L / 3 - 0.25L * ay - 0.25L * ay * ay)));
        add(&l21, (1 - a.x * a.x) * (1 - a.y * a.y));
        pair_terms d = pair_term(a, a);
        add(&cd2, d.cd);
        add(&wd2, d.wd);
        add(&md2, d.md);
        add(&l22, d.l2);
        for (size_t j = i + 1; j < n; j++) {
            pair_terms t = pair_term(a, pts[j]);
            add(&cd2, 2 * t.cd);
            add(&wd2, 2 * t.wd);
            add(&md2, 2 * t.md);
            add(&l22, 2 * t.l2);
        }
    }
    /* Each square is a constant minus sums of its size (about 1.2 to 2.5) giving a result as
     * small as 1e-5: combined in long double (64-bit mantissa on x86-64), the cancellation loses
     * nothing of the double result. */
    long double N = (long double)n, N2 = N * N;
    out->centered_sq = (double)((169.0L / 144) - 2 * total(&cd1) / N + total(&cd2) / N2);
    out->wrap_around_sq = (double)(-(16.0L / 9) + total(&wd2) / N2);
    out->mixture_sq = (double)((361.0L / 144) - 2 * total(&md1) / N + total(&md2) / N2);
    out->l2_star_sq = (double)(1.0L / 9 - total(&l21) / (2 * N) + total(&l22) / N2);
    out->centered = root(out->centered_sq);
    out->wrap_around = root(out->wrap_around_sq);
    out->mixture = root(out->mixture_sq);
    out->l2_star = root(out->l2_star_sq);
    return AA_OK;
}
