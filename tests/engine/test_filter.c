/* Reference filters: unit integral, symmetry, CDF(-r) = 0 and CDF(r) = 1, CDF against the
 * quadrature of h and against the independent closed forms (reference_metric.c), piece lookup,
 * the stated error bound of tabulated CDFs, named constructors, and rejection of invalid
 * parameters with the right field. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "aa_pattern.h"
#include "reference_metric.h"

typedef struct named {
    const char *name;
    aa_filter f;
    ref_filter r;
} named;

static named all[10];
static size_t all_count;

static int setup(void **state)
{
    (void)state;
    aa_filter_params par = aa_filter_params_default();
    aa_error err;
    struct {
        const char *name;
        long double B, C;
    } mn[] = {{"mitchell", 1.0L / 3, 1.0L / 3},
              {"catmull-rom", 0.0L, 0.5L},
              {"bspline", 1.0L, 0.0L},
              {"notch", 1.5L, -0.25L}};
    for (size_t i = 0; i < 4; i++) {
        named *n = &all[all_count++];
        n->name = mn[i].name;
        if (aa_filter_by_name(&n->f, n->name, &par, &err))
            return -1;
        ref_filter_mitchell(&n->r, mn[i].B, mn[i].C, 2.0L);
    }
    named *n = &all[all_count++];
    n->name = "box";
    if (aa_filter_by_name(&n->f, "box", &par, &err))
        return -1;
    ref_filter_box(&n->r, 0.5L);
    n = &all[all_count++];
    n->name = "tent";
    if (aa_filter_by_name(&n->f, "tent", &par, &err))
        return -1;
    ref_filter_tent(&n->r, 1.0L);
    n = &all[all_count++];
    n->name = "gaussian";
    if (aa_filter_by_name(&n->f, "gaussian", &par, &err))
        return -1;
    ref_filter_gaussian(&n->r, 0.5L, 2.0L);
    n = &all[all_count++];
    n->name = "lanczos";
    if (aa_filter_by_name(&n->f, "lanczos", &par, &err))
        return -1;
    ref_filter_lanczos(&n->r, 2.0L);
    n = &all[all_count++];
    n->name = "gaussian s=0.05";
    if (aa_filter_gaussian(&n->f, 0.05, 2.0, &err))
        return -1;
    ref_filter_gaussian(&n->r, 0.05L, 2.0L);
    n = &all[all_count++];
    n->name = "gaussian s=1.5 r=4";
    if (aa_filter_gaussian(&n->f, 1.5, 4.0, &err))
        return -1;
    ref_filter_gaussian(&n->r, 1.5L, 4.0L);
    return 0;
}

static void test_names_and_defaults(void **state)
{
    (void)state;
    const char *want[] = {"mitchell", "catmull-rom", "bspline",  "notch",
                          "box",      "tent",        "gaussian", "lanczos"};
    for (size_t i = 0; i < 8; i++) {
        bool found = false;
        for (size_t j = 0; aa_filter_names[j]; j++)
            found |= strcmp(aa_filter_names[j], want[i]) == 0;
        assert_true(found);
    }
    aa_filter d;
    aa_filter_default(&d);
    assert_int_equal(d.formula, AA_FILTER_MITCHELL);
    assert_true(fabs(d.B - 1.0 / 3) < 1e-15 && fabs(d.C - 1.0 / 3) < 1e-15);
    assert_true(d.radius == 2.0);
    assert_string_equal(d.name, "mitchell");
    /* by name with explicit B, C equals the named member of the family */
    aa_filter_params par = aa_filter_params_default();
    assert_true(isnan(par.B) && isnan(par.C) && isnan(par.radius) && isnan(par.sigma) &&
                isnan(par.a));
    par.B = 0.0;
    par.C = 0.5;
    aa_filter m;
    aa_error err;
    assert_int_equal(aa_filter_by_name(&m, "mitchell", &par, &err), AA_OK);
    for (double x = -2.0; x <= 2.0; x += 0.0625)
        assert_true(fabs(aa_filter_eval(&m, x) - aa_filter_eval(&all[1].f, x)) < 1e-15);
    assert_int_equal(aa_filter_by_name(&m, "no-such-filter", NULL, &err), AA_EINVAL);
    par = aa_filter_params_default();
    par.sigma = 0.3;
    assert_int_equal(aa_filter_by_name(&m, "gaussian", &par, &err), AA_OK);
    assert_true(m.sigma == 0.3 && m.radius == 2.0);
}

/* Composite 20-point Gauss-Legendre of the engine's h over [u, v] in cells of `cell`. */
static long double engine_h_integral(const aa_filter *f, long double u, long double v,
                                     long double cell)
{
    static long double node[20], weight[20];
    static int ready;
    if (!ready) {
        ref_gauss_legendre(20, node, weight);
        ready = 1;
    }
    long double acc = 0.0L;
    for (long double a = u; a < v; a += cell) {
        long double b = fminl(a + cell, v), mid = 0.5L * (a + b), half = 0.5L * (b - a);
        for (int i = 0; i < 20; i++)
            acc += half * weight[i] * aa_filter_eval(f, (double)(mid + half * node[i]));
    }
    return acc;
}

static void test_unit_integral_symmetry_endpoints(void **state)
{
    (void)state;
    int failures = 0;
    for (size_t k = 0; k < all_count; k++) {
        const aa_filter *f = &all[k].f;
        double r = f->radius;
        /* cells aligned with 1/8 so that no cell straddles a knot of the cubics */
        long double integral = engine_h_integral(f, -r, r, 1.0L / 64);
        if (fabsl(integral - 1.0L) > 1e-13L) {
            print_error("%s: integral of h = %.17Lg\n", all[k].name, integral);
            failures++;
        }
        for (int i = 0; i <= 400; i++) {
            double x = r * i / 400.0;
            assert_true(aa_filter_eval(f, x) == aa_filter_eval(f, -x));
            double g = aa_filter_cdf(f, x), gm = aa_filter_cdf(f, -x);
            assert_true(fabs(g + gm - 1.0) <= 1e-15 + 2 * f->cdf_error_bound);
        }
        assert_true(aa_filter_cdf(f, -r) == 0.0);
        assert_true(aa_filter_cdf(f, r) == 1.0);
        assert_true(aa_filter_cdf(f, -r - 1.0) == 0.0);
        assert_true(aa_filter_cdf(f, r + 1e6) == 1.0);
        assert_true(aa_filter_eval(f, r + 0.5) == 0.0);
        assert_true(aa_filter_eval(f, -r - 0.5) == 0.0);
        assert_true(fabs(aa_filter_cdf(f, 0.0) - 0.5) <= f->cdf_error_bound + 1e-15);
    }
    assert_int_equal(failures, 0);
}

/* Engine h and CDF vs the independent reference; engine CDF vs quadrature of engine h. */
static void test_against_reference(void **state)
{
    (void)state;
    int failures = 0;
    for (size_t k = 0; k < all_count; k++) {
        const aa_filter *f = &all[k].f;
        const ref_filter *rf = &all[k].r;
        double r = f->radius, worst_h = 0.0, worst_g = 0.0, worst_q = 0.0;
        /* a measured bound: rounding level for the cubic family, table error for the others */
        assert_true(f->cdf_error_bound >= 0.0 && f->cdf_error_bound <= 1e-14);
        for (int i = 0; i <= 2000; i++) {
            double a = -r + 2.0 * r * i / 2000.0 + (i % 7) * 1e-4 * (i < 2000);
            if (a >= r)
                a = r;
            long double hr = ref_filter_h(rf, a), gr = ref_filter_cdf(rf, a);
            double he = aa_filter_eval(f, a), ge = aa_filter_cdf(f, a);
            /* h is discontinuous at +-r for box and truncated Gaussians: skip the edge */
            if (fabs(fabs(a) - r) > 1e-12)
                worst_h = fmax(worst_h, (double)(fabsl(he - hr) / (fabsl(hr) + 1.0L)));
            worst_g = fmax(worst_g, (double)fabsl(ge - gr));
            if (i % 20 == 0) {
                long double q = engine_h_integral(f, -r, a, 1.0L / 64);
                worst_q = fmax(worst_q, (double)fabsl(ge - q));
            }
        }
        /* the reference's own closed form vs its own quadrature of h */
        double self = 0.0;
        for (int i = 0; i <= 200; i++) {
            long double a = -r + 2.0L * r * i / 200.0L;
            self = fmax(self, (double)fabsl(ref_filter_cdf(rf, a) -
                                            ref_filter_cdf_by_quadrature(rf, a, 1.0L / 32)));
        }
        print_message(
            "%-20s |h-href|/(|href|+1) %.2g  |g-gref| %.2g (bound %.2g)  |g-quad(h)| %.2g  "
            "reference self-check %.2g\n",
            all[k].name, worst_h, worst_g, f->cdf_error_bound, worst_q, self);
        assert_true(self < 1e-17);
        /* h: a few ulp of 1 (cubic evaluation with cancellation); g: the stated bound plus a few
         * ulp of 1 for the final evaluation's rounding */
        if (!(worst_h < 8e-15 && worst_g <= f->cdf_error_bound + 1e-15 && worst_q < 1e-13)) {
            print_error("%s: out of tolerance\n", all[k].name);
            failures++;
        }
    }
    assert_int_equal(failures, 0);
}

static void test_pieces(void **state)
{
    (void)state;
    for (size_t k = 0; k < all_count; k++) {
        const aa_filter *f = &all[k].f;
        double r = f->radius;
        assert_true(f->pieces >= 1 && f->pieces <= AA_FILTER_MAX_PIECES);
        assert_true(f->degree >= 1 && f->degree <= AA_FILTER_MAX_DEGREE);
        assert_true(f->knot[0] == -r && f->knot[f->pieces] == r);
        for (int j = 0; j < f->pieces; j++)
            assert_true(f->knot[j] < f->knot[j + 1]);
        assert_int_equal(aa_filter_piece(f, -r), -1);
        assert_int_equal(aa_filter_piece(f, -r - 3.0), -1);
        assert_int_equal(aa_filter_piece(f, r), f->pieces);
        assert_int_equal(aa_filter_piece(f, 1e6), f->pieces);
        for (int i = 1; i < 1000; i++) {
            double a = -r + 2.0 * r * i / 1000.0;
            int j = aa_filter_piece(f, a);
            assert_true(j >= 0 && j < f->pieces);
            assert_true(f->knot[j] <= a && a <= f->knot[j + 1]);
            assert_true(fabs(aa_filter_cdf_in_piece(f, j, a) - aa_filter_cdf(f, a)) < 1e-15);
        }
    }
    /* the cubic family's knots are where h changes polynomial */
    const aa_filter *m = &all[0].f;
    assert_int_equal(m->pieces, 4);
    assert_int_equal(m->degree, 4);
}

/* Mitchell with radius != 2 is the standard cubic stretched to the radius. */
static void test_mitchell_radius(void **state)
{
    (void)state;
    aa_filter f;
    aa_error err;
    ref_filter rf;
    assert_int_equal(aa_filter_mitchell(&f, 1.0 / 3, 1.0 / 3, 3.0, &err), AA_OK);
    ref_filter_mitchell(&rf, 1.0L / 3, 1.0L / 3, 3.0L);
    assert_true(f.radius == 3.0);
    for (int i = 0; i <= 600; i++) {
        double a = -3.0 + i * 0.01;
        assert_true(fabsl(aa_filter_cdf(&f, a) - ref_filter_cdf(&rf, a)) < 1e-15L);
        assert_true(fabsl(aa_filter_eval(&f, a) - ref_filter_h(&rf, a)) < 8e-15L);
    }
}

static void expect_error(int rc, const aa_error *err, const char *field)
{
    assert_int_equal(rc, AA_EINVAL);
    assert_int_equal(err->code, AA_EINVAL);
    assert_string_equal(err->field, field);
    assert_true(err->message[0] != '\0');
}

static void test_invalid_parameters(void **state)
{
    (void)state;
    aa_filter f;
    aa_error err;
    const double bad_positive[] = {0.0, -1.0, -0.0, NAN, INFINITY, -INFINITY};
    for (size_t i = 0; i < sizeof bad_positive / sizeof bad_positive[0]; i++) {
        double v = bad_positive[i];
        memset(&err, 0, sizeof err);
        expect_error(aa_filter_gaussian(&f, v, 2.0, &err), &err, "sigma");
        memset(&err, 0, sizeof err);
        expect_error(aa_filter_gaussian(&f, 0.5, v, &err), &err, "radius");
        memset(&err, 0, sizeof err);
        expect_error(aa_filter_box(&f, v, &err), &err, "radius");
        memset(&err, 0, sizeof err);
        expect_error(aa_filter_tent(&f, v, &err), &err, "radius");
        memset(&err, 0, sizeof err);
        expect_error(aa_filter_lanczos(&f, v, &err), &err, "a");
        memset(&err, 0, sizeof err);
        expect_error(aa_filter_mitchell(&f, 1.0 / 3, 1.0 / 3, v, &err), &err, "radius");
    }
    const double non_finite[] = {NAN, INFINITY, -INFINITY};
    for (size_t i = 0; i < 3; i++) {
        memset(&err, 0, sizeof err);
        expect_error(aa_filter_mitchell(&f, non_finite[i], 0.0, 2.0, &err), &err, "B");
        memset(&err, 0, sizeof err);
        expect_error(aa_filter_mitchell(&f, 0.0, non_finite[i], 2.0, &err), &err, "C");
    }
    /* through the named constructor: an explicit bad value is an error, NaN is the default */
    aa_filter_params par = aa_filter_params_default();
    par.sigma = -0.5;
    memset(&err, 0, sizeof err);
    expect_error(aa_filter_by_name(&f, "gaussian", &par, &err), &err, "sigma");
    par = aa_filter_params_default();
    par.radius = INFINITY;
    memset(&err, 0, sizeof err);
    expect_error(aa_filter_by_name(&f, "box", &par, &err), &err, "radius");
    par = aa_filter_params_default();
    par.a = 0.0;
    memset(&err, 0, sizeof err);
    expect_error(aa_filter_by_name(&f, "lanczos", &par, &err), &err, "a");
    /* NULL err is allowed */
    assert_int_equal(aa_filter_gaussian(&f, -1.0, 2.0, NULL), AA_EINVAL);
}

/* ---------- closed-form tables (docs/metric.md 2b), against the formulas written there ----------
 */

/* Gamma of the radius-2 Mitchell-Netravali cubic at t >= 0 (docs/metric.md 2b). */
static long double doc_mitchell_gamma2(long double B, long double C, long double t)
{
    long double K1_1 = ((12 - 9 * B - 6 * C) / 4 + (-18 + 12 * B + 6 * C) / 3 + (6 - 2 * B)) / 6;
#define L1(x)                                                                                      \
    (((12 - 9 * B - 6 * C) * powl(x, 5) / 20 + (-18 + 12 * B + 6 * C) * powl(x, 4) / 12 +          \
      (6 - 2 * B) * (x) * (x) / 2) /                                                               \
     6)
#define P2(x)                                                                                      \
    (((-B - 6 * C) * powl(x, 4) / 4 + (6 * B + 30 * C) * powl(x, 3) / 3 +                          \
      (-12 * B - 48 * C) * (x) * (x) / 2 + (8 * B + 24 * C) * (x)) /                               \
     6)
#define M2(x)                                                                                      \
    (((-B - 6 * C) * powl(x, 5) / 20 + (6 * B + 30 * C) * powl(x, 4) / 12 +                        \
      (-12 * B - 48 * C) * powl(x, 3) / 6 + (8 * B + 24 * C) * (x) * (x) / 2) /                    \
     6)
    long double T = 17.0L / 20 - B / 12 + C / 15;
    if (t <= 1)
        return L1(t) - T;
    return L1(1.0L) + (K1_1 - P2(1.0L)) * (t - 1) + M2(t) - M2(1.0L) - T;
#undef L1
#undef P2
#undef M2
}

/* Gamma from the engine's table, in long double (the table's coefficients are doubles). */
static long double table_gamma(const aa_filter *f, double a)
{
    int j = (int)((a + f->radius) * f->closed_inv_width);
    j = j < 0 ? 0 : (j >= f->closed_pieces ? f->closed_pieces - 1 : j);
    long double s = (long double)a - f->closed_mid[j], v = 0;
    for (int k = AA_FILTER_CLOSED_DEGREE; k >= 0; k--)
        v = v * s + f->closed_gamma[j][k];
    return v;
}

static void test_closed_form_tables(void **state)
{
    (void)state;
    aa_error err;
    aa_filter f;
    double worst = 0;
    /* Mitchell-Netravali family, several (B, C, r). */
    const double bcr[][3] = {{1.0 / 3, 1.0 / 3, 2}, {0, 0.5, 2},     {1, 0, 2},
                             {1.5, -0.25, 2},       {0.7, 0.1, 0.6}, {-0.5, 1.2, 5}};
    for (size_t i = 0; i < sizeof bcr / sizeof bcr[0]; i++) {
        long double B = bcr[i][0], C = bcr[i][1], r = bcr[i][2];
        assert_int_equal(aa_filter_mitchell(&f, bcr[i][0], bcr[i][1], bcr[i][2], &err), AA_OK);
        assert_int_equal(f.closed_pieces, 4);
        for (int k = 0; k <= 200; k++) {
            double a = -bcr[i][2] + 2 * bcr[i][2] * k / 200.0;
            long double want = r / 2 * doc_mitchell_gamma2(B, C, fabsl(2 * (long double)a / r));
            long double got = table_gamma(&f, a);
            double e = (double)(fabsl(got - want) / r);
            worst = fmax(worst, e);
            assert_true(e <= 4e-16);
        }
        /* V = (r/2) V_2, V_2 = 2 int_0^2 K^2 by 20-point Gauss-Legendre per unit (exact). */
        ref_filter rf;
        ref_filter_mitchell(&rf, B, C, r);
        long double node[20], weight[20], v = 0;
        ref_gauss_legendre(20, node, weight);
        for (int piece = 0; piece < 2; piece++)
            for (int q = 0; q < 20; q++) {
                long double x = (piece + 0.5L + 0.5L * node[q]) * r / 2;
                long double g = ref_filter_cdf(&rf, x) - 0.5L;
                v += 2 * weight[q] * 0.5L * (r / 2) * g * g;
            }
        assert_true(fabsl(f.closed_var - v) <= 4e-16L * r);
    }
    /* Box and tent: the closed forms of docs/metric.md. */
    const double radii[] = {0.5, 1, 3.25};
    for (size_t i = 0; i < 3; i++) {
        long double r = radii[i];
        assert_int_equal(aa_filter_box(&f, radii[i], &err), AA_OK);
        for (int k = 0; k <= 100; k++) {
            double a = -radii[i] + 2 * radii[i] * k / 100.0;
            long double want = ((long double)a * a - r * r) / (4 * r);
            assert_true(fabsl(table_gamma(&f, a) - want) <= 4e-16L * r);
        }
        assert_true(fabsl(f.closed_var - r / 6) <= 4e-16L * r);
        assert_int_equal(aa_filter_tent(&f, radii[i], &err), AA_OK);
        for (int k = 0; k <= 100; k++) {
            double a = -radii[i] + 2 * radii[i] * k / 100.0;
            long double x = fabsl((long double)a);
            long double want = -(r * r - x * x) / (2 * r) + (r * r * r - x * x * x) / (6 * r * r);
            assert_true(fabsl(table_gamma(&f, a) - want) <= 4e-16L * r);
        }
        assert_true(fabsl(f.closed_var - 4 * r / 15) <= 4e-16L * r);
    }
    /* No tables for the Gaussian and Lanczos: they keep the quadrature. */
    assert_int_equal(aa_filter_gaussian(&f, 0.5, 2, &err), AA_OK);
    assert_int_equal(f.closed_pieces, 0);
    assert_int_equal(aa_filter_lanczos(&f, 2, &err), AA_OK);
    assert_int_equal(f.closed_pieces, 0);
    print_message("closed-form Gamma tables vs docs/metric.md formulas: max error %.3g r\n", worst);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names_and_defaults),
        cmocka_unit_test(test_unit_integral_symmetry_endpoints),
        cmocka_unit_test(test_against_reference),
        cmocka_unit_test(test_pieces),
        cmocka_unit_test(test_mitchell_radius),
        cmocka_unit_test(test_invalid_parameters),
        cmocka_unit_test(test_closed_form_tables),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
