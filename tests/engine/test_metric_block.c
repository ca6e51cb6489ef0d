/* The kernel x angle block (aa_e1_kernel_block, aa_e1_gradient_kernel_block, and aa_evaluate
 * which uses it) against the straightforward path: one aa_e1_at_direction /
 * aa_e1_gradient_at_direction call per direction with the workspace's order forgotten before
 * each (a first sort from the input order every time). Same E1 and gradients to 1e-13 relative
 * on every preset, random kernels (negative weights included), axis-aligned grids whose
 * projections tie at 0, 45 and 90 degrees, and a jittered P(16,16,4) tile; for both methods,
 * with the quadrature as the independent check of the block's AUTO values. Single calls of
 * small kernels (their own sort and stack arrays) equal the general path bit for bit. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aa_metric.h"
#include "aa_pattern.h"

#define PI_D 3.14159265358979323846
#define MAX_N 256

static uint64_t rng_state;

static double uniform(double lo, double hi)
{
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return lo + (hi - lo) * ((double)(z >> 11) * 0x1.0p-53);
}

/* Angle sets: the default 36 (5 degree steps), a fine sweep (many small reorders) and a coarse
 * reversed one (large reorders, 180 degrees included: the order reverses). */
typedef struct angle_set {
    size_t n;
    double c[400], s[400];
} angle_set;

static void make_angles(angle_set *as, double first_deg, double step_deg, size_t n)
{
    as->n = n;
    for (size_t a = 0; a < n; a++)
        aa_metric_direction((first_deg + step_deg * (double)a) * (PI_D / 180), &as->c[a],
                            &as->s[a]);
}

static double rel(double a, double b)
{
    double d = fabs(a - b), m = fmax(fabs(a), fabs(b));
    return m > 0 ? d / m : d;
}

/* E1 of the block against per-direction calls from a fresh order, both methods; and the
 * block's AUTO against the quadrature (1e-12, the stability suite's bound). */
static void check_e1(const aa_filter *f, const aa_sample *s, size_t n, const angle_set *as)
{
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    double block[400], quad[400];
    const aa_e1_method methods[2] = {AA_E1_AUTO, AA_E1_QUADRATURE};
    for (int m = 0; m < 2; m++) {
        double *out = m == 0 ? block : quad;
        assert_int_equal(aa_e1_kernel_block(f, s, n, as->c, as->s, as->n, methods[m], &ws, out),
                         AA_OK);
        for (size_t a = 0; a < as->n; a++) {
            double e = -1;
            ws.order_of = NULL;
            assert_int_equal(aa_e1_at_direction(f, s, n, as->c[a], as->s[a], methods[m], &ws, &e),
                             AA_OK);
            if (rel(out[a], e) > 1e-13)
                fail_msg("n=%zu angle %zu method %d: block %.17g, per call %.17g", n, a, m, out[a],
                         e);
        }
    }
    for (size_t a = 0; a < as->n; a++)
        if (rel(block[a], quad[a]) > 1e-12)
            fail_msg("n=%zu angle %zu: block %.17g, quadrature %.17g", n, a, block[a], quad[a]);
    aa_metric_workspace_free(&ws);
}

/* The block's accumulated gradient against the sum of per-direction gradients (fresh order),
 * factors including zeros and negatives; relative to the largest component. */
static void check_gradient(const aa_filter *f, const aa_sample *s, size_t n, const angle_set *as)
{
    static double gx[3][MAX_N], gy[3][MAX_N], gw[3][MAX_N], dx[MAX_N], dy[MAX_N], dw[MAX_N];
    double factor[400], e1[400];
    for (size_t a = 0; a < as->n; a++)
        factor[a] = a % 5 == 3 ? 0 : uniform(-1, 2);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    const aa_e1_method methods[2] = {AA_E1_AUTO, AA_E1_QUADRATURE};
    for (int m = 0; m < 2; m++) {
        memset(gx[m], 0, sizeof gx[m]);
        memset(gy[m], 0, sizeof gy[m]);
        memset(gw[m], 0, sizeof gw[m]);
        assert_int_equal(aa_e1_gradient_kernel_block(f, s, n, as->c, as->s, as->n, factor,
                                                     methods[m], &ws, e1, gx[m], gy[m], gw[m]),
                         AA_OK);
    }
    memset(gx[2], 0, sizeof gx[2]);
    memset(gy[2], 0, sizeof gy[2]);
    memset(gw[2], 0, sizeof gw[2]);
    for (size_t a = 0; a < as->n; a++) {
        double e = -1;
        ws.order_of = NULL;
        assert_int_equal(aa_e1_gradient_at_direction(f, s, n, as->c[a], as->s[a], AA_E1_AUTO, &ws,
                                                     &e, dx, dy, dw),
                         AA_OK);
        assert_true(rel(e, e1[a]) <= 1e-12); /* e1 holds the quadrature block's values */
        if (factor[a] == 0 || !(e > 0))
            continue;
        for (size_t i = 0; i < n; i++) {
            gx[2][i] += factor[a] * dx[i];
            gy[2][i] += factor[a] * dy[i];
            gw[2][i] += factor[a] * dw[i];
        }
    }
    double scale = 0;
    for (size_t i = 0; i < n; i++)
        scale = fmax(scale, fmax(fabs(gx[2][i]), fmax(fabs(gy[2][i]), fabs(gw[2][i]))));
    /* scale 0 (one centred sample: every derivative vanishes): then all must be exactly 0 */
    for (size_t i = 0; i < n; i++) {
        double d = fmax(fabs(gx[0][i] - gx[2][i]),
                        fmax(fabs(gy[0][i] - gy[2][i]), fabs(gw[0][i] - gw[2][i])));
        if (d > 1e-13 * scale)
            fail_msg("n=%zu sample %zu: block gradient differs by %.3g (scale %.3g)", n, i, d,
                     scale);
        /* the quadrature block: the independent method, near-ties make it one-sided alike */
        double q = fmax(fabs(gx[1][i] - gx[2][i]),
                        fmax(fabs(gy[1][i] - gy[2][i]), fabs(gw[1][i] - gw[2][i])));
        if (q > 1e-9 * scale)
            fail_msg("n=%zu sample %zu: quadrature block gradient differs by %.3g (scale %.3g)", n,
                     i, q, scale);
    }
    aa_metric_workspace_free(&ws);
}

static void check_kernel(const aa_filter *f, const aa_sample *s, size_t n)
{
    angle_set as;
    make_angles(&as, 0, 5, 36);
    check_e1(f, s, n, &as);
    check_gradient(f, s, n, &as);
    make_angles(&as, 0, 0.5, 361);
    check_e1(f, s, n, &as);
    make_angles(&as, 180, -22.5, 9);
    check_e1(f, s, n, &as);
    check_gradient(f, s, n, &as);
}

static void filters(aa_filter f[3])
{
    aa_error err;
    aa_filter_default(&f[0]);
    assert_int_equal(aa_filter_tent(&f[1], 1.5, &err), AA_OK);
    assert_int_equal(aa_filter_gaussian(&f[2], 0.5, 2.0, &err), AA_OK);
}

static void test_presets(void **state)
{
    (void)state;
    aa_filter f;
    aa_filter_default(&f);
    for (size_t i = 0; i < aa_preset_count(); i++) {
        aa_pattern p;
        aa_error err;
        assert_int_equal(aa_pattern_from_preset(&p, aa_preset_at(i), &err), AA_OK);
        for (size_t k = 0; k < p.kernel_count; k++)
            check_kernel(&f, p.kernels[k].samples, p.kernels[k].count);
        aa_pattern_free(&p);
    }
}

static void test_random_kernels(void **state)
{
    (void)state;
    aa_filter f[3];
    filters(f);
    static aa_sample s[MAX_N];
    rng_state = 15;
    const size_t sizes[] = {1, 2, 3, 7, 16, 33, 64, 200};
    for (size_t t = 0; t < sizeof sizes / sizeof sizes[0]; t++) {
        size_t n = sizes[t];
        for (int rep = 0; rep < 3; rep++) {
            double sum = 0;
            for (size_t i = 0; i < n; i++) {
                /* rep 2: negative weights too; every third kernel reaches far outside */
                double span = rep == 1 ? 4.0 : 1.5;
                s[i] = (aa_sample){uniform(-span, span), uniform(-span, span),
                                   rep == 2 ? uniform(-0.5, 1.0) : uniform(0.1, 1.0)};
                sum += s[i].w;
            }
            if (fabs(sum) < 0.05)
                sum = 0.05;
            for (size_t i = 0; i < n; i++)
                s[i].w /= sum;
            check_kernel(&f[t % 3], s, n);
        }
    }
}

/* Grids: at 0, 45, 90 ... degrees whole rows, columns and diagonals tie exactly
 * (aa_metric_direction makes those directions exact). */
static void test_coincident_grids(void **state)
{
    (void)state;
    aa_filter f[3];
    filters(f);
    static aa_sample s[MAX_N];
    const int sides[] = {2, 4, 8};
    for (int t = 0; t < 3; t++) {
        int m = sides[t];
        size_t n = 0;
        for (int j = 0; j < m; j++)
            for (int i = 0; i < m; i++)
                s[n++] = (aa_sample){-1.5 + 3.0 * (i + 0.5) / m, -1.5 + 3.0 * (j + 0.5) / m,
                                     1.0 / (m * m)};
        /* a few samples stacked on one point too */
        s[1] = s[0];
        s[n - 1] = s[0];
        for (int k = 0; k < 3; k++)
            check_kernel(&f[k], s, n);
    }
}

/* A jittered 4x4 tile with 4 samples per pixel and 4x4 kernels: P(16,16,4), 64 samples a
 * kernel, as bench_metric times it; and aa_evaluate's table equals per-call values. */
static void test_p16(void **state)
{
    (void)state;
    aa_filter f;
    aa_filter_default(&f);
    aa_acuity acuity;
    aa_acuity_naiman(&acuity);
    rng_state = 1616;
    aa_point pts[64];
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 4; k++)
                pts[(j * 4 + i) * 4 + k] = (aa_point){i + 0.5 * (k % 2) + uniform(0.0, 0.5),
                                                      j + 0.5 * (k / 2) + uniform(0.0, 0.5)};
    aa_tile_spec spec = {
        .tile = 4, .kernel_size = 4, .count = 64, .samples = pts, .weight_filter = &f};
    aa_pattern p;
    aa_error err;
    assert_int_equal(aa_pattern_from_tile(&p, &spec, 0, &err), AA_OK);
    assert_int_equal(p.kernel_count, 16);
    for (size_t k = 0; k < p.kernel_count; k++)
        check_kernel(&f, p.kernels[k].samples, p.kernels[k].count);

    aa_metric_params mp = {.filter = &f, .acuity = &acuity};
    aa_evaluation ev;
    assert_int_equal(aa_evaluate(&p, &mp, &ev, &err), AA_OK);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    for (size_t k = 0; k < p.kernel_count; k++)
        for (size_t a = 0; a < ev.angle_count; a++) {
            double c, s, e = -1;
            aa_metric_direction(ev.angles_deg[a] * (PI_D / 180), &c, &s);
            ws.order_of = NULL;
            assert_int_equal(aa_e1_at_direction(&f, p.kernels[k].samples, p.kernels[k].count, c, s,
                                                AA_E1_AUTO, &ws, &e),
                             AA_OK);
            assert_true(rel(ev.e1[k * ev.angle_count + a], e) <= 1e-13);
        }
    aa_metric_workspace_free(&ws);
    aa_evaluation_free(&ev);
    aa_pattern_free(&p);
}

/* The block keeps the order for a following single call of the same kernel, and a single call
 * after the samples moved (same pointer) still sees the new positions. */
static void test_order_handover_and_errors(void **state)
{
    (void)state;
    aa_filter f;
    aa_filter_default(&f);
    aa_sample s[5] = {
        {-0.4, 0.1, 0.2}, {0.3, -0.2, 0.2}, {0.0, 0.5, 0.2}, {0.6, 0.6, 0.2}, {-0.7, -0.3, 0.2}};
    angle_set as;
    make_angles(&as, 0, 5, 36);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    double e1[36], e, fresh;
    assert_int_equal(aa_e1_kernel_block(&f, s, 5, as.c, as.s, 36, AA_E1_AUTO, &ws, e1), AA_OK);
    s[2].x = 1.4; /* moved in place */
    assert_int_equal(aa_e1_at_direction(&f, s, 5, as.c[35], as.s[35], AA_E1_AUTO, &ws, &e), AA_OK);
    ws.order_of = NULL;
    assert_int_equal(aa_e1_at_direction(&f, s, 5, as.c[35], as.s[35], AA_E1_AUTO, &ws, &fresh),
                     AA_OK);
    assert_true(e == fresh);
    assert_true(e != e1[35]);

    double bad_c[2] = {1, NAN}, bad_s[2] = {0, 0};
    assert_int_equal(aa_e1_kernel_block(&f, s, 0, as.c, as.s, 36, AA_E1_AUTO, &ws, e1), AA_EINVAL);
    assert_int_equal(aa_e1_kernel_block(&f, s, 5, bad_c, bad_s, 2, AA_E1_AUTO, &ws, e1), AA_EINVAL);
    assert_int_equal(aa_e1_gradient_kernel_block(&f, s, 5, bad_c, bad_s, 2, NULL, AA_E1_AUTO, &ws,
                                                 e1, NULL, NULL, NULL),
                     AA_EINVAL);
    /* no factor: E1 alone, as the plain block */
    double e1b[36];
    assert_int_equal(aa_e1_gradient_kernel_block(&f, s, 5, as.c, as.s, 36, NULL, AA_E1_AUTO, &ws,
                                                 e1b, NULL, NULL, NULL),
                     AA_OK);
    assert_int_equal(aa_e1_kernel_block(&f, s, 5, as.c, as.s, 36, AA_E1_AUTO, &ws, e1), AA_OK);
    for (size_t a = 0; a < 36; a++)
        assert_true(e1[a] == e1b[a]);
    aa_metric_workspace_free(&ws);
}

/* Single calls of small kernels (metric.c's e1_small: a branch-free sort on the stack, the
 * closed form over stack arrays) give the general path's value bit for bit: against
 * aa_e1_sorted_at_direction (the workspace's sort) and the block, every method, on random
 * kernels of 1 to 20 samples (negative weights, far outside the support, stacked samples), grids
 * whose projections tie at 0, 45 and 90 degrees, filters so narrow that the closed form falls
 * back to the quadrature, and non-finite samples (where both must give NaN or the same value). */
static bool same_value(double a, double b)
{
    return a == b ? signbit(a) == signbit(b) : (isnan(a) && isnan(b));
}

static void check_small_path(const aa_filter *f, const aa_sample *s, size_t n, double theta,
                             aa_metric_workspace *ws, long *fallbacks)
{
    double c, sn, e = -1, d = -2;
    aa_metric_direction(theta, &c, &sn);
    for (int m = 0; m < 3; m++) {
        double general = -2, block = -3;
        long before = ws->fallback_calls;
        assert_int_equal(aa_e1_at_direction(f, s, n, c, sn, (aa_e1_method)m, ws, &e), AA_OK);
        *fallbacks += ws->fallback_calls - before;
        assert_int_equal(aa_e1_sorted_at_direction(f, s, n, c, sn, (aa_e1_method)m, ws, &general),
                         AA_OK);
        assert_int_equal(aa_e1_kernel_block(f, s, n, &c, &sn, 1, (aa_e1_method)m, ws, &block),
                         AA_OK);
        if (!same_value(e, general) || !same_value(e, block))
            fail_msg("n=%zu theta %.17g method %d: single %a, general %a, block %a", n, theta, m, e,
                     general, block);
    }
    assert_int_equal(aa_e1_at_angle(f, s, n, theta, ws, &e), AA_OK);
    assert_int_equal(aa_e1_at_direction(f, s, n, c, sn, AA_E1_AUTO, ws, &d), AA_OK);
    assert_true(same_value(e, d));
}

static void test_small_kernels_bit_for_bit(void **state)
{
    (void)state;
    aa_filter f[5];
    aa_error err;
    filters(f);
    /* radius 1e-9 and 1e-12: nearly perfect kernels, where the closed form cancels and falls back
     */
    assert_int_equal(aa_filter_mitchell(&f[3], 1.0 / 3, 1.0 / 3, 1e-9, &err), AA_OK);
    assert_int_equal(aa_filter_mitchell(&f[4], 0, 0.5, 1e-12, &err), AA_OK);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    aa_sample s[20];
    long fallbacks = 0;
    rng_state = 33;
    for (int fi = 0; fi < 5; fi++)
        for (size_t n = 1; n <= 20; n++)
            for (int rep = 0; rep < (n <= 8 ? 240 : 24); rep++) {
                double span = rep % 4 == 1 ? 4.0 : 1.5, sum = 0;
                if (fi >= 3 && rep % 4 == 3)
                    span = 1e-9 * f[fi].radius; /* inside the narrow support */
                for (size_t i = 0; i < n; i++) {
                    s[i] = (aa_sample){uniform(-span, span), uniform(-span, span),
                                       rep % 4 == 2 ? uniform(-0.5, 1.0) : uniform(0.1, 1.0)};
                    sum += s[i].w;
                }
                if (fabs(sum) < 0.05)
                    sum = 0.05;
                for (size_t i = 0; i < n; i++)
                    s[i].w /= sum;
                if (rep % 6 == 5 && n > 2) {
                    s[1].x = s[n - 1].x = s[0].x;
                    s[1].y = s[n - 1].y = s[0].y;
                }
                check_small_path(&f[fi], s, n, uniform(0, PI_D), &ws, &fallbacks);
            }
    /* grids: ties at every multiple of 45 degrees; the narrow filters see them scaled down */
    for (int fi = 0; fi < 5; fi++)
        for (int m = 1; m <= 4; m++) {
            size_t n = 0;
            double scale = fi >= 3 ? f[fi].radius : 1.0;
            double sum = 0;
            for (int j = 0; j < m; j++)
                for (int i = 0; i < m; i++) {
                    /* unequal weights: the order of tied entries shows in the sums */
                    s[n] = (aa_sample){scale * (-1.5 + 3.0 * (i + 0.5) / m),
                                       scale * (-1.5 + 3.0 * (j + 0.5) / m), uniform(0.1, 1.0)};
                    sum += s[n++].w;
                }
            for (size_t i = 0; i < n; i++)
                s[i].w /= sum;
            if (n > 2) {
                s[n - 1].x = s[0].x;
                s[n - 1].y = s[0].y;
            }
            for (int a = 0; a < 36; a++)
                check_small_path(&f[fi], s, n, a * 5 * (PI_D / 180), &ws, &fallbacks);
        }
    /* Large cancelling weights far outside, and samples at the narrow filter's quantiles: the
     * closed form's terms cancel, so it falls back to the quadrature. */
    for (int k = 0; k < 6; k++) {
        s[0] = (aa_sample){-1e6, 0.0, 1e3};
        s[1] = (aa_sample){1e6, 0.0, -1e3};
        s[2] = (aa_sample){0.1 * k, 0.0, 1.0};
        check_small_path(&f[0], s, 3, 0.0, &ws, &fallbacks);
        check_small_path(&f[0], s, 3, uniform(0, PI_D), &ws, &fallbacks);
    }
    for (size_t n = 2; n <= 16; n++) {
        for (size_t i = 0; i < n; i++) {
            double lo = -f[4].radius, hi = f[4].radius, q = ((double)i + 0.5) / (double)n;
            for (int it = 0; it < 80; it++) {
                double mid = 0.5 * (lo + hi);
                *(aa_filter_cdf(&f[4], mid) < q ? &lo : &hi) = mid;
            }
            s[i] = (aa_sample){0.5 * (lo + hi), 0.0, 1.0 / (double)n};
        }
        check_small_path(&f[4], s, n, 0.0, &ws, &fallbacks);
    }
    assert_true(fallbacks > 0); /* the quadrature branch of the small path ran */
    /* non-finite coordinates and weights, at every position */
    const double bad[4] = {NAN, INFINITY, -INFINITY, 1e300};
    for (int b = 0; b < 4; b++)
        for (size_t n = 1; n <= 9; n++)
            for (size_t at = 0; at < n; at++) {
                for (size_t i = 0; i < n; i++)
                    s[i] = (aa_sample){uniform(-1, 1), uniform(-1, 1), 1.0 / (double)n};
                s[at].x = bad[b];
                check_small_path(&f[0], s, n, 0.3, &ws, &fallbacks);
                check_small_path(&f[0], s, n, 0, &ws, &fallbacks);
                s[at].x = 0;
                s[at].w = bad[b];
                check_small_path(&f[0], s, n, 0.7, &ws, &fallbacks);
            }
    aa_metric_workspace_free(&ws);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_presets),
        cmocka_unit_test(test_random_kernels),
        cmocka_unit_test(test_coincident_grids),
        cmocka_unit_test(test_p16),
        cmocka_unit_test(test_order_handover_and_errors),
        cmocka_unit_test(test_small_kernels_bit_for_bit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
