/* The reference's step response across an edge at angle θ (edge_profile.h) against independent
 * numerical integration: g_θ(a) = ∫ h(x) G((a - x c) / s) dx with h and G the Mitchell-
 * Netravali formulas of docs/metric.md written out here, composite Simpson over x; equal to the
 * 1-D g at 0° and 90°; the table against the direct quadrature; E1 against g_θ equal to the
 * metric's E1 at 0° and 90° and to the integral of (ĝ - g_θ)² with the independent g_θ elsewhere.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>

#include "aa_metric.h"
#include "aa_render.h"

#define PI 3.14159265358979323846

/* Mitchell-Netravali B = C = 1/3, radius 2 (docs/metric.md §2). */
static double mn_h(double x)
{
    const double B = 1.0 / 3, C = 1.0 / 3;
    double t = fabs(x);
    if (t < 1)
        return ((12 - 9 * B - 6 * C) * t * t * t + (-18 + 12 * B + 6 * C) * t * t + (6 - 2 * B)) /
               6;
    if (t < 2)
        return ((-B - 6 * C) * t * t * t + (6 * B + 30 * C) * t * t + (-12 * B - 48 * C) * t +
                (8 * B + 24 * C)) /
               6;
    return 0;
}

static double mn_K(double t) /* ∫_0^t h, 0 <= t <= 2 */
{
    const double B = 1.0 / 3, C = 1.0 / 3;
    double k1 = ((12 - 9 * B - 6 * C) * t * t * t * t / 4 + (-18 + 12 * B + 6 * C) * t * t * t / 3 +
                 (6 - 2 * B) * t) /
                6;
    if (t <= 1)
        return k1;
#define P2(u)                                                                                      \
    (((-B - 6 * C) * (u) * (u) * (u) * (u) / 4 + (6 * B + 30 * C) * (u) * (u) * (u) / 3 +          \
      (-12 * B - 48 * C) * (u) * (u) / 2 + (8 * B + 24 * C) * (u)) /                               \
     6)
    double K1 = ((12 - 9 * B - 6 * C) / 4 + (-18 + 12 * B + 6 * C) / 3 + (6 - 2 * B)) / 6;
    return K1 + P2(t) - P2(1.0);
#undef P2
}

static double mn_G(double t)
{
    if (t <= -2)
        return 0;
    if (t >= 2)
        return 1;
    return 0.5 + (t < 0 ? -mn_K(-t) : mn_K(t));
}

/* Composite Simpson over x in [-2, 2], n intervals. */
static double independent_profile(double theta, double a, int n)
{
    double c = fabs(cos(theta)), s = fabs(sin(theta)), step = 4.0 / n, sum = 0;
    for (int k = 0; k <= n; k++) {
        double x = -2 + k * step, w = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
        sum += w * mn_h(x) * mn_G((a - x * c) / s);
    }
    return sum * step / 3;
}

static const double angles_deg[] = {10, 27, 30, 45, 63, 63.43494882292201, 80, 83, 94};
#define ANGLES (sizeof angles_deg / sizeof angles_deg[0])

static void test_against_independent_integration(void **state)
{
    (void)state;
    aa_filter f;
    aa_filter_default(&f);
    double worst = 0;
    for (size_t k = 0; k < ANGLES; k++) {
        double th = angles_deg[k] * PI / 180;
        aa_edge_profile prof;
        aa_edge_profile_init(&prof, &f, th);
        for (double a = -2.9; a <= 2.9; a += 0.37) {
            double want = independent_profile(th, a, 20000);
            double exact = aa_edge_profile_exact(&f, cos(th), sin(th), a);
            double table = aa_edge_profile_eval(&prof, a);
            worst = fmax(worst, fmax(fabs(exact - want), fabs(table - want)));
            assert_true(fabs(exact - want) < 1e-10);
            assert_true(fabs(table - want) < 1e-10);
        }
    }
    printf("g_theta: direct and table against Simpson (20000): max |diff| %.2e\n", worst);
}

/* At 0° and 90° the reference's step response is the 1-D g; at 45° it is not. */
static void test_axis_profile_is_g(void **state)
{
    (void)state;
    aa_filter f;
    aa_filter_default(&f);
    aa_edge_profile p0, p90, p45;
    aa_edge_profile_init(&p0, &f, 0);
    aa_edge_profile_init(&p90, &f, PI / 2);
    aa_edge_profile_init(&p45, &f, PI / 4);
    double far = 0;
    for (double a = -2.5; a <= 2.5; a += 0.01) {
        double g = aa_filter_cdf(&f, a);
        assert_true(fabs(aa_edge_profile_exact(&f, 1, 0, a) - g) < 1e-15);
        assert_true(fabs(aa_edge_profile_exact(&f, 0, -1, a) - g) < 1e-15);
        assert_true(fabs(aa_edge_profile_eval(&p0, a) - g) < 1e-14);
        assert_true(fabs(aa_edge_profile_eval(&p90, a) - g) < 1e-14);
        /* Symmetric: g_θ(-a) = 1 - g_θ(a). */
        assert_true(fabs(aa_edge_profile_eval(&p45, -a) - (1 - aa_edge_profile_eval(&p45, a))) <
                    1e-14);
        far = fmax(far, fabs(aa_edge_profile_eval(&p45, a) - g));
    }
    assert_true(far > 1e-3); /* the separable reference differs at generic angles */
    /* 90° - θ and 180° - θ share the profile. */
    aa_edge_profile a1, a2, a3;
    aa_edge_profile_init(&a1, &f, 27 * PI / 180);
    aa_edge_profile_init(&a2, &f, 63 * PI / 180);
    aa_edge_profile_init(&a3, &f, 153 * PI / 180);
    for (double a = -2.5; a <= 2.5; a += 0.1) {
        assert_true(fabs(aa_edge_profile_eval(&a1, a) - aa_edge_profile_eval(&a2, a)) < 1e-14);
        assert_true(fabs(aa_edge_profile_eval(&a1, a) - aa_edge_profile_eval(&a3, a)) < 1e-14);
    }
}

/* Other filters: the table against the direct quadrature. */
static void test_other_filters(void **state)
{
    (void)state;
    const char *names[] = {"catmull-rom", "bspline", "box", "tent", "gaussian", "lanczos"};
    for (size_t n = 0; n < sizeof names / sizeof names[0]; n++) {
        aa_filter f;
        assert_int_equal(aa_filter_by_name(&f, names[n], NULL, NULL), AA_OK);
        double worst = 0;
        for (size_t k = 0; k < ANGLES; k++) {
            double th = angles_deg[k] * PI / 180;
            aa_edge_profile prof;
            aa_edge_profile_init(&prof, &f, th);
            for (double a = -prof.reach - 0.2; a <= prof.reach + 0.2; a += 0.093) {
                double d = fabs(aa_edge_profile_eval(&prof, a) -
                                aa_edge_profile_exact(&f, cos(th), sin(th), a));
                worst = fmax(worst, d);
            }
        }
        printf("%-12s table against direct quadrature: max |diff| %.2e\n", names[n], worst);
        assert_true(worst < 1e-9);
    }
}

static void random_kernel(uint64_t *st, aa_sample *s, size_t n)
{
    double total = 0;
    for (size_t i = 0; i < n; i++) {
        *st = *st * 6364136223846793005ull + 1442695040888963407ull;
        s[i].x = ((*st >> 11) * (1.0 / 9007199254740992.0)) * 3 - 1.5;
        *st = *st * 6364136223846793005ull + 1442695040888963407ull;
        s[i].y = ((*st >> 11) * (1.0 / 9007199254740992.0)) * 3 - 1.5;
        *st = *st * 6364136223846793005ull + 1442695040888963407ull;
        s[i].w = 0.2 + ((*st >> 11) * (1.0 / 9007199254740992.0));
        total += s[i].w;
    }
    for (size_t i = 0; i < n; i++)
        s[i].w /= total;
}

/* E1 against the profile: the metric's E1 at 0° and 90°, a midpoint integral elsewhere. */
static void test_e1_against_profile(void **state)
{
    (void)state;
    aa_filter f;
    aa_filter_default(&f);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    uint64_t st = 7;
    double worst = 0, node[10], weight[10];
    aa_gauss_legendre(10, node, weight);
    for (int trial = 0; trial < 12; trial++) {
        aa_sample s[9];
        size_t n = 1 + (size_t)trial % 9;
        random_kernel(&st, s, n);
        const double axis[2][2] = {{1, 0}, {0, 1}};
        for (int k = 0; k < 2; k++) {
            aa_edge_profile prof;
            aa_edge_profile_init(&prof, &f, k * PI / 2);
            double got, want;
            assert_int_equal(aa_edge_profile_e1(&prof, s, n, axis[k][0], axis[k][1], &got), AA_OK);
            assert_int_equal(
                aa_e1_at_direction(&f, s, n, axis[k][0], axis[k][1], AA_E1_AUTO, &ws, &want),
                AA_OK);
            assert_true(fabs(got - want) < 1e-12);
        }
        double th = (17 + 11 * trial) * PI / 180, ct = cos(th), stn = sin(th);
        aa_edge_profile prof;
        aa_edge_profile_init(&prof, &f, th);
        double got;
        assert_int_equal(aa_edge_profile_e1(&prof, s, n, ct, stn, &got), AA_OK);
        /* Between the sorted projections and where g_θ changes polynomial (k_i c + k_j s, the
         * filter's knots k) ĝ is constant and g_θ one polynomial: (ĝ - g_θ)² integrated there
         * with g_θ from independent_profile. */
        double br[9 + 25];
        size_t m = 0;
        for (size_t i = 0; i < n; i++)
            br[m++] = s[i].x * ct + s[i].y * stn;
        for (int i = -2; i <= 2; i++)
            for (int j = -2; j <= 2; j++)
                br[m++] = i * fabs(ct) + j * fabs(stn);
        for (size_t i = 1; i < m; i++)
            for (size_t j = i; j > 0 && br[j - 1] > br[j]; j--) {
                double t = br[j];
                br[j] = br[j - 1];
                br[j - 1] = t;
            }
        double sum = 0;
        for (size_t k = 0; k + 1 < m; k++) {
            double lo = br[k], hi = br[k + 1], ghat = 0;
            for (size_t i = 0; i < n; i++)
                if (s[i].x * ct + s[i].y * stn <= lo)
                    ghat += s[i].w;
            /* 10-point Gauss-Legendre: (ĝ - g_θ)² is a polynomial of degree 16 here. */
            double mid = (lo + hi) / 2, half = (hi - lo) / 2;
            for (int c = 0; c < 10 && hi > lo; c++) {
                double a = mid + half * node[c];
                double d = ghat - (a <= -prof.reach  ? 0
                                   : a >= prof.reach ? 1
                                                     : independent_profile(th, a, 4000));
                sum += half * weight[c] * d * d;
            }
        }
        worst = fmax(worst, fabs(got - sqrt(sum)) / sqrt(sum));
        assert_true(fabs(got - sqrt(sum)) < 1e-11 * sqrt(sum));
    }
    printf("E1 against g_theta: relative difference to the independent integral %.2e\n", worst);
    /* Weights not summing to 1: infinite, like the metric's E1. */
    aa_sample bad[2] = {{0, 0, 0.5}, {0.3, 0, 0.4}};
    aa_edge_profile prof;
    aa_edge_profile_init(&prof, &f, 0.3);
    double e1;
    assert_int_equal(aa_edge_profile_e1(&prof, bad, 2, cos(0.3), sin(0.3), &e1), AA_OK);
    assert_true(isinf(e1));
    assert_int_equal(aa_edge_profile_e1(&prof, bad, 0, 1, 0, &e1), AA_EINVAL);
    aa_metric_workspace_free(&ws);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_against_independent_integration),
        cmocka_unit_test(test_axis_profile_is_g),
        cmocka_unit_test(test_other_filters),
        cmocka_unit_test(test_e1_against_profile),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
