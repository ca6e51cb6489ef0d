/* Spearman's rho and its p-value (server/engine/core/spearman.c) on cases worked by hand; the
 * comparison with scipy.stats.spearmanr on random data with ties is spearman_scipy.py. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>

#include "aa_core.h"

static void ranks_average_ties(void **state)
{
    (void)state;
    const double v[] = {3, 1, 4, 1, 5, 9, 2, 6, 5};
    const double want[] = {4, 1.5, 5, 1.5, 6.5, 9, 3, 8, 6.5};
    double r[9];
    assert_int_equal(aa_rank_average(v, 9, r), AA_OK);
    for (int i = 0; i < 9; i++)
        assert_true(r[i] == want[i]);
}

static void monotone_is_one(void **state)
{
    (void)state;
    const double x[] = {1, 2, 3, 4, 5}, y[] = {0.1, 0.5, 0.7, 10, 100}, z[] = {5, 4, 3, 2, 1};
    aa_spearman_result s;
    assert_int_equal(aa_spearman_of(x, y, 5, &s), AA_OK);
    assert_true(s.rho == 1 && s.p_value == 0 && s.n == 5);
    assert_int_equal(aa_spearman_of(x, z, 5, &s), AA_OK);
    assert_true(s.rho == -1 && s.p_value == 0);
}

/* x = 1, 2, 3, 4; y = 1, 3, 2, 4 (no ties): d^2 = 0 + 1 + 1 + 0, rho = 1 - 6 * 2 / (4 * 15) =
 * 0.8; p = I_{0.36}(1, 1/2) = 1 - sqrt(1 - 0.36) = 0.2 with 2 degrees of freedom. */
static void small_case_by_hand(void **state)
{
    (void)state;
    const double x[] = {1, 2, 3, 4}, y[] = {1, 3, 2, 4};
    aa_spearman_result s;
    assert_int_equal(aa_spearman_of(x, y, 4, &s), AA_OK);
    assert_true(fabs(s.rho - 0.8) < 1e-15);
    assert_true(fabs(s.p_value - 0.2) < 1e-14);
}

/* Ties: x = 1, 1, 2, 3 gives ranks 1.5, 1.5, 3, 4 against y ranks 1, 2, 3, 4: Pearson of the
 * ranks = 4.5 / sqrt(4.5 * 5) = sqrt(0.9). */
static void ties_by_hand(void **state)
{
    (void)state;
    const double x[] = {1, 1, 2, 3}, y[] = {10, 20, 30, 40};
    aa_spearman_result s;
    assert_int_equal(aa_spearman_of(x, y, 4, &s), AA_OK);
    assert_true(fabs(s.rho - sqrt(0.9)) < 1e-15);
}

static void undefined_cases(void **state)
{
    (void)state;
    const double x[] = {1, 2, NAN, 4, INFINITY}, y[] = {2, 2, 2, 2, 2}, w[] = {1, 5, 2, 3, 4};
    aa_spearman_result s;
    assert_int_equal(aa_spearman_of(x, y, 5, &s), AA_OK);
    assert_true(isnan(s.rho) && isnan(s.p_value) && s.n == 3); /* y constant */
    assert_int_equal(aa_spearman_of(x, w, 5, &s), AA_OK);
    assert_int_equal(s.n, 3); /* the NaN and infinite pairs are left out */
    assert_true(fabs(s.rho - 0.5) < 1e-15);
    assert_int_equal(aa_spearman_of(x, w, 2, &s), AA_OK);
    assert_true(isnan(s.rho) && s.n == 2);
}

/* I_x(1, 1) = x, I_x(a, 1) = x^a, I_x(1, b) = 1 - (1 - x)^b, I_{1/2}(a, a) = 1/2. */
static void incomplete_beta_closed_forms(void **state)
{
    (void)state;
    for (double x = 0.05; x < 1; x += 0.1) {
        assert_true(fabs(aa_incomplete_beta(1, 1, x) - x) < 1e-14);
        assert_true(fabs(aa_incomplete_beta(7.5, 1, x) / pow(x, 7.5) - 1) < 1e-13);
        assert_true(fabs(aa_incomplete_beta(1, 0.5, x) - (1 - sqrt(1 - x))) < 1e-14);
    }
    for (double a = 0.5; a < 2000; a *= 3)
        assert_true(fabs(aa_incomplete_beta(a, a, 0.5) - 0.5) < 1e-12);
    assert_true(isnan(aa_incomplete_beta(-1, 1, 0.5)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ranks_average_ties), cmocka_unit_test(monotone_is_one),
        cmocka_unit_test(small_case_by_hand), cmocka_unit_test(ties_by_hand),
        cmocka_unit_test(undefined_cases),    cmocka_unit_test(incomplete_beta_closed_forms),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
