/* Numerical exactness of aa_e1_at_angle against the independent long-double reference
 * (reference_metric.c): >= 10,000 random kernels and >= 200 stiff or extreme cases, each within
 * 1e-12 relative.
 *
 * The only slack beyond 1e-12 is the unavoidable rounding of the projections: the engine takes
 * double x, y, theta and must form p = x cos(theta) + y sin(theta) in double, an error of a few
 * ulp of |x| + |y| per sample, which moves E1 by |dE1/dp_i| times that. The reference projects in
 * long double; for kernels with a coordinate beyond 16 the test adds the first-order effect of
 * 2^-51 (|x_i| + |y_i|) per sample (a bound on |dE1/dp_i| times that); below 16 there is no
 * slack: the tolerance is exactly 1e-12. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aa_metric.h"
#include "reference_metric.h"

#define REL_TOL 1e-12
#define PI_D 3.14159265358979323846

typedef struct filter_pair {
    const char *label;
    aa_filter engine;
    ref_filter ref;
} filter_pair;

enum {
    F_MITCHELL,
    F_CATMULL_ROM,
    F_BSPLINE,
    F_NOTCH,
    F_BOX,
    F_TENT,
    F_GAUSS,
    F_GAUSS_NARROW,
    F_GAUSS_WIDE,
    F_LANCZOS2,
    F_LANCZOS3,
    F_COUNT
};

static filter_pair filters[F_COUNT];

typedef struct stats {
    size_t cases;
    double max_rel;
    double max_slack;
    char worst[160];
    /* The two methods on their own (aa_e1_at_direction): the quadrature (always held to the
     * same tolerance: the independent check) and the closed form without its fallback (only
     * measured: where it cancels, the automatic choice must have fallen back). */
    double max_rel_quadrature;
    double max_rel_closed_raw;
    size_t closed_rejected;  /* cases where the automatic choice fell back */
    double max_rel_accepted; /* worst closed-form error among the cases it was accepted for */
    double max_error_per_condition; /* closed-form error of E1 / (eps * its condition number) */
} stats;

/* The worst error of the automatic method over every test of this file, printed at the end. */
static double worst_overall;

static uint64_t rng_state;

static uint64_t rng_next(void)
{
    /* splitmix64: deterministic across platforms */
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double rng_uniform(double lo, double hi)
{
    return lo + (hi - lo) * ((double)(rng_next() >> 11) * 0x1.0p-53);
}

static size_t rng_int(size_t lo, size_t hi)
{
    return lo + (size_t)(rng_next() % (uint64_t)(hi - lo + 1));
}

static int setup_filters(void **state)
{
    (void)state;
    aa_error err;
    aa_filter_params par = aa_filter_params_default();
    struct {
        const char *name;
        int idx;
        long double B, C;
    } mn[] = {{"mitchell", F_MITCHELL, 1.0L / 3, 1.0L / 3},
              {"catmull-rom", F_CATMULL_ROM, 0.0L, 0.5L},
              {"bspline", F_BSPLINE, 1.0L, 0.0L},
              {"notch", F_NOTCH, 1.5L, -0.25L}};
    for (size_t i = 0; i < 4; i++) {
        filter_pair *fp = &filters[mn[i].idx];
        fp->label = mn[i].name;
        if (aa_filter_by_name(&fp->engine, mn[i].name, &par, &err) != AA_OK)
            return -1;
        ref_filter_mitchell(&fp->ref, mn[i].B, mn[i].C, 2.0L);
    }
    filters[F_BOX].label = "box r=0.5";
    if (aa_filter_box(&filters[F_BOX].engine, 0.5, &err) != AA_OK)
        return -1;
    ref_filter_box(&filters[F_BOX].ref, 0.5L);
    filters[F_TENT].label = "tent r=1";
    if (aa_filter_tent(&filters[F_TENT].engine, 1.0, &err) != AA_OK)
        return -1;
    ref_filter_tent(&filters[F_TENT].ref, 1.0L);
    struct {
        int idx;
        const char *label;
        double sigma, radius;
    } ga[] = {{F_GAUSS, "gaussian s=0.5 r=2", 0.5, 2.0},
              {F_GAUSS_NARROW, "gaussian s=0.05 r=2", 0.05, 2.0},
              {F_GAUSS_WIDE, "gaussian s=1.5 r=4", 1.5, 4.0}};
    for (size_t i = 0; i < 3; i++) {
        filter_pair *fp = &filters[ga[i].idx];
        fp->label = ga[i].label;
        if (aa_filter_gaussian(&fp->engine, ga[i].sigma, ga[i].radius, &err) != AA_OK)
            return -1;
        ref_filter_gaussian(&fp->ref, ga[i].sigma, ga[i].radius);
    }
    filters[F_LANCZOS2].label = "lanczos a=2";
    if (aa_filter_lanczos(&filters[F_LANCZOS2].engine, 2.0, &err) != AA_OK)
        return -1;
    ref_filter_lanczos(&filters[F_LANCZOS2].ref, 2.0L);
    filters[F_LANCZOS3].label = "lanczos a=3";
    if (aa_filter_lanczos(&filters[F_LANCZOS3].engine, 3.0, &err) != AA_OK)
        return -1;
    ref_filter_lanczos(&filters[F_LANCZOS3].ref, 3.0L);
    return 0;
}

/* First-order effect on E1 of rounding each projection by 2^-51 (|x| + |y|), relative. */
static double projection_slack(const ref_filter *rf, const long double *p, const aa_sample *s,
                               size_t n, long double e1)
{
    long double abs_w = 0.0L, acc = 0.0L;
    for (size_t i = 0; i < n; i++)
        abs_w += fabsl((long double)s[i].w);
    for (size_t i = 0; i < n; i++) {
        long double dp = 0x1.0p-51L * (fabsl((long double)s[i].x) + fabsl((long double)s[i].y));
        long double g = ref_filter_cdf(rf, p[i]);
        long double bound = fabsl((long double)s[i].w) *
                            (2.0L * (fabsl(g) + abs_w) + fabsl((long double)s[i].w)) / (2.0L * e1);
        acc += bound * dp;
    }
    return (double)(acc / e1);
}

static void check_case(const filter_pair *fp, const aa_sample *s, size_t n, double theta,
                       aa_metric_workspace *ws, stats *st, const char *what)
{
    double *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *w = malloc(n * sizeof *w);
    long double *p = malloc(n * sizeof *p);
    for (size_t i = 0; i < n; i++) {
        x[i] = s[i].x;
        y[i] = s[i].y;
        w[i] = s[i].w;
    }
    ref_project(x, y, n, theta, p);
    long double ref = ref_e1_at_angle(&fp->ref, x, y, w, n, theta);
    double got = NAN;
    int rc = aa_e1_at_angle(&fp->engine, s, n, theta, ws, &got);
    double rel = (double)(fabsl((long double)got - ref) / ref);
    double ct, stn, quad = NAN, closed = NAN;
    aa_metric_direction(theta, &ct, &stn);
    long fallbacks = ws->fallback_calls;
    int rc2 = aa_e1_at_direction(&fp->engine, s, n, ct, stn, AA_E1_AUTO, ws, &got);
    bool rejected = ws->fallback_calls != fallbacks;
    int rc3 = aa_e1_at_direction(&fp->engine, s, n, ct, stn, AA_E1_QUADRATURE, ws, &quad);
    int rc4 = aa_e1_at_direction(&fp->engine, s, n, ct, stn, AA_E1_CLOSED, ws, &closed);
    double cond = ws->closed_condition;
    double rel_quad = (double)(fabsl((long double)quad - ref) / ref);
    double rel_closed = (double)(fabsl((long double)closed - ref) / ref);
    if (rel_quad > st->max_rel_quadrature)
        st->max_rel_quadrature = rel_quad;
    if (rel_closed > st->max_rel_closed_raw)
        st->max_rel_closed_raw = rel_closed;
    if (fp->engine.closed_pieces > 0 && cond > 0 &&
        rel_closed / (0x1.0p-52 * cond) > st->max_error_per_condition)
        st->max_error_per_condition = rel_closed / (0x1.0p-52 * cond);
    if (rejected)
        st->closed_rejected++;
    else if (fp->engine.closed_pieces > 0 && rel_closed > st->max_rel_accepted)
        st->max_rel_accepted = rel_closed;
    if (rel > worst_overall)
        worst_overall = rel;
    double extent = 0.0;
    for (size_t i = 0; i < n; i++)
        extent = fmax(extent, fmax(fabs(s[i].x), fabs(s[i].y)));
    /* Below 16 the projection rounding moves E1 by ~1e-15 relative: no slack at all. */
    double slack = extent > 16.0 ? projection_slack(&fp->ref, p, s, n, ref) : 0.0;
    st->cases++;
    if (rel > st->max_rel) {
        st->max_rel = rel;
        snprintf(st->worst, sizeof st->worst, "%s, %s, n=%zu, theta=%.17g", what, fp->label, n,
                 theta);
    }
    if (slack > st->max_slack)
        st->max_slack = slack;
    if (rc != AA_OK || rc2 != AA_OK || rc3 != AA_OK || rc4 != AA_OK || !(rel <= REL_TOL + slack) ||
        !(rel_quad <= REL_TOL + slack)) {
        print_error("E1 mismatch (%s, filter %s, n=%zu, theta=%.17g): engine %.17g, reference "
                    "%.20Lg, rel %.3g (quadrature %.3g, tolerance %.3g), rc %d\n",
                    what, fp->label, n, theta, got, ref, rel, rel_quad, REL_TOL + slack, rc);
        for (size_t i = 0; i < n && i < 8; i++)
            print_error("  sample %zu: %.17g %.17g %.17g\n", i, s[i].x, s[i].y, s[i].w);
        fail();
    }
    free(x);
    free(y);
    free(w);
    free(p);
}

/* Weights in [-0.5, 1] scaled to sum 1 (redrawn while the raw sum is small). */
static void random_weights(aa_sample *s, size_t n)
{
    double sum;
    do {
        sum = 0.0;
        for (size_t i = 0; i < n; i++) {
            s[i].w = rng_uniform(-0.5, 1.0);
            sum += s[i].w;
        }
    } while (fabs(sum) < 0.3);
    for (size_t i = 0; i < n; i++)
        s[i].w /= sum;
}

static void random_kernel(aa_sample *s, size_t n, double extent)
{
    for (size_t i = 0; i < n; i++) {
        s[i].x = rng_uniform(-extent, extent);
        s[i].y = rng_uniform(-extent, extent);
    }
    random_weights(s, n);
}

static void print_stats(const char *title, const stats *st)
{
    print_message("%s: %zu cases, max relative error %.3g (worst: %s), max projection slack "
                  "%.3g; quadrature alone %.3g; closed form alone %.3g, %.3g where accepted, "
                  "fell back in %zu cases; closed-form error / (eps condition) <= %.3g\n",
                  title, st->cases, st->max_rel, st->worst, st->max_slack, st->max_rel_quadrature,
                  st->max_rel_closed_raw, st->max_rel_accepted, st->closed_rejected,
                  st->max_error_per_condition);
}

static void test_random_kernels_default_filter(void **state)
{
    (void)state;
    rng_state = 20260101;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample s[64];
    stats st = {0};
    for (int k = 0; k < 10000; k++) {
        size_t n = rng_int(1, 64);
        random_kernel(s, n, k % 4 == 0 ? 3.0 : 1.5);
        check_case(&filters[F_MITCHELL], s, n, rng_uniform(0.0, PI_D), &ws, &st, "random");
    }
    print_stats("random kernels, mitchell(1/3,1/3)", &st);
    assert_true(st.cases >= 10000);
    aa_metric_workspace_free(&ws);
}

static void test_random_kernels_other_filters(void **state)
{
    (void)state;
    rng_state = 777;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample s[64];
    stats st = {0};
    for (int k = 0; k < 1500; k++) {
        int fi = 1 + k % (F_COUNT - 1);
        size_t n = rng_int(1, (fi == F_LANCZOS2 || fi == F_LANCZOS3) ? 16 : 64);
        random_kernel(s, n, filters[fi].ref.radius);
        check_case(&filters[fi], s, n, rng_uniform(0.0, PI_D), &ws, &st, "random");
    }
    print_stats("random kernels, other filters", &st);
    aa_metric_workspace_free(&ws);
}

/* ---------- stiff and extreme cases ---------- */

static const double exact_angles[3] = {0.0, PI_D / 4, PI_D / 2};

static void test_stiff_cases(void **state)
{
    (void)state;
    rng_state = 99;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample *s = calloc(1024, sizeof *s);
    stats st = {0};
    const filter_pair *mit = &filters[F_MITCHELL];

    /* Ties and coincident samples: duplicated positions; equal x at theta = 0. */
    for (int k = 0; k < 24; k++) {
        size_t n = rng_int(2, 16);
        random_kernel(s, n, 1.5);
        for (size_t i = 1; i < n; i += 2)
            s[i].x = s[i - 1].x, s[i].y = (k % 2) ? s[i - 1].y : s[i].y;
        check_case(mit, s, n, exact_angles[k % 3], &ws, &st, "ties");
        check_case(mit, s, n, rng_uniform(0, PI_D), &ws, &st, "ties");
    }
    /* All samples at one point (E1 of a single step). */
    for (int k = 0; k < 6; k++) {
        size_t n = 5;
        for (size_t i = 0; i < n; i++)
            s[i] = (aa_sample){0.25 * k - 0.5, 0.1, 0.2};
        check_case(mit, s, n, exact_angles[k % 3], &ws, &st, "coincident");
    }
    /* Projections exactly on the filter knots (theta = 0 gives p = x exactly). */
    const double knots[] = {-2.0, -1.0, 0.0, 1.0, 2.0, -0.5, 0.5};
    for (int k = 0; k < 30; k++) {
        size_t n = rng_int(1, 7);
        random_kernel(s, n, 1.0);
        for (size_t i = 0; i < n; i++)
            s[i].x = knots[rng_int(0, 6)];
        check_case(mit, s, n, 0.0, &ws, &st, "on knots");
        for (size_t i = 0; i < n; i++) {
            double t = s[i].x;
            s[i].x = s[i].y;
            s[i].y = t;
        }
        check_case(mit, s, n, PI_D / 2, &ws, &st, "on knots (90)");
    }
    /* Knots of other filters. */
    for (int k = 0; k < 12; k++) {
        const filter_pair *fp = &filters[(int[]){F_BOX, F_TENT, F_GAUSS, F_LANCZOS2}[k % 4]];
        double r = fp->ref.radius;
        size_t n = 4;
        double at[4] = {-r, 0.0, r, 0.5 * r};
        random_kernel(s, n, 1.0);
        for (size_t i = 0; i < n; i++)
            s[i].x = at[(i + (size_t)k) % 4];
        check_case(fp, s, n, 0.0, &ws, &st, "on knots");
    }
    /* Samples far outside the support. */
    for (int k = 0; k < 20; k++) {
        size_t n = rng_int(2, 12);
        random_kernel(s, n, 1.0);
        double far = (double[]){5.0, -7.5, 50.0, -1000.0, 1e4}[k % 5];
        s[0].x = far;
        s[n - 1].y = -far;
        check_case(mit, s, n, rng_uniform(0, PI_D), &ws, &st, "far outside");
        check_case(mit, s, n, exact_angles[k % 3], &ws, &st, "far outside");
    }
    /* Every sample outside the support on one side. */
    for (int k = 0; k < 4; k++) {
        size_t n = 3;
        random_kernel(s, n, 1.0);
        for (size_t i = 0; i < n; i++)
            s[i].x = (k % 2 ? -1 : 1) * (3.0 + i);
        check_case(mit, s, n, 0.0, &ws, &st, "all outside");
    }
    /* Separations of 1e-9 (and a cluster of them). */
    for (int k = 0; k < 20; k++) {
        size_t n = rng_int(2, 10);
        random_kernel(s, n, 1.0);
        double x0 = rng_uniform(-1.0, 1.0);
        for (size_t i = 0; i < n; i++)
            s[i].x = x0 + 1e-9 * (double)i * (k % 2 ? 1.0 : -1.0);
        check_case(mit, s, n, 0.0, &ws, &st, "1e-9 separation");
        check_case(mit, s, n, rng_uniform(0, PI_D), &ws, &st, "1e-9 separation");
    }
    /* Coordinates up to 1e6: at theta = 0 (exact projections) and at random angles. */
    for (int k = 0; k < 20; k++) {
        size_t n = rng_int(2, 8);
        random_kernel(s, n, 1.0);
        double big = (double[]){1e6, -1e6, 3.5e5, 999999.75}[k % 4];
        s[k % n].x = big;
        if (k % 3 == 0)
            s[(k + 1) % n].y = -big;
        check_case(mit, s, n, 0.0, &ws, &st, "1e6 coordinates");
        check_case(mit, s, n, rng_uniform(0, PI_D), &ws, &st, "1e6 coordinates");
    }
    /* Weights that are large and cancel, at distant points. */
    for (int k = 0; k < 6; k++) {
        size_t n = 3;
        s[0] = (aa_sample){-1e6, 0.0, 1e3};
        s[1] = (aa_sample){1e6, 0.0, -1e3};
        s[2] = (aa_sample){0.1 * k, 0.0, 1.0};
        check_case(mit, s, n, 0.0, &ws, &st, "cancelling 1e3 weights");
    }
    /* 1024-sample kernels. */
    for (int k = 0; k < 6; k++) {
        random_kernel(s, 1024, k % 2 ? 2.0 : 0.5);
        check_case(mit, s, 1024, rng_uniform(0, PI_D), &ws, &st, "1024 samples");
        check_case(&filters[1 + k % 5], s, 1024, exact_angles[k % 3], &ws, &st, "1024 samples");
    }
    /* Negative and tiny weights. */
    for (int k = 0; k < 20; k++) {
        size_t n = rng_int(3, 12);
        random_kernel(s, n, 1.0);
        double tiny = (double[]){1e-9, 1e-15, 1e-30, 1e-300, -1e-12}[k % 5];
        s[0].w = tiny;
        s[1].w = -0.75;
        double sum = 0.0;
        for (size_t i = 2; i < n; i++)
            sum += s[i].w;
        for (size_t i = 2; i < n; i++)
            s[i].w *= (1.0 - tiny + 0.75) / sum;
        check_case(mit, s, n, rng_uniform(0, PI_D), &ws, &st, "negative/tiny weights");
        check_case(mit, s, n, exact_angles[k % 3], &ws, &st, "negative/tiny weights");
    }
    /* Single sample anywhere. */
    for (int k = 0; k < 10; k++) {
        s[0] = (aa_sample){rng_uniform(-3, 3), rng_uniform(-3, 3), 1.0};
        check_case(mit, s, 1, rng_uniform(0, PI_D), &ws, &st, "single sample");
    }
    /* Every filter on random kernels at exactly 0, 45 and 90 degrees. */
    for (int fi = 0; fi < F_COUNT; fi++) {
        for (int k = 0; k < 6; k++) {
            size_t n = rng_int(1, 24);
            random_kernel(s, n, filters[fi].ref.radius * 0.75);
            check_case(&filters[fi], s, n, exact_angles[k % 3], &ws, &st, "exact angles");
        }
    }
    print_stats("stiff and extreme cases", &st);
    assert_true(st.cases >= 200);
    free(s);
    aa_metric_workspace_free(&ws);
}

/* ---------- cases aimed at the closed form's cancellation ---------- */

/* x with g(x) = q on the reference, by bisection in long double. */
static double ref_quantile(const ref_filter *rf, long double q)
{
    long double lo = -rf->radius, hi = rf->radius;
    for (int i = 0; i < 200 && hi - lo > 0; i++) {
        long double mid = 0.5L * (lo + hi);
        if (ref_filter_cdf(rf, mid) < q)
            lo = mid;
        else
            hi = mid;
    }
    return (double)(0.5L * (lo + hi));
}

/* n equal weights at the quantiles (i + 1/2) / n of the filter: the best step approximation
 * of g with n equal steps, E1 ~ radius^(1/2) / n, far below the closed form's terms. */
static void quantile_kernel(const ref_filter *rf, aa_sample *s, size_t n, double scale_y)
{
    for (size_t i = 0; i < n; i++)
        s[i] = (aa_sample){ref_quantile(rf, ((long double)i + 0.5L) / (long double)n),
                           scale_y * rng_uniform(-1.0, 1.0), 1.0 / (double)n};
}

static void swap_xy(aa_sample *s, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        double t = s[i].x;
        s[i].x = s[i].y;
        s[i].y = t;
    }
}

static void test_cancellation_cases(void **state)
{
    (void)state;
    rng_state = 1515;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample *s = calloc(1024, sizeof *s);
    stats st = {0};
    aa_error err;
    static filter_pair narrow[3];
    /* Nearly perfect kernels (E1 < 1e-6): filters 1e-7 .. 1e-12 wide, samples at their
     * quantiles; theta = 0 and 90 degrees keep the projections exact. */
    narrow[0].label = "box r=1e-7";
    assert_int_equal(aa_filter_box(&narrow[0].engine, 1e-7, &err), AA_OK);
    ref_filter_box(&narrow[0].ref, 1e-7L);
    narrow[1].label = "mitchell r=1e-9";
    assert_int_equal(aa_filter_mitchell(&narrow[1].engine, 1.0 / 3, 1.0 / 3, 1e-9, &err), AA_OK);
    ref_filter_mitchell(&narrow[1].ref, 1.0L / 3, 1.0L / 3, 1e-9L);
    narrow[2].label = "catmull-rom r=1e-12";
    assert_int_equal(aa_filter_mitchell(&narrow[2].engine, 0, 0.5, 1e-12, &err), AA_OK);
    ref_filter_mitchell(&narrow[2].ref, 0.0L, 0.5L, 1e-12L);
    const size_t sizes[] = {1024, 256, 4};
    size_t tiny = 0;
    for (int fi = 0; fi < 3; fi++) {
        size_t n = sizes[fi];
        quantile_kernel(&narrow[fi].ref, s, n, 0.0);
        double x[1024], y[1024], w[1024];
        for (size_t i = 0; i < n; i++)
            x[i] = s[i].x, y[i] = s[i].y, w[i] = s[i].w;
        long double e1 = ref_e1_at_angle(&narrow[fi].ref, x, y, w, n, 0.0);
        tiny += e1 < 1e-6L;
        check_case(&narrow[fi], s, n, 0.0, &ws, &st, "nearly perfect (E1 < 1e-6)");
        swap_xy(s, n);
        check_case(&narrow[fi], s, n, PI_D / 2, &ws, &st, "nearly perfect (E1 < 1e-6)");
    }
    assert_int_equal(tiny, 3);
    /* Quantile kernels of the reference filters of radius 2 (E1 ~ 1e-2 .. 1e-4). */
    for (int k = 0; k < 12; k++) {
        const filter_pair *fp = &filters[(int[]){F_MITCHELL, F_CATMULL_ROM, F_BOX, F_TENT}[k % 4]];
        size_t n = (size_t[]){16, 64, 256}[k % 3] * (k >= 9 ? 4 : 1);
        quantile_kernel(&fp->ref, s, n, 1.0);
        check_case(fp, s, n, 0.0, &ws, &st, "quantile kernel");
        swap_xy(s, n);
        check_case(fp, s, n, PI_D / 2, &ws, &st, "quantile kernel");
    }
    /* Every sample beyond +-2 (outside the support), on one side or both, at any angle: the
     * samples are placed along the edge normal with a random offset along the edge. */
    for (int k = 0; k < 60; k++) {
        const filter_pair *fp = &filters[(int[]){F_MITCHELL, F_NOTCH, F_BOX, F_TENT}[k % 4]];
        double r = fp->ref.radius, th = k % 3 == 0 ? exact_angles[k % 3] : rng_uniform(0, PI_D);
        size_t n = rng_int(1, 16);
        double far = (double[]){2.0 + 1e-9, 2.5, 10.0, 1e3}[k % 4];
        random_weights(s, n);
        for (size_t i = 0; i < n; i++) {
            double side = (k % 5 == 0) ? 1.0 : (k % 5 == 1 ? -1.0 : (rng_int(0, 1) ? 1.0 : -1.0));
            double p = side * fmax(r, 2.0) * (1.0 + 1e-12) + side * rng_uniform(0.0, far - 2.0);
            double q = rng_uniform(-1.0, 1.0);
            s[i].x = p * cos(th) - q * sin(th);
            s[i].y = p * sin(th) + q * cos(th);
        }
        check_case(fp, s, n, th, &ws, &st, "all beyond +-2");
    }
    print_stats("cancellation cases (nearly perfect, quantile kernels, all beyond +-2)", &st);
    /* The detection is needed: some of these cancel beyond 1e-12 in the closed form alone, and
     * the automatic choice fell back there. */
    assert_true(st.max_rel_closed_raw > REL_TOL);
    assert_true(st.closed_rejected > 0);
    assert_true(st.max_rel_accepted <= REL_TOL);
    free(s);
    aa_metric_workspace_free(&ws);
}

/* The sorted order a workspace remembers between calls (metric.h) never changes a result: the
 * same kernel at angles in any order, and other kernels of the same size in between, give the
 * same bits as a fresh workspace. */
static void test_order_reuse_is_invisible(void **state)
{
    (void)state;
    rng_state = 8080;
    aa_metric_workspace shared, fresh;
    aa_metric_workspace_init(&shared);
    aa_sample s[3][48];
    for (int k = 0; k < 3; k++)
        random_kernel(s[k], 48, 2.0);
    for (int i = 0; i < 600; i++) {
        int k = (int)rng_int(0, 2);
        double th = i % 3 ? rng_uniform(0, PI_D) : (i % 36) * (PI_D / 36), a = NAN, b = NAN;
        assert_int_equal(aa_e1_at_angle(&filters[F_MITCHELL].engine, s[k], 48, th, &shared, &a),
                         AA_OK);
        aa_metric_workspace_init(&fresh);
        assert_int_equal(aa_e1_at_angle(&filters[F_MITCHELL].engine, s[k], 48, th, &fresh, &b),
                         AA_OK);
        aa_metric_workspace_free(&fresh);
        assert_true(a == b);
    }
    aa_metric_workspace_free(&shared);
}

/* The E1 that aa_e1_gradient_at_angle reports is the same number, and both methods give the
 * same gradient (the quadrature's prefix integrals against the closed form's). */
static void test_gradient_e1_matches(void **state)
{
    (void)state;
    rng_state = 4242;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample s[64];
    double dx[64], dy[64], dw[64], qx[64], qy[64], qw[64], worst = 0;
    for (int k = 0; k < 300; k++) {
        size_t n = rng_int(1, 64);
        const filter_pair *fp = &filters[k % 3 == 0 ? F_MITCHELL : (k % 3 == 1 ? F_BOX : F_TENT)];
        random_kernel(s, n, k % 5 == 0 ? 4.0 : 1.5);
        double th = rng_uniform(0, PI_D), a = NAN, b = NAN, c = NAN, ct, st;
        assert_int_equal(aa_e1_at_angle(&fp->engine, s, n, th, &ws, &a), AA_OK);
        assert_int_equal(aa_e1_gradient_at_angle(&fp->engine, s, n, th, &ws, &b, dx, dy, dw),
                         AA_OK);
        assert_true(fabs(a - b) <= 1e-14 * a);
        aa_metric_direction(th, &ct, &st);
        assert_int_equal(aa_e1_gradient_at_direction(&fp->engine, s, n, ct, st, AA_E1_QUADRATURE,
                                                     &ws, &c, qx, qy, qw),
                         AA_OK);
        double scale = 0;
        for (size_t i = 0; i < n; i++)
            scale = fmax(scale, fmax(fabs(qx[i]) + fabs(qy[i]), fabs(qw[i])));
        for (size_t i = 0; i < n; i++) {
            double e = fmax(fabs(dx[i] - qx[i]) + fabs(dy[i] - qy[i]), fabs(dw[i] - qw[i]));
            worst = fmax(worst, e / fmax(scale, 1e-300));
        }
    }
    print_message("gradient, closed form vs quadrature: max difference %.3g of the largest "
                  "component\n",
                  worst);
    assert_true(worst <= 1e-11);
    aa_metric_workspace_free(&ws);
}

/* The whole Mitchell-Netravali family: random (B, C) and radius (the cubic stretched). */
static void test_random_mitchell_family(void **state)
{
    (void)state;
    rng_state = 1234;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample s[64];
    stats st = {0};
    static filter_pair fp;
    fp.label = "mitchell(B,C,r)";
    for (int k = 0; k < 40; k++) {
        double B = rng_uniform(-0.5, 1.5), C = rng_uniform(-0.5, 1.0), r = rng_uniform(0.5, 4.0);
        aa_error err;
        assert_int_equal(aa_filter_mitchell(&fp.engine, B, C, r, &err), AA_OK);
        ref_filter_mitchell(&fp.ref, B, C, r);
        for (int j = 0; j < 25; j++) {
            size_t n = rng_int(1, 48);
            random_kernel(s, n, 0.75 * r);
            check_case(&fp, s, n, rng_uniform(0.0, PI_D), &ws, &st, "random family");
        }
    }
    print_stats("random kernels, random Mitchell-Netravali (B, C, radius)", &st);
    aa_metric_workspace_free(&ws);
}

/* A non-finite angle cannot give a finite E1 (aa_evaluate rejects it as "angles[i]"). */
static void test_non_finite_angle(void **state)
{
    (void)state;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample s[2] = {{0.1, 0.2, 0.5}, {-0.1, 0.3, 0.5}};
    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int i = 0; i < 3; i++) {
        double e = 0.0;
        int rc = aa_e1_at_angle(&filters[F_MITCHELL].engine, s, 2, bad[i], &ws, &e);
        if (rc == AA_OK && !isnan(e)) {
            print_error("theta = %g: rc %d, E1 %.17g (expected an error or NaN)\n", bad[i], rc, e);
            fail();
        }
    }
    aa_metric_workspace_free(&ws);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_kernels_default_filter),
        cmocka_unit_test(test_random_kernels_other_filters),
        cmocka_unit_test(test_random_mitchell_family),
        cmocka_unit_test(test_stiff_cases),
        cmocka_unit_test(test_cancellation_cases),
        cmocka_unit_test(test_non_finite_angle),
        cmocka_unit_test(test_gradient_e1_matches),
        cmocka_unit_test(test_order_reuse_is_invisible),
    };
    int failed = cmocka_run_group_tests(tests, setup_filters, NULL);
    print_message("worst relative error of E1 (automatic method) over every case: %.3g\n",
                  worst_overall);
    return failed;
}
