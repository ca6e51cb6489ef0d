/* Poisson disks by dart throwing on the torus at a stated radius (seeds.h): no two points closer
 * than the radius, measured independently with the torus distance; the default radius; the same
 * points for the same stream; a radius with no room is AA_ERANGE naming poisson_radius. And the
 * L&A Table 3 protocol of one cell (table3.h) against its parts: the random columns equal
 * aa_random_patterns_range_radius's, Opt W and Opt W+P do not exceed the best random pattern,
 * a clock-free budget repeats to the bit, and the mean / sd helper. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aa_optimizer.h"

static double torus_distance(aa_point a, aa_point b, double T)
{
    double dx = fabs(a.x - b.x), dy = fabs(a.y - b.y);
    dx = fmin(dx, T - dx);
    dy = fmin(dy, T - dy);
    return sqrt(dx * dx + dy * dy);
}

static double min_distance(const aa_point *p, size_t n, double T)
{
    double m = INFINITY;
    for (size_t i = 0; i < n; i++)
        for (size_t j = i + 1; j < n; j++)
            m = fmin(m, torus_distance(p[i], p[j], T));
    return m;
}

static void dart_throwing_keeps_the_radius(void **state)
{
    (void)state;
    assert_true(fabs(aa_poisson_default_radius(4) - 0.365) < 1e-12);
    aa_point pts[1024], again[1024];
    const struct {
        size_t n;
        int T;
        double r;
    } cases[] = {{1024, 16, 0}, {1024, 16, 0.3}, {64, 4, 0}, {3, 1, 0}, {1, 1, 0}, {16, 2, 0.38}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        double r = cases[c].r > 0
                       ? cases[c].r
                       : aa_poisson_default_radius((double)cases[c].n / (cases[c].T * cases[c].T));
        for (uint64_t s = 0; s < 3; s++) {
            aa_rng rng;
            aa_rng_seed(&rng, 7, s);
            assert_int_equal(aa_seed_points_radius(AA_SEED_POISSON, cases[c].n, cases[c].T,
                                                   cases[c].r, &rng, pts),
                             AA_OK);
            for (size_t i = 0; i < cases[c].n; i++)
                assert_true(pts[i].x >= 0 && pts[i].x < cases[c].T && pts[i].y >= 0 &&
                            pts[i].y < cases[c].T);
            if (cases[c].n > 1)
                assert_true(min_distance(pts, cases[c].n, cases[c].T) >= r);
            aa_rng_seed(&rng, 7, s);
            assert_int_equal(aa_seed_points_radius(AA_SEED_POISSON, cases[c].n, cases[c].T,
                                                   cases[c].r, &rng, again),
                             AA_OK);
            assert_memory_equal(pts, again, cases[c].n * sizeof pts[0]);
        }
    }
    /* Default radius through the old entry point. */
    aa_rng rng;
    aa_rng_seed(&rng, 1, 0);
    assert_int_equal(aa_seed_points(AA_SEED_POISSON, 1024, 16, &rng, pts), AA_OK);
    assert_true(min_distance(pts, 1024, 16) >= 0.365);
    /* Hexagonal packing holds 1024 disks of 0.5 px in 16x16 only just; darts jam long before. */
    aa_family fam;
    assert_int_equal(aa_family_parse("P(16,16,4)", &fam, NULL), AA_OK);
    aa_filter f;
    aa_filter_default(&f);
    aa_pattern p;
    aa_error err = {0};
    aa_rng_seed(&rng, 1, 0);
    assert_int_equal(aa_family_seed_radius(&fam, AA_SEED_POISSON, 0.5, &f, &rng, &p, &err),
                     AA_ERANGE);
    assert_string_equal(err.field, "poisson_radius");
    assert_string_equal(aa_seed_generator_name(AA_SEED_POISSON), "dart-throwing-torus");
    assert_string_equal(aa_seed_generator_name(AA_SEED_JITTERED), "jittered-grid");
}

static void mean_and_sd(void **state)
{
    (void)state;
    const double v[] = {1, 2, 3, 4};
    double m, sd;
    aa_mean_sd(v, 4, &m, &sd);
    assert_true(m == 2.5);
    assert_true(fabs(sd - sqrt(5.0 / 3.0)) < 1e-15);
    aa_mean_sd(v, 1, &m, &sd);
    assert_true(m == 1 && sd == 0);
    assert_true(aa_table3_paper_row(AA_SEED_POISSON)->opt_w == 0.221);
    assert_true(aa_table3_paper_row(AA_SEED_JITTERED)->opt_wp == 0.169);
    assert_null(aa_table3_paper_row(AA_SEED_UNIFORM));
}

static void one_cell_against_its_parts(void **state)
{
    (void)state;
    aa_family fam;
    assert_int_equal(aa_family_parse("P(4,4,2)", &fam, NULL), AA_OK);
    aa_filter f;
    aa_acuity a;
    aa_filter_default(&f);
    aa_acuity_naiman(&a);
    aa_metric_params metric = {&f, &a, NULL, 0, 0};
    aa_table3_params tp;
    aa_table3_params_default(&tp);
    tp.count = 12;
    tp.poisson_radius = 0.45;
    tp.opt_w_seconds = 0;
    tp.opt_wp_seconds = 0;
    tp.max_iterations = 60; /* clock-free: the same to the bit every time */
    aa_table3_cell c1, c2;
    aa_error err = {0};
    assert_int_equal(
        aa_table3_cell_run(&fam, AA_SEED_POISSON, &metric, &tp, 5, NULL, NULL, &c1, &err), AA_OK);
    assert_int_equal(
        aa_table3_cell_run(&fam, AA_SEED_POISSON, &metric, &tp, 5, NULL, NULL, &c2, &err), AA_OK);
    assert_true(c1.opt_w == c2.opt_w && c1.opt_wp == c2.opt_wp);
    aa_pattern best;
    aa_random_stats rs;
    size_t bi;
    assert_int_equal(aa_random_patterns_range_radius(&fam, AA_SEED_POISSON, 0.45, &metric, 5, 0, 12,
                                                     NULL, NULL, NULL, &best, &bi, &rs, &err),
                     AA_OK);
    assert_true(rs.min == c1.random.min && rs.avg == c1.random.avg && rs.max == c1.random.max);
    assert_int_equal(bi, c1.best_index);
    assert_true(c1.random.min <= c1.random.avg && c1.random.avg <= c1.random.max);
    assert_true(c1.opt_w <= c1.random.min && c1.opt_wp <= c1.random.min);
    assert_int_equal(c1.opt_w_method, AA_METHOD_MINIMAX);
    assert_true(c1.opt_wp_run.iterations <= 60);
    aa_evaluation ev;
    assert_int_equal(aa_evaluate(&c1.opt_wp_pattern, &metric, &ev, &err), AA_OK);
    assert_true(fabs(ev.e2 - c1.opt_wp) < 1e-12);
    aa_evaluation_free(&ev);
    aa_pattern_free(&best);
    aa_table3_cell_free(&c1);
    aa_table3_cell_free(&c2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(dart_throwing_keeps_the_radius),
        cmocka_unit_test(mean_and_sd),
        cmocka_unit_test(one_cell_against_its_parts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
