/* The simplex QP of the minimax step (simplex_qp.h) against its optimality conditions and a
 * brute-force grid over the simplex. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "aa_core.h"
#include "simplex_qp.h"

/* Q = A A^T (PSD, rank <= cols) and f of random entries. */
static void random_problem(aa_rng *rng, size_t m, size_t cols, double *Q, double *f)
{
    double A[8 * 8];
    for (size_t i = 0; i < m * cols; i++)
        A[i] = 2 * aa_rng_uniform(rng) - 1;
    for (size_t i = 0; i < m; i++) {
        f[i] = aa_rng_uniform(rng);
        for (size_t j = 0; j < m; j++) {
            double s = 0;
            for (size_t c = 0; c < cols; c++)
                s += A[i * cols + c] * A[j * cols + c];
            Q[i * m + j] = s;
        }
    }
}

static double objective(size_t m, const double *Q, const double *f, double delta, const double *l)
{
    double lin = 0, quad = 0;
    for (size_t i = 0; i < m; i++) {
        lin += f[i] * l[i];
        for (size_t j = 0; j < m; j++)
            quad += l[i] * Q[i * m + j] * l[j];
    }
    return lin - 0.5 * delta * quad;
}

/* KKT of max phi over the simplex: grad_i <= mu for all i, = mu on the support. */
static void optimality_conditions_hold(void **state)
{
    (void)state;
    aa_rng rng;
    aa_rng_seed(&rng, 5, 0);
    for (int trial = 0; trial < 200; trial++) {
        size_t m = 1 + aa_rng_below(&rng, 8), cols = 1 + aa_rng_below(&rng, 8);
        double Q[64], f[8], l[8] = {0}, q[8];
        double delta = 0.05 + 4 * aa_rng_uniform(&rng);
        random_problem(&rng, m, cols, Q, f);
        aa_simplex_qp_result r;
        assert_int_equal(aa_simplex_qp_solve(m, Q, f, delta, l, q, 1e-13, 100000, &r), 0);
        double sum = 0, mu = -INFINITY;
        for (size_t i = 0; i < m; i++) {
            assert_true(l[i] >= 0);
            sum += l[i];
            mu = fmax(mu, f[i] - delta * q[i]);
        }
        assert_true(fabs(sum - 1) < 1e-12);
        for (size_t i = 0; i < m; i++)
            if (l[i] > 1e-6)
                assert_true(f[i] - delta * q[i] > mu - 1e-6);
        assert_true(fabs(r.objective - objective(m, Q, f, delta, l)) < 1e-12);
    }
}

/* m = 3: no grid point of spacing 1/600 beats the solution. */
static void no_grid_point_is_better(void **state)
{
    (void)state;
    aa_rng rng;
    aa_rng_seed(&rng, 8, 0);
    for (int trial = 0; trial < 20; trial++) {
        double Q[9], f[3], l[3] = {0}, q[3];
        random_problem(&rng, 3, 2, Q, f);
        double delta = 0.5 + aa_rng_uniform(&rng);
        aa_simplex_qp_result r;
        assert_int_equal(aa_simplex_qp_solve(3, Q, f, delta, l, q, 1e-14, 100000, &r), 0);
        double best = -INFINITY;
        const int n = 600;
        for (int a = 0; a <= n; a++)
            for (int b = 0; a + b <= n; b++) {
                double g[3] = {(double)a / n, (double)b / n, (double)(n - a - b) / n};
                best = fmax(best, objective(3, Q, f, delta, g));
            }
        assert_true(r.objective >= best - 1e-12);
        /* and the grid comes within its resolution of it */
        assert_true(r.objective - best < 1e-3);
    }
}

static void warm_start_reaches_the_same_optimum(void **state)
{
    (void)state;
    aa_rng rng;
    aa_rng_seed(&rng, 13, 0);
    double Q[64], f[8], cold[8] = {0}, warm[8], q[8];
    random_problem(&rng, 8, 3, Q, f);
    aa_simplex_qp_result rc, rw;
    assert_int_equal(aa_simplex_qp_solve(8, Q, f, 1.0, cold, q, 1e-14, 100000, &rc), 0);
    for (int i = 0; i < 8; i++)
        warm[i] = 1.0 / 8;
    assert_int_equal(aa_simplex_qp_solve(8, Q, f, 1.0, warm, q, 1e-14, 100000, &rw), 0);
    assert_true(fabs(rc.objective - rw.objective) < 1e-10);
}

static void bad_arguments_are_refused(void **state)
{
    (void)state;
    double Q[1] = {1}, f[1] = {0}, l[1] = {0}, q[1];
    assert_int_equal(aa_simplex_qp_solve(0, Q, f, 1, l, q, 1e-9, 10, NULL), -1);
    assert_int_equal(aa_simplex_qp_solve(1, Q, f, 0, l, q, 1e-9, 10, NULL), -1);
    assert_int_equal(aa_simplex_qp_solve(1, Q, f, NAN, l, q, 1e-9, 10, NULL), -1);
    assert_int_equal(aa_simplex_qp_solve(1, Q, f, 1, l, q, 1e-9, 10, NULL), 0);
    assert_true(l[0] == 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(optimality_conditions_hold),
        cmocka_unit_test(no_grid_point_is_better),
        cmocka_unit_test(warm_start_reaches_the_same_optimum),
        cmocka_unit_test(bad_arguments_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
