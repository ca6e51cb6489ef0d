/* The figures a random-stats or table3 job records per pattern (point_metrics.c): names, and the
 * values equal to the point-set functions' own for a preset's tile. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aa_pattern.h"

static void names_round_trip(void **state)
{
    (void)state;
    for (int m = 0; m < AA_PM_COUNT; m++) {
        aa_point_metric back;
        assert_int_equal(aa_point_metric_parse(aa_point_metric_name((aa_point_metric)m), &back),
                         AA_OK);
        assert_int_equal(back, m);
    }
    aa_point_metric x;
    assert_int_equal(aa_point_metric_parse("discrepancy", &x), AA_EINVAL);
    assert_int_equal(aa_point_metric_parse(NULL, &x), AA_EINVAL);
    assert_string_equal(aa_point_metric_name(AA_PM_STAR_LINF), "star_linf");
}

static void values_are_the_point_set_figures(void **state)
{
    (void)state;
    aa_pattern p;
    aa_error err = {0};
    assert_int_equal(aa_pattern_from_preset(&p, aa_preset_find("flipquad"), &err), AA_OK);
    aa_point *pts;
    size_t n;
    assert_int_equal(aa_pattern_unit_points(&p, &pts, &n, &err), AA_OK);
    aa_discrepancy d;
    aa_spacing sp;
    aa_spectrum s;
    double star;
    assert_int_equal(aa_point_set_discrepancy(pts, n, &d, &err), AA_OK);
    assert_int_equal(aa_point_set_star_discrepancy(pts, n, &star, &err), AA_OK);
    assert_int_equal(aa_point_set_spacing(pts, n, &sp, &err), AA_OK);
    assert_int_equal(aa_point_set_spectrum(pts, n, AA_PM_SPECTRUM_RADIUS, &s, &err), AA_OK);
    const double want[AA_PM_COUNT] = {d.l2_star,
                                      d.centered,
                                      d.wrap_around,
                                      d.mixture,
                                      star,
                                      sp.min_distance,
                                      sp.mean_nn_distance,
                                      sp.min_distance_normalized,
                                      sp.mean_nn_distance_normalized,
                                      s.effective_nyquist,
                                      s.effective_nyquist / sqrt((double)n),
                                      s.oscillation};
    /* every figure, in reverse order, and one alone */
    aa_point_metric which[AA_PM_COUNT];
    for (int m = 0; m < AA_PM_COUNT; m++)
        which[m] = (aa_point_metric)(AA_PM_COUNT - 1 - m);
    double got[AA_PM_COUNT];
    assert_int_equal(aa_point_metrics_of(&p, which, AA_PM_COUNT, got, &err), AA_OK);
    for (int m = 0; m < AA_PM_COUNT; m++) {
        double w = want[AA_PM_COUNT - 1 - m];
        assert_true((isnan(w) && isnan(got[m])) || got[m] == w);
    }
    aa_point_metric one = AA_PM_MIXTURE;
    assert_int_equal(aa_point_metrics_of(&p, &one, 1, got, &err), AA_OK);
    assert_true(got[0] == d.mixture && d.mixture > 0);
    aa_spectrum_free(&s);
    free(pts);
    aa_pattern_free(&p);
}

/* One sample per tile is not a point set: the error names "points". */
static void one_point_is_refused(void **state)
{
    (void)state;
    aa_pattern p;
    aa_error err = {0};
    assert_int_equal(aa_pattern_from_preset(&p, aa_preset_find("centroid"), &err), AA_OK);
    aa_point_metric one = AA_PM_CENTERED;
    double v;
    assert_int_equal(aa_point_metrics_of(&p, &one, 1, &v, &err), AA_EINVAL);
    assert_string_equal(err.field, "points");
    aa_pattern_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(names_round_trip),
        cmocka_unit_test(values_are_the_point_set_figures),
        cmocka_unit_test(one_point_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
