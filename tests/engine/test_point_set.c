/* Point-set analysis against independent values:
 *   - the exact L-infinity star discrepancy against a brute-force O(n^3) count over every
 *     candidate corner (random sets, and grids with tied coordinates);
 *   - the L2 discrepancies against a plain long-double evaluation of the defining sums, and the
 *     closed form for two points; (tests/e2e/e2e_analysis.py compares with scipy);
 *   - the periodogram of a regular k x k grid: n at multiples of k, zero elsewhere;
 *   - the normalised minimum distance of a near-hexagonal lattice on the torus: about 1;
 *   - the periodogram of a jittered m x m grid, averaged over 1000 draws, against its expected
 *     value 1 - sinc^2(pi kx / m) sinc^2(pi ky / m) within 4 standard errors;
 *   - the pair correlation of uniform random sets: about 1 at moderate r;
 *   - bad inputs: each named. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aa_core.h"
#include "aa_pattern.h"

#define PI_D 3.14159265358979323846

static void random_points(aa_rng *r, aa_point *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        p[i].x = aa_rng_uniform(r);
        p[i].y = aa_rng_uniform(r);
    }
}

/* Every corner (a, b) with a, b from the coordinates and 1, both box kinds counted directly. */
static double star_brute_force(const aa_point *p, size_t n)
{
    double worst = 0;
    for (size_t i = 0; i <= n; i++) {
        double a = i < n ? p[i].x : 1.0;
        for (size_t j = 0; j <= n; j++) {
            double b = j < n ? p[j].y : 1.0;
            size_t open = 0, closed = 0;
            for (size_t k = 0; k < n; k++) {
                open += p[k].x < a && p[k].y < b;
                closed += p[k].x <= a && p[k].y <= b;
            }
            worst = fmax(worst, fmax(a * b - (double)open / n, (double)closed / n - a * b));
        }
    }
    return worst;
}

static void test_star_discrepancy(void **state)
{
    (void)state;
    aa_rng r;
    aa_rng_seed(&r, 7, 0);
    aa_point p[64];
    aa_error err = {0};
    for (size_t n = 2; n <= 64; n += 3) {
        random_points(&r, p, n);
        double fast, slow = star_brute_force(p, n);
        assert_int_equal(aa_point_set_star_discrepancy(p, n, &fast, &err), AA_OK);
        assert_true(fabs(fast - slow) <= 1e-15);
    }
    /* A 4 x 4 grid of cell corners: ties in x and y everywhere. */
    for (int i = 0; i < 16; i++)
        p[i] = (aa_point){(i % 4) / 4.0, (i / 4) / 4.0};
    double fast;
    assert_int_equal(aa_point_set_star_discrepancy(p, 16, &fast, &err), AA_OK);
    assert_true(fabs(fast - star_brute_force(p, 16)) <= 1e-15);
    /* By hand: the closed box [0, 3/4]^2 holds all 16 points and has area 9/16. */
    assert_true(fabs(fast - 7.0 / 16) <= 1e-15);
}

/* The defining sums in long double, no compensation, pair by pair (i, j) over all n^2. */
static void discrepancy_long_double(const aa_point *p, size_t n, long double out[4])
{
    long double cd1 = 0, md1 = 0, l21 = 0, cd2 = 0, wd2 = 0, md2 = 0, l22 = 0;
    for (size_t i = 0; i < n; i++) {
        long double x[2] = {p[i].x, p[i].y}, c = 1, m = 1, l = 1;
        for (int k = 0; k < 2; k++) {
            long double a = fabsl(x[k] - 0.5L);
            c *= 1 + a / 2 - a * a / 2;
            m *= 5.0L / 3 - a / 4 - a * a / 4;
            l *= 1 - x[k] * x[k];
        }
        cd1 += c;
        md1 += m;
        l21 += l;
        for (size_t j = 0; j < n; j++) {
            long double y[2] = {p[j].x, p[j].y}, c2 = 1, w2 = 1, m2 = 1, l2 = 1;
            for (int k = 0; k < 2; k++) {
                long double a = fabsl(x[k] - 0.5L), b = fabsl(y[k] - 0.5L), d = fabsl(x[k] - y[k]);
                c2 *= 1 + a / 2 + b / 2 - d / 2;
                w2 *= 1.5L - d * (1 - d);
                m2 *= 15.0L / 8 - a / 4 - b / 4 - 3 * d / 4 + d * d / 2;
                l2 *= 1 - fmaxl(x[k], y[k]);
            }
            cd2 += c2;
            wd2 += w2;
            md2 += m2;
            l22 += l2;
        }
    }
    long double N = (long double)n;
    out[0] = (13.0L / 12) * (13.0L / 12) - 2 * cd1 / N + cd2 / (N * N);
    out[1] = -(4.0L / 3) * (4.0L / 3) + wd2 / (N * N);
    out[2] = (19.0L / 12) * (19.0L / 12) - 2 * md1 / N + md2 / (N * N);
    out[3] = 1.0L / 9 - l21 / (2 * N) + l22 / (N * N);
}

static void test_l2_discrepancies(void **state)
{
    (void)state;
    aa_rng r;
    aa_rng_seed(&r, 11, 0);
    static aa_point p[1024];
    aa_error err = {0};
    const size_t sizes[] = {2, 4, 16, 100, 1024};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        size_t n = sizes[s];
        random_points(&r, p, n);
        aa_discrepancy d;
        assert_int_equal(aa_point_set_discrepancy(p, n, &d, &err), AA_OK);
        long double ref[4];
        discrepancy_long_double(p, n, ref);
        double got[4] = {d.centered_sq, d.wrap_around_sq, d.mixture_sq, d.l2_star_sq};
        for (int k = 0; k < 4; k++) {
            /* The squares' absolute error is a few eps times the terms (about 2): relative to
             * the square, which shrinks like 1/n. */
            double tol = 64 * 0x1.0p-52 * 2.0;
            assert_true(fabsl((long double)got[k] - ref[k]) <= tol);
            assert_true(got[k] > 0);
        }
        assert_true(fabs(d.centered * d.centered - d.centered_sq) <= 1e-15 * d.centered_sq);
    }
    /* Two points: the centred discrepancy of {(1/4, 1/4), (3/4, 3/4)} by hand.
     * Per point: a = 1/4 in both coordinates, (1 + 1/8 - 1/32)^2 = (35/32)^2.
     * Pairs: same point (1 + 1/4)^2 = 25/16; other point (1 + 1/4 - 1/4)^2 = 1.
     * CD^2 = (13/12)^2 - 2 (35/32)^2 + (2 * 25/16 + 2 * 1) / 4. */
    aa_point two[2] = {{0.25, 0.25}, {0.75, 0.75}};
    aa_discrepancy d;
    assert_int_equal(aa_point_set_discrepancy(two, 2, &d, &err), AA_OK);
    double cd = (13.0 / 12) * (13.0 / 12) - 2 * (35.0 / 32) * (35.0 / 32) + (50.0 / 16 + 2) / 4;
    assert_true(fabs(d.centered_sq - cd) <= 1e-15);
}

static void test_grid_periodogram(void **state)
{
    (void)state;
    const int k = 8, R = 20;
    aa_point p[64];
    for (int i = 0; i < 64; i++)
        p[i] = (aa_point){(i % k + 0.5) / k, (i / k + 0.5) / k};
    aa_spectrum s;
    aa_error err = {0};
    assert_int_equal(aa_point_set_spectrum(p, 64, R, &s, &err), AA_OK);
    for (int ky = -R; ky <= R; ky++) {
        for (int kx = -R; kx <= R; kx++) {
            double v = s.power[(size_t)(ky + R) * s.side + (size_t)(kx + R)];
            if (kx % k == 0 && ky % k == 0)
                assert_true(fabs(v - 64) <= 1e-10);
            else
                assert_true(v <= 1e-20);
        }
    }
    assert_true(fabs(s.radial[0] - 64) < 1e-10);
    /* Nothing below the first lattice frequency |k| = 8. */
    assert_true(s.effective_nyquist >= 7);
    aa_spectrum_free(&s);
}

static double sinc(double x)
{
    return x == 0 ? 1 : sin(x) / x;
}

static void test_jittered_spectrum(void **state)
{
    (void)state;
    enum { M = 8, N = M * M, R = 12, DRAWS = 1000 };
    size_t side = 2 * R + 1;
    double *sum = calloc(side * side, sizeof *sum), *sumsq = calloc(side * side, sizeof *sumsq);
    aa_rng r;
    aa_rng_seed(&r, 3, 0);
    aa_point p[N];
    aa_error err = {0};
    for (int d = 0; d < DRAWS; d++) {
        for (int i = 0; i < N; i++)
            p[i] = (aa_point){(i % M + aa_rng_uniform(&r)) / M, (i / M + aa_rng_uniform(&r)) / M};
        aa_spectrum s;
        assert_int_equal(aa_point_set_spectrum(p, N, R, &s, &err), AA_OK);
        for (size_t i = 0; i < side * side; i++) {
            sum[i] += s.power[i];
            sumsq[i] += s.power[i] * s.power[i];
        }
        aa_spectrum_free(&s);
    }
    int checked = 0, outside = 0;
    for (int ky = -R; ky <= R; ky++) {
        for (int kx = -R; kx <= R; kx++) {
            if (!kx && !ky)
                continue;
            size_t i = (size_t)(ky + R) * side + (size_t)(kx + R);
            double mean = sum[i] / DRAWS, var = sumsq[i] / DRAWS - mean * mean;
            double phi = sinc(PI_D * kx / M) * sinc(PI_D * ky / M);
            double expect = 1 - phi * phi, se = sqrt(var / DRAWS);
            checked++;
            outside += fabs(mean - expect) > 4 * se + 1e-12;
        }
    }
    /* 624 frequencies at 4 standard errors: a handful outside would be chance, not none. */
    assert_true(checked == (int)(side * side) - 1);
    assert_true(outside <= 2);
    free(sum);
    free(sumsq);
}

static void test_hexagonal_spacing(void **state)
{
    (void)state;
    /* 26 columns x 30 rows, odd rows shifted by half a column: rows 1/30 apart, columns 1/26;
     * 30/26 is within 0.1 % of 2/sqrt(3), so the lattice is nearly hexagonal on the torus. */
    enum { C = 26, ROWS = 30 };
    static aa_point p[C * ROWS];
    for (int j = 0; j < ROWS; j++)
        for (int i = 0; i < C; i++)
            p[j * C + i] = (aa_point){(i + 0.5 * (j % 2)) / C, (double)j / ROWS};
    aa_spacing s;
    aa_error err = {0};
    assert_int_equal(aa_point_set_spacing(p, C * ROWS, &s, &err), AA_OK);
    assert_true(s.min_distance_normalized > 0.99 && s.min_distance_normalized <= 1.0);
    assert_true(fabs(s.min_distance - 1.0 / C) < 1e-12);
    assert_true(s.mean_nn_distance_normalized >= s.min_distance_normalized);
    /* Random points pack far worse. */
    aa_rng r;
    aa_rng_seed(&r, 5, 0);
    random_points(&r, p, 256);
    assert_int_equal(aa_point_set_spacing(p, 256, &s, &err), AA_OK);
    assert_true(s.min_distance_normalized < 0.5);
}

static void test_pcf_uniform(void **state)
{
    (void)state;
    enum { N = 512, BINS = 20, DRAWS = 20 };
    aa_point p[N];
    double g[BINS], mean[BINS] = {0};
    aa_rng r;
    aa_rng_seed(&r, 9, 0);
    aa_error err = {0};
    for (int d = 0; d < DRAWS; d++) {
        random_points(&r, p, N);
        assert_int_equal(aa_point_set_pcf(p, N, 0.2, BINS, 0.01, g, &err), AA_OK);
        for (int b = 0; b < BINS; b++)
            mean[b] += g[b] / DRAWS;
    }
    /* Away from r = 0 (where the kernel's width matters) a Poisson set has g = 1. */
    for (int b = 5; b < BINS; b++)
        assert_true(fabs(mean[b] - 1) < 0.05);
}

static void test_bad_inputs(void **state)
{
    (void)state;
    aa_point p[3] = {{0.1, 0.2}, {0.5, 1.0}, {0.3, 0.3}};
    aa_error err = {0};
    aa_discrepancy d;
    assert_int_equal(aa_point_set_discrepancy(p, 3, &d, &err), AA_EINVAL);
    assert_string_equal(err.field, "points");
    assert_int_equal(aa_point_set_discrepancy(p, 1, &d, &err), AA_EINVAL);
    aa_point ok[2] = {{0.1, 0.2}, {0.3, 0.3}};
    aa_spectrum s;
    assert_int_equal(aa_point_set_spectrum(ok, 2, 0, &s, &err), AA_EINVAL);
    assert_string_equal(err.field, "radius");
    double g[4];
    assert_int_equal(aa_point_set_pcf(ok, 2, 0.7, 4, 0.01, g, &err), AA_EINVAL);
    assert_string_equal(err.field, "r_max");
    assert_int_equal(aa_point_set_pcf(ok, 2, 0.2, 4, -1, g, &err), AA_EINVAL);
    assert_string_equal(err.field, "sigma");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_star_discrepancy),  cmocka_unit_test(test_l2_discrepancies),
        cmocka_unit_test(test_grid_periodogram),  cmocka_unit_test(test_jittered_spectrum),
        cmocka_unit_test(test_hexagonal_spacing), cmocka_unit_test(test_pcf_uniform),
        cmocka_unit_test(test_bad_inputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
