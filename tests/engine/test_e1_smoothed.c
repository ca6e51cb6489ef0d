/* The kink-smoothed E1 (aa_e1_smoothed_at_direction, e1_smoothed.c): its value against the
 * independent long-double reference E1 plus the Huber correction summed over all pairs in long
 * double (1e-12 relative); its gradient against central differences of itself (1e-6 relative);
 * that it is continuously differentiable across a crossing of two projections where the exact
 * E1 is not (the claim it exists for: E1^2 has a slope jump of 2 |w_i w_j| there); and that
 * width 0 gives the exact functions bit for bit. Kernels put some pairs of projections closer
 * than the width, with weights of both signs. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aa_core.h"
#include "aa_metric.h"
#include "reference_metric.h"

#define MAX_N 24

static aa_rng rng;

static double rng_uniform(double lo, double hi)
{
    return lo + (hi - lo) * aa_rng_uniform(&rng);
}

/* n samples in [-1.5, 1.5]^2, weights of both signs summing to 1; every third sample is put
 * within +-h/2 of the previous one's projection on (c, s) (moved along the edge direction). */
static void kernel_with_close_pairs(aa_sample *k, size_t n, double c, double s, double h)
{
    double sum = 0;
    for (size_t i = 0; i < n; i++) {
        k[i] = (aa_sample){rng_uniform(-1.5, 1.5), rng_uniform(-1.5, 1.5), rng_uniform(-0.4, 1)};
        if (i % 3 == 2) {
            double along = rng_uniform(-1, 1), off = rng_uniform(-h / 2, h / 2);
            k[i].x = k[i - 1].x - s * along + c * off;
            k[i].y = k[i - 1].y + c * along + s * off;
        }
        sum += k[i].w;
    }
    for (size_t i = 0; i < n; i++)
        k[i].w /= sum;
}

/* Independent: the reference E1^2 plus C = -sum_{i<j, |d| < h} w_i w_j (h - |d|)^2 / (2h)
 * over all pairs (no sorting), all in long double. */
static long double reference_smoothed_e1(const ref_filter *rf, const aa_sample *k, size_t n,
                                         double theta, double h)
{
    double x[MAX_N], y[MAX_N], w[MAX_N];
    long double p[MAX_N], lw[MAX_N];
    for (size_t i = 0; i < n; i++) {
        x[i] = k[i].x;
        y[i] = k[i].y;
        w[i] = k[i].w;
        lw[i] = k[i].w;
    }
    (void)w;
    ref_project(x, y, n, theta, p);
    long double sq = ref_e1_squared(rf, p, lw, n);
    for (size_t i = 0; i < n; i++)
        for (size_t j = i + 1; j < n; j++) {
            long double d = fabsl(p[i] - p[j]);
            if (d < h)
                sq -= lw[i] * lw[j] * (h - d) * (h - d) / (2 * (long double)h);
        }
    return sqrtl(sq);
}

static void test_value_against_reference(void **state)
{
    (void)state;
    aa_filter f;
    aa_filter_default(&f);
    ref_filter rf;
    ref_filter_mitchell(&rf, 1.0L / 3, 1.0L / 3, 2.0L);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    double worst = 0;
    int corrected = 0;
    for (int trial = 0; trial < 200; trial++) {
        size_t n = 3 + (size_t)(trial % (MAX_N - 2));
        double theta = rng_uniform(0, 3.14159265358979), h = rng_uniform(0.001, 0.3);
        double c, s, e1, e1s, exact;
        aa_metric_direction(theta, &c, &s);
        aa_sample k[MAX_N];
        kernel_with_close_pairs(k, n, c, s, h);
        assert_int_equal(aa_e1_smoothed_at_direction(&f, k, n, c, s, h, &ws, &e1, &e1s), AA_OK);
        assert_int_equal(aa_e1_at_direction(&f, k, n, c, s, AA_E1_AUTO, &ws, &exact), AA_OK);
        assert_true(e1 == exact);
        corrected += e1s != e1;
        long double ref = reference_smoothed_e1(&rf, k, n, theta, h);
        double rel = (double)(fabsl((long double)e1s - ref) / ref);
        worst = fmax(worst, rel);
        if (!(rel <= 1e-12))
            fail_msg("n %zu h %g: smoothed E1 %.17g, reference %.17Lg (rel %.2e)", n, h, e1s, ref,
                     rel);
    }
    assert_true(corrected >= 150); /* the pairs within h were there */
    print_message("smoothed E1 vs reference: worst relative error %.2e (%d of 200 corrected)\n",
                  worst, corrected);
    aa_metric_workspace_free(&ws);
}

static double smoothed_of(const aa_filter *f, const aa_sample *k, size_t n, double c, double s,
                          double h, aa_metric_workspace *ws)
{
    double e1, e1s;
    assert_int_equal(aa_e1_smoothed_at_direction(f, k, n, c, s, h, ws, &e1, &e1s), AA_OK);
    return e1s;
}

static void test_gradient_against_differences(void **state)
{
    (void)state;
    aa_filter f;
    aa_filter_default(&f);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    for (int trial = 0; trial < 60; trial++) {
        size_t n = 4 + (size_t)(trial % 12);
        double theta = rng_uniform(0, 3.14159265358979), h = rng_uniform(0.01, 0.3);
        double c, s, e1, e1s, dx[MAX_N], dy[MAX_N], dw[MAX_N];
        aa_metric_direction(theta, &c, &s);
        aa_sample k[MAX_N];
        kernel_with_close_pairs(k, n, c, s, h);
        assert_int_equal(
            aa_e1_smoothed_gradient_at_direction(&f, k, n, c, s, h, &ws, &e1, &e1s, dx, dy, dw),
            AA_OK);
        assert_true(e1s == smoothed_of(&f, k, n, c, s, h, &ws));
        const double step = 1e-6;
        for (size_t i = 0; i < n; i++) {
            /* weights along e_i - 1/n (sum kept): the projected gradient's component */
            aa_sample t[MAX_N];
            double fd[3];
            for (int v = 0; v < 3; v++) {
                memcpy(t, k, n * sizeof *t);
                double *q = v == 0 ? &t[i].x : v == 1 ? &t[i].y : NULL;
                if (q)
                    *q += step;
                else
                    for (size_t j = 0; j < n; j++)
                        t[j].w += step * ((j == i) - 1.0 / (double)n);
                double up = smoothed_of(&f, t, n, c, s, h, &ws);
                memcpy(t, k, n * sizeof *t);
                if (q) {
                    q = v == 0 ? &t[i].x : &t[i].y;
                    *q -= step;
                } else {
                    for (size_t j = 0; j < n; j++)
                        t[j].w -= step * ((j == i) - 1.0 / (double)n);
                }
                fd[v] = (up - smoothed_of(&f, t, n, c, s, h, &ws)) / (2 * step);
            }
            double got[3] = {dx[i], dy[i], dw[i] - 0}, scale = 1e-3;
            /* dw is the projected gradient; the directional derivative along e_i - 1/n is
             * dw_i - mean(dw) = dw_i (its mean is 0) */
            for (int v = 0; v < 3; v++)
                if (!(fabs(got[v] - fd[v]) <= 1e-6 * fmax(fabs(fd[v]), scale)))
                    fail_msg("trial %d sample %zu %s: analytic %.12g, differences %.12g", trial, i,
                             v == 0   ? "x"
                             : v == 1 ? "y"
                                      : "w",
                             got[v], fd[v]);
        }
    }
    aa_metric_workspace_free(&ws);
}

/* Slopes of E1 in the offset d of sample 1 from sample 0's projection, left and right of d = 0
 * (one-sided differences of step 1e-7, taken from d = -+1e-9 so no difference spans the
 * crossing). */
static void slopes_at_crossing(double h, double *left, double *right)
{
    aa_filter f;
    aa_filter_default(&f);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    double c, s;
    aa_metric_direction(0.4, &c, &s);
    /* samples 0 and 1 of opposite weights, sample 1 moved along the normal by d */
    aa_sample k[5] = {
        {0.2, 0.1, 0.6}, {0, 0, -0.15}, {-0.7, 0.5, 0.25}, {0.9, -0.4, 0.2}, {-0.3, -0.8, 0.1}};
    double along = 0.6, base_x = k[0].x - s * along, base_y = k[0].y + c * along;
    double d[4] = {-1e-9 - 1e-7, -1e-9, 1e-9, 1e-9 + 1e-7}, v[4];
    for (int j = 0; j < 4; j++) {
        k[1].x = base_x + c * d[j];
        k[1].y = base_y + s * d[j];
        v[j] = smoothed_of(&f, k, 5, c, s, h, &ws);
    }
    *left = (v[1] - v[0]) / (d[1] - d[0]);
    *right = (v[3] - v[2]) / (d[3] - d[2]);
    aa_metric_workspace_free(&ws);
}

static void test_smooth_across_crossing(void **state)
{
    (void)state;
    double l0, r0, lh, rh;
    slopes_at_crossing(0, &l0, &r0);
    slopes_at_crossing(0.05, &lh, &rh);
    /* exact: the slope of E1^2 jumps by 2 |w_0 w_1| = 0.18 (E1's by 0.18 / (2 E1)) */
    assert_true(r0 - l0 > 0.01);
    assert_true(fabs(rh - lh) < 1e-4 * fmax(fabs(rh), 1e-2));
    print_message("slope of E1 across a crossing: exact %.6f | %.6f, smoothed %.6f | %.6f\n", l0,
                  r0, lh, rh);
}

static void test_width_zero_and_errors(void **state)
{
    (void)state;
    aa_filter f;
    aa_filter_default(&f);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample k[MAX_N];
    double c, s;
    aa_metric_direction(1.1, &c, &s);
    kernel_with_close_pairs(k, 12, c, s, 0.05);
    double e1, e1s, ex, dx[MAX_N], dy[MAX_N], dw[MAX_N], ex_dx[MAX_N], ex_dy[MAX_N], ex_dw[MAX_N];
    assert_int_equal(
        aa_e1_smoothed_gradient_at_direction(&f, k, 12, c, s, 0, &ws, &e1, &e1s, dx, dy, dw),
        AA_OK);
    assert_int_equal(
        aa_e1_gradient_at_direction(&f, k, 12, c, s, AA_E1_AUTO, &ws, &ex, ex_dx, ex_dy, ex_dw),
        AA_OK);
    assert_true(e1 == ex && e1s == ex);
    assert_memory_equal(dx, ex_dx, 12 * sizeof *dx);
    assert_memory_equal(dy, ex_dy, 12 * sizeof *dy);
    assert_memory_equal(dw, ex_dw, 12 * sizeof *dw);
    assert_int_equal(aa_e1_smoothed_at_direction(&f, k, 12, c, s, -0.1, &ws, &e1, &e1s), AA_EINVAL);
    assert_int_equal(aa_e1_smoothed_at_direction(&f, k, 12, c, s, NAN, &ws, &e1, &e1s), AA_EINVAL);
    assert_int_equal(
        aa_e1_smoothed_gradient_at_direction(&f, k, 12, c, s, INFINITY, &ws, &e1, &e1s, dx, dy, dw),
        AA_EINVAL);
    /* no pair within the width: the exact value */
    aa_sample apart[3] = {{-1, 0, 0.3}, {0, 0, 0.4}, {1, 0, 0.3}};
    assert_int_equal(aa_e1_smoothed_at_direction(&f, apart, 3, 1, 0, 0.5, &ws, &e1, &e1s), AA_OK);
    assert_true(e1s == e1);
    aa_metric_workspace_free(&ws);
}

int main(void)
{
    aa_rng_seed(&rng, 41, 0);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_value_against_reference),
        cmocka_unit_test(test_gradient_against_differences),
        cmocka_unit_test(test_smooth_across_crossing),
        cmocka_unit_test(test_width_zero_and_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
