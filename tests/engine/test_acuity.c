/* Acuity tables W(theta): the Naiman table (pinned W(0) = 3.93, W(45) = 2.5, knots of
 * data/acuity-naiman.json), folding by the square's symmetries, linear interpolation against the
 * independent reference_e2.c, default angle sets, uniform, custom folded and periodic tables,
 * and rejection of bad knots with field names. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "aa_metric.h"
#include "reference_e2.h"

static void test_naiman_pinned_and_knots(void **state)
{
    (void)state;
    aa_acuity a;
    aa_acuity_naiman(&a);
    assert_string_equal(a.name, "naiman");
    assert_int_equal(a.version, 2);
    assert_true(a.folded);
    assert_int_equal(a.count, 10);
    const double w[10] = {3.93, 3.0, 2.5, 2.2, 2.0, 1.9, 1.9, 2.0, 2.2, 2.5};
    for (size_t i = 0; i < 10; i++) {
        assert_true(a.angle_deg[i] == 5.0 * i);
        assert_true(a.weight[i] == w[i]);
    }
    assert_true(aa_acuity_weight(&a, 0.0) == 3.93);
    assert_true(aa_acuity_weight(&a, 45.0) == 2.5);
    assert_true(aa_acuity_weight(&a, 90.0) == 3.93);
    assert_true(aa_acuity_weight(&a, 135.0) == 2.5);
    assert_true(aa_acuity_weight(&a, 180.0) == 3.93);
    assert_true(fabs(aa_acuity_weight(&a, 2.5) - 3.465) < 1e-15);
    assert_true(fabs(aa_acuity_weight(&a, 47.5) - 2.35) < 1e-15);
    aa_acuity b;
    aa_error err;
    assert_int_equal(aa_acuity_by_name(&b, "naiman", &err), AA_OK);
    assert_memory_equal(&a, &b, sizeof a);
}

/* Version 1 stays available by name; it shares the pinned W(0) and W(45) and lies on or above
 * version 2 everywhere (version 2 only lowered the reconstructed knots). */
static void test_naiman_envelope(void **state)
{
    (void)state;
    aa_acuity e, v2;
    aa_error err;
    assert_int_equal(aa_acuity_by_name(&e, "naiman-envelope", &err), AA_OK);
    assert_string_equal(e.name, "naiman-envelope");
    assert_int_equal(e.version, 1);
    const double w[10] = {3.93, 3.55, 3.1, 2.67, 2.3, 1.95, 1.95, 2.15, 2.2, 2.5};
    assert_int_equal(e.count, 10);
    for (size_t i = 0; i < 10; i++)
        assert_true(e.angle_deg[i] == 5.0 * i && e.weight[i] == w[i]);
    aa_acuity_naiman(&v2);
    for (int i = 0; i <= 900; i++) {
        double t = i * 0.1;
        assert_true(aa_acuity_weight(&e, t) >= aa_acuity_weight(&v2, t));
    }
    assert_true(aa_acuity_weight(&e, 0) == aa_acuity_weight(&v2, 0));
    assert_true(aa_acuity_weight(&e, 45) == aa_acuity_weight(&v2, 45));
    size_t named = 0;
    for (const char *const *n = aa_acuity_names; *n; n++, named++) {
        aa_acuity t;
        assert_int_equal(aa_acuity_by_name(&t, *n, &err), AA_OK);
        assert_string_equal(t.name, *n);
        assert_true(t.version >= 1);
    }
    assert_int_equal(named, 3);
    assert_string_equal(aa_acuity_names[0], "naiman");
}

static void test_folding_symmetry(void **state)
{
    (void)state;
    aa_acuity a;
    aa_acuity_naiman(&a);
    for (int i = 0; i <= 3600; i++) {
        double t = i * 0.05 + (i % 3) * 1e-7;
        double w = aa_acuity_weight(&a, t);
        const double images[] = {-t,        90.0 - t,  90.0 + t,  180.0 - t,
                                 t + 180.0, t - 180.0, 270.0 + t, t + 360.0};
        for (size_t k = 0; k < sizeof images / sizeof images[0]; k++)
            assert_true(fabs(aa_acuity_weight(&a, images[k]) - w) < 1e-12);
        assert_true(fabs(w - ref_naiman_weight(t)) < 1e-14);
    }
}

static void test_default_angles(void **state)
{
    (void)state;
    aa_acuity a;
    double ang[AA_MAX_ANGLES];
    aa_acuity_naiman(&a);
    size_t n = aa_acuity_default_angles(&a, ang, AA_MAX_ANGLES);
    assert_int_equal(n, 36);
    for (size_t i = 0; i < n; i++)
        assert_true(fabs(ang[i] - 5.0 * i) < 1e-12);
    /* a small cap is respected */
    double few[4] = {-1, -1, -1, -1};
    size_t m = aa_acuity_default_angles(&a, few, 3);
    assert_true(m <= 3);
    assert_true(few[3] == -1);
    aa_acuity_uniform(&a);
    assert_string_equal(a.name, "uniform");
    n = aa_acuity_default_angles(&a, ang, AA_MAX_ANGLES);
    assert_int_equal(n, 36);
    for (size_t i = 0; i < n; i++)
        assert_true(fabs(ang[i] - 5.0 * i) < 1e-12);
    for (int i = -360; i <= 720; i += 7)
        assert_true(aa_acuity_weight(&a, i + 0.3) == 1.0);
    aa_error err;
    aa_acuity b;
    assert_int_equal(aa_acuity_by_name(&b, "uniform", &err), AA_OK);
    assert_true(aa_acuity_weight(&b, 33.0) == 1.0);
    memset(&err, 0, sizeof err);
    assert_int_equal(aa_acuity_by_name(&b, "no-such-table", &err), AA_EINVAL);
    assert_int_equal(err.code, AA_EINVAL);
}

static void test_custom_folded(void **state)
{
    (void)state;
    const double knots[3][2] = {{0, 1.0}, {30, 4.0}, {45, 2.0}};
    aa_acuity a;
    aa_error err;
    assert_int_equal(aa_acuity_from_knots(&a, knots, 3, &err), AA_OK);
    assert_true(a.folded);
    assert_string_equal(a.name, "custom");
    assert_int_equal(a.version, 0);
    assert_true(fabs(aa_acuity_weight(&a, 15.0) - 2.5) < 1e-15);
    assert_true(fabs(aa_acuity_weight(&a, 75.0) - 2.5) < 1e-15);  /* 90 - 15 */
    assert_true(fabs(aa_acuity_weight(&a, 105.0) - 2.5) < 1e-15); /* 90 + 15 */
    assert_true(fabs(aa_acuity_weight(&a, 37.5) - 3.0) < 1e-15);
    assert_true(fabs(aa_acuity_weight(&a, 52.5) - 3.0) < 1e-15);
    double ang[64];
    size_t n = aa_acuity_default_angles(&a, ang, 64);
    /* {k, 90-k, 90+k, 180-k} for k in {0, 30, 45}: 0, 30, 45, 60, 90, 120, 135, 150 */
    const double want[8] = {0, 30, 45, 60, 90, 120, 135, 150};
    assert_int_equal(n, 8);
    for (size_t i = 0; i < 8; i++)
        assert_true(fabs(ang[i] - want[i]) < 1e-12);
    /* unsorted input is sorted */
    const double shuffled[3][2] = {{45, 2.0}, {0, 1.0}, {30, 4.0}};
    aa_acuity b;
    assert_int_equal(aa_acuity_from_knots(&b, shuffled, 3, &err), AA_OK);
    for (int t = 0; t < 180; t++)
        assert_true(aa_acuity_weight(&a, t) == aa_acuity_weight(&b, t));
}

static void test_custom_periodic(void **state)
{
    (void)state;
    const double knots[2][2] = {{10, 1.0}, {100, 3.0}};
    aa_acuity a;
    aa_error err;
    assert_int_equal(aa_acuity_from_knots(&a, knots, 2, &err), AA_OK);
    assert_false(a.folded);
    assert_true(fabs(aa_acuity_weight(&a, 10.0) - 1.0) < 1e-15);
    assert_true(fabs(aa_acuity_weight(&a, 100.0) - 3.0) < 1e-15);
    assert_true(fabs(aa_acuity_weight(&a, 55.0) - 2.0) < 1e-15);
    assert_true(fabs(aa_acuity_weight(&a, 145.0) - 2.0) < 1e-15); /* wraps 100 -> 190 */
    assert_true(fabs(aa_acuity_weight(&a, 0.0) - (3.0 - 2.0 * 80.0 / 90.0)) < 1e-15);
    assert_true(fabs(aa_acuity_weight(&a, 235.0) - 2.0) < 1e-15); /* period 180 */
    double ang[8];
    size_t n = aa_acuity_default_angles(&a, ang, 8);
    assert_int_equal(n, 2);
    assert_true(ang[0] == 10.0 && ang[1] == 100.0);
    /* single knot: constant */
    const double one[1][2] = {{60, 2.5}};
    assert_int_equal(aa_acuity_from_knots(&a, one, 1, &err), AA_OK);
    assert_true(aa_acuity_weight(&a, 13.0) == 2.5);
}

static void expect_knot_error(const double (*knots)[2], size_t count, const char *field)
{
    aa_acuity a;
    aa_error err;
    memset(&err, 0, sizeof err);
    int rc = aa_acuity_from_knots(&a, knots, count, &err);
    if (rc >= 0 || strcmp(err.field, field) != 0) {
        print_error("expected an error on %s, got rc %d field '%s'\n", field, rc, err.field);
        fail();
    }
    assert_int_equal(err.code, rc);
}

static void test_bad_knots(void **state)
{
    (void)state;
    const double nan_w[2][2] = {{0, 1}, {20, NAN}};
    expect_knot_error(nan_w, 2, "knots[1][1]");
    const double neg_w[2][2] = {{0, -0.5}, {20, 1}};
    expect_knot_error(neg_w, 2, "knots[0][1]");
    const double inf_w[3][2] = {{0, 1}, {20, 1}, {30, INFINITY}};
    expect_knot_error(inf_w, 3, "knots[2][1]");
    const double nan_a[2][2] = {{NAN, 1}, {20, 1}};
    expect_knot_error(nan_a, 2, "knots[0][0]");
    const double big_a[3][2] = {{0, 1}, {20, 1}, {180, 1}};
    expect_knot_error(big_a, 3, "knots[2][0]");
    const double neg_a[2][2] = {{0, 1}, {-5, 1}};
    expect_knot_error(neg_a, 2, "knots[1][0]");
    const double inf_a[2][2] = {{0, 1}, {INFINITY, 1}};
    expect_knot_error(inf_a, 2, "knots[1][0]");
    const double dup[3][2] = {{0, 1}, {20, 2}, {20, 3}};
    expect_knot_error(dup, 3, "knots[2][0]");
    aa_acuity a;
    aa_error err;
    memset(&err, 0, sizeof err);
    assert_true(aa_acuity_from_knots(&a, dup, 0, &err) < 0);
    static double many[AA_ACUITY_MAX_KNOTS + 1][2];
    for (size_t i = 0; i <= AA_ACUITY_MAX_KNOTS; i++)
        many[i][0] = i * (179.0 / (AA_ACUITY_MAX_KNOTS + 1)), many[i][1] = 1.0;
    assert_true(aa_acuity_from_knots(&a, many, AA_ACUITY_MAX_KNOTS + 1, &err) < 0);
    assert_int_equal(aa_acuity_from_knots(&a, many, AA_ACUITY_MAX_KNOTS, &err), AA_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_naiman_pinned_and_knots),
        cmocka_unit_test(test_naiman_envelope),
        cmocka_unit_test(test_folding_symmetry),
        cmocka_unit_test(test_default_angles),
        cmocka_unit_test(test_custom_folded),
        cmocka_unit_test(test_custom_periodic),
        cmocka_unit_test(test_bad_knots),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
