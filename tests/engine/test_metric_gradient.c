/* Analytic gradients of E1(theta) (aa_e1_gradient_at_angle) against central differences of
 * the engine's own E1 (1e-6 relative) and against the reference formulas evaluated with the
 * independent long-double filter and quadrature (1e-10 relative). Also checks the reference
 * formulas themselves (docs/metric.md) against central differences of the reference E1, so the
 * derivation is verified independently of the engine.
 *
 * Weights move along e_i - 1/n, which keeps sum(w) = 1: the directional derivative along it is
 * raw_i - mean(raw), exactly the projected dw the engine returns.
 * Kernels are drawn away from ties (projections >= 1e-3 apart) so E1 is smooth there. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "aa_metric.h"
#include "reference_metric.h"

#define PI_D 3.14159265358979323846
#define MAX_N 32

static uint64_t rng_state;

static uint64_t rng_next(void)
{
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double rng_uniform(double lo, double hi)
{
    return lo + (hi - lo) * ((double)(rng_next() >> 11) * 0x1.0p-53);
}

typedef struct gfilter {
    const char *name;
    aa_filter engine;
    ref_filter ref;
    double extent; /* keep projections inside the smooth part of g */
} gfilter;

static gfilter gfilters[4];

static int setup(void **state)
{
    (void)state;
    aa_error err;
    aa_filter_params par = aa_filter_params_default();
    const char *names[3] = {"mitchell", "catmull-rom", "bspline"};
    const long double bc[3][2] = {{1.0L / 3, 1.0L / 3}, {0.0L, 0.5L}, {1.0L, 0.0L}};
    for (int i = 0; i < 3; i++) {
        gfilters[i].name = names[i];
        if (aa_filter_by_name(&gfilters[i].engine, names[i], &par, &err) != AA_OK)
            return -1;
        ref_filter_mitchell(&gfilters[i].ref, bc[i][0], bc[i][1], 2.0L);
        gfilters[i].extent = 1.5;
    }
    gfilters[3].name = "gaussian";
    if (aa_filter_gaussian(&gfilters[3].engine, 0.5, 2.0, &err) != AA_OK)
        return -1;
    ref_filter_gaussian(&gfilters[3].ref, 0.5L, 2.0L);
    gfilters[3].extent = 1.2; /* g' jumps at the truncation +-2: stay inside */
    return 0;
}

/* Random kernel with projections at theta pairwise >= 1e-3 apart, weights sum 1. */
static void random_kernel(aa_sample *s, size_t n, double extent, double theta)
{
    double c = cos(theta), sn = sin(theta);
    for (;;) {
        double sum = 0.0;
        for (size_t i = 0; i < n; i++) {
            s[i].x = rng_uniform(-extent, extent);
            s[i].y = rng_uniform(-extent, extent);
            s[i].w = rng_uniform(-0.3, 1.0);
            sum += s[i].w;
        }
        if (fabs(sum) < 0.3)
            continue;
        int ok = 1;
        for (size_t i = 0; i < n && ok; i++) {
            s[i].w /= sum;
            double pi = s[i].x * c + s[i].y * sn;
            for (size_t j = 0; j < i && ok; j++)
                ok = fabs(pi - (s[j].x * c + s[j].y * sn)) >= 1e-3;
        }
        if (ok)
            return;
    }
}

static double e1_of(const aa_filter *f, const aa_sample *s, size_t n, double theta,
                    aa_metric_workspace *ws)
{
    double e = NAN;
    assert_int_equal(aa_e1_at_angle(f, s, n, theta, ws, &e), AA_OK);
    return e;
}

static double max_rel_seen;

static void expect_close(double analytic, double reference, double scale, double tol,
                         const char *what, size_t i)
{
    double err = fabs(analytic - reference) / fmax(fabs(reference), scale);
    if (err > max_rel_seen)
        max_rel_seen = err;
    if (!(err <= tol)) {
        print_error("%s[%zu]: analytic %.15g, expected %.15g, rel %.3g > %.1g\n", what, i, analytic,
                    reference, err, tol);
        fail();
    }
}

static void test_gradient_vs_central_differences(void **state)
{
    (void)state;
    rng_state = 31337;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample s[MAX_N], t[MAX_N];
    double dx[MAX_N], dy[MAX_N], dw[MAX_N];
    const double h = 1e-6;
    max_rel_seen = 0.0;
    size_t checked = 0;
    for (int k = 0; k < 400; k++) {
        const gfilter *gf = &gfilters[k % 4];
        size_t n = 2 + (size_t)(rng_next() % (MAX_N - 1));
        double theta = k < 12 ? (double[]){0.0, PI_D / 4, PI_D / 2}[k % 3] : rng_uniform(0, PI_D);
        random_kernel(s, n, gf->extent, theta);
        double e1 = NAN;
        assert_int_equal(aa_e1_gradient_at_angle(&gf->engine, s, n, theta, &ws, &e1, dx, dy, dw),
                         AA_OK);
        double scale = 0.0;
        for (size_t i = 0; i < n; i++)
            scale = fmax(scale, fmax(fabs(dx[i]), fmax(fabs(dy[i]), fabs(dw[i]))));
        /* components far below the gradient's size are judged relative to 1e-3 of it */
        scale *= 1e-3;
        for (size_t i = 0; i < n; i++) {
            memcpy(t, s, n * sizeof *s);
            t[i].x = s[i].x + h;
            double ep = e1_of(&gf->engine, t, n, theta, &ws);
            t[i].x = s[i].x - h;
            double em = e1_of(&gf->engine, t, n, theta, &ws);
            expect_close(dx[i], (ep - em) / (2 * h), scale, 1e-6, "dx", i);

            memcpy(t, s, n * sizeof *s);
            t[i].y = s[i].y + h;
            ep = e1_of(&gf->engine, t, n, theta, &ws);
            t[i].y = s[i].y - h;
            em = e1_of(&gf->engine, t, n, theta, &ws);
            expect_close(dy[i], (ep - em) / (2 * h), scale, 1e-6, "dy", i);

            for (int sign = -1; sign <= 1; sign += 2) {
                for (size_t j = 0; j < n; j++)
                    t[j] = s[j], t[j].w = s[j].w + sign * h * ((j == i ? 1.0 : 0.0) - 1.0 / n);
                if (sign < 0)
                    em = e1_of(&gf->engine, t, n, theta, &ws);
                else
                    ep = e1_of(&gf->engine, t, n, theta, &ws);
            }
            expect_close(dw[i], (ep - em) / (2 * h), scale, 1e-6, "dw", i);
            checked += 3;
        }
    }
    print_message("gradient vs central differences (h = 1e-6): %zu components, max relative "
                  "error %.3g\n",
                  checked, max_rel_seen);
    aa_metric_workspace_free(&ws);
}

/* dx = cos(theta) dE1/dp, dy = sin(theta) dE1/dp, dw = raw - mean(raw), with dE1/dp and raw from
 * the reference's own g and quadrature. */
static void test_gradient_vs_reference_formulas(void **state)
{
    (void)state;
    rng_state = 8080;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample s[MAX_N];
    double dx[MAX_N], dy[MAX_N], dw[MAX_N];
    long double p[MAX_N], w[MAX_N], dp[MAX_N], raw[MAX_N], e1r;
    max_rel_seen = 0.0;
    for (int k = 0; k < 400; k++) {
        const gfilter *gf = &gfilters[k % 4];
        size_t n = 1 + (size_t)(rng_next() % MAX_N);
        double theta = rng_uniform(0, PI_D);
        random_kernel(s, n, gf->extent, theta);
        double e1 = NAN;
        assert_int_equal(aa_e1_gradient_at_angle(&gf->engine, s, n, theta, &ws, &e1, dx, dy, dw),
                         AA_OK);
        double xs[MAX_N], ys[MAX_N];
        for (size_t i = 0; i < n; i++)
            xs[i] = s[i].x, ys[i] = s[i].y, w[i] = s[i].w;
        ref_project(xs, ys, n, theta, p);
        ref_e1_gradient_1d(&gf->ref, p, w, n, &e1r, dp, raw);
        long double mean = 0.0L;
        for (size_t i = 0; i < n; i++)
            mean += raw[i] / n;
        double scale = 0.0;
        for (size_t i = 0; i < n; i++)
            scale = fmax(scale, fmax(fabs(dx[i]), fmax(fabs(dy[i]), fabs(dw[i]))));
        scale *= 1e-4;
        for (size_t i = 0; i < n; i++) {
            expect_close(dx[i], (double)(cosl(theta) * dp[i]), scale, 1e-10, "dx", i);
            expect_close(dy[i], (double)(sinl(theta) * dp[i]), scale, 1e-10, "dy", i);
            expect_close(dw[i], (double)(raw[i] - mean), scale, 1e-10, "dw", i);
        }
    }
    print_message("gradient vs reference formulas: max relative error %.3g\n", max_rel_seen);
    aa_metric_workspace_free(&ws);
}

/* The derivation itself: reference formulas vs central differences of the reference E1 in long
 * double (no engine code involved). */
static void test_reference_formulas_vs_reference_differences(void **state)
{
    (void)state;
    rng_state = 5;
    aa_sample s[MAX_N];
    long double p[MAX_N], w[MAX_N], q[MAX_N], v[MAX_N], dp[MAX_N], raw[MAX_N], e1r;
    const long double h = 1e-7L;
    max_rel_seen = 0.0;
    for (int k = 0; k < 60; k++) {
        const gfilter *gf = &gfilters[k % 4];
        size_t n = 2 + (size_t)(rng_next() % 12);
        random_kernel(s, n, gf->extent, 0.0);
        for (size_t i = 0; i < n; i++)
            p[i] = s[i].x, w[i] = s[i].w;
        ref_e1_gradient_1d(&gf->ref, p, w, n, &e1r, dp, raw);
        long double mean = 0.0L;
        for (size_t i = 0; i < n; i++)
            mean += raw[i] / n;
        for (size_t i = 0; i < n; i++) {
            memcpy(q, p, n * sizeof *q);
            q[i] = p[i] + h;
            long double ep = sqrtl(ref_e1_squared(&gf->ref, q, w, n));
            q[i] = p[i] - h;
            long double em = sqrtl(ref_e1_squared(&gf->ref, q, w, n));
            expect_close((double)dp[i], (double)((ep - em) / (2 * h)), 1e-6, 1e-7, "ref dp", i);
            for (size_t j = 0; j < n; j++)
                v[j] = w[j] + h * ((j == i ? 1.0L : 0.0L) - 1.0L / n);
            ep = sqrtl(ref_e1_squared(&gf->ref, p, v, n));
            for (size_t j = 0; j < n; j++)
                v[j] = w[j] - h * ((j == i ? 1.0L : 0.0L) - 1.0L / n);
            em = sqrtl(ref_e1_squared(&gf->ref, p, v, n));
            expect_close((double)(raw[i] - mean), (double)((ep - em) / (2 * h)), 1e-6, 1e-7,
                         "ref dw", i);
        }
    }
    print_message("reference formulas vs reference central differences: max relative error "
                  "%.3g\n",
                  max_rel_seen);
}

/* NULL gradient outputs are allowed, and the others are unchanged by them. */
static void test_gradient_null_outputs(void **state)
{
    (void)state;
    rng_state = 1;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample s[8];
    double dx[8], dy[8], dw[8], dx2[8], e1a, e1b;
    random_kernel(s, 8, 1.0, 0.3);
    assert_int_equal(aa_e1_gradient_at_angle(&gfilters[0].engine, s, 8, 0.3, &ws, &e1a, dx, dy, dw),
                     AA_OK);
    assert_int_equal(
        aa_e1_gradient_at_angle(&gfilters[0].engine, s, 8, 0.3, &ws, &e1b, dx2, NULL, NULL), AA_OK);
    assert_true(e1a == e1b);
    assert_memory_equal(dx, dx2, sizeof dx);
    double sum = 0.0;
    for (int i = 0; i < 8; i++)
        sum += dw[i];
    assert_true(fabs(sum) < 1e-12); /* projected onto sum(w) = 1 */
    aa_metric_workspace_free(&ws);
}

/* At a tie the derivative is one-sided: each dx_i equals the forward or the backward difference
 * (ties keep input order, so the first of a tied pair moves left, the second right, unchanged). */
static void test_gradient_at_ties(void **state)
{
    (void)state;
    rng_state = 77;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample s[6], t[6];
    double dx[6], dy[6], dw[6];
    const double h = 1e-7;
    for (int k = 0; k < 50; k++) {
        random_kernel(s, 6, 1.2, 0.0);
        s[1].x = s[0].x; /* tie at theta = 0 */
        s[4].x = s[3].x;
        double e1 = NAN;
        assert_int_equal(
            aa_e1_gradient_at_angle(&gfilters[0].engine, s, 6, 0.0, &ws, &e1, dx, dy, dw), AA_OK);
        for (size_t i = 0; i < 6; i++) {
            memcpy(t, s, sizeof t);
            double e0 = e1_of(&gfilters[0].engine, t, 6, 0.0, &ws);
            t[i].x = s[i].x + h;
            double fwd = (e1_of(&gfilters[0].engine, t, 6, 0.0, &ws) - e0) / h;
            t[i].x = s[i].x - h;
            double bwd = (e0 - e1_of(&gfilters[0].engine, t, 6, 0.0, &ws)) / h;
            double scale = fmax(fabs(fwd), fabs(bwd)) + 1e-3;
            bool ok = fabs(dx[i] - fwd) <= 1e-5 * scale || fabs(dx[i] - bwd) <= 1e-5 * scale;
            if (!ok) {
                print_error("tie case %d sample %zu: dx %.12g, forward %.12g, backward %.12g\n", k,
                            i, dx[i], fwd, bwd);
                fail();
            }
        }
    }
    aa_metric_workspace_free(&ws);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gradient_vs_central_differences),
        cmocka_unit_test(test_gradient_vs_reference_formulas),
        cmocka_unit_test(test_reference_formulas_vs_reference_differences),
        cmocka_unit_test(test_gradient_null_outputs),
        cmocka_unit_test(test_gradient_at_ties),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
