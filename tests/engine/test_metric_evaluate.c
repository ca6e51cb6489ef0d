/* aa_evaluate and aa_evaluate_dense: the returned table (angles, W, unweighted E1 per kernel and
 * angle) against the independent reference, E2/argmax/mean/Lp recomputed from it, custom angle
 * lists, parameter errors with field names, and the dense check against a dense reference scan. */
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
#include "reference_e2.h"

static aa_filter filter;
static aa_acuity acuity;
static ref_filter rfilter;

static int setup(void **state)
{
    (void)state;
    aa_filter_default(&filter);
    aa_acuity_naiman(&acuity);
    ref_filter_mitchell(&rfilter, 1.0L / 3, 1.0L / 3, 2.0L);
    return 0;
}

static void preset_pattern(aa_pattern *p, const char *name)
{
    aa_error err;
    assert_int_equal(aa_pattern_from_preset(p, aa_preset_find(name), &err), AA_OK);
}

static long double ref_kernel_e1(const aa_kernel *k, double deg)
{
    double x[64], y[64], w[64];
    for (size_t i = 0; i < k->count; i++)
        x[i] = k->samples[i].x, y[i] = k->samples[i].y, w[i] = k->samples[i].w;
    return ref_e1_at_angle(&rfilter, x, y, w, k->count, (double)(deg * (REF_PI / 180.0L)));
}

static void test_table_and_norms(void **state)
{
    (void)state;
    const char *names[] = {"hasselgren-c", "quincunx", "d3d-8x"};
    for (size_t t = 0; t < 3; t++) {
        aa_pattern p;
        preset_pattern(&p, names[t]);
        aa_metric_params mp = {.filter = &filter, .acuity = &acuity, .lp = 4.0};
        aa_evaluation ev;
        aa_error err;
        assert_int_equal(aa_evaluate(&p, &mp, &ev, &err), AA_OK);
        assert_int_equal(ev.kernel_count, p.kernel_count);
        assert_int_equal(ev.angle_count, 36);
        double best = -1, sum = 0, sump = 0;
        size_t bk = 0;
        double bdeg = 0;
        for (size_t a = 0; a < ev.angle_count; a++) {
            assert_true(fabs(ev.angles_deg[a] - 5.0 * a) < 1e-12);
            assert_true(fabs(ev.weight[a] - ref_naiman_weight(ev.angles_deg[a])) < 1e-14);
        }
        for (size_t k = 0; k < ev.kernel_count; k++) {
            for (size_t a = 0; a < ev.angle_count; a++) {
                double e1 = ev.e1[k * ev.angle_count + a];
                long double r = ref_kernel_e1(&p.kernels[k], ev.angles_deg[a]);
                assert_true(fabsl(e1 - r) <= 1e-12L * r);
                double v = ev.weight[a] * e1;
                if (v > best)
                    best = v, bk = k, bdeg = ev.angles_deg[a];
                sum += v;
                sump += pow(v, 4.0);
            }
        }
        size_t cells = ev.kernel_count * ev.angle_count;
        assert_true(ev.e2 == best);
        /* the argmax cell attains the maximum (ties may pick any of them) */
        size_t ai = (size_t)llround(ev.argmax_angle_deg / 5.0);
        assert_true(ev.weight[ai] * ev.e1[ev.argmax_kernel * ev.angle_count + ai] == best);
        (void)bk;
        (void)bdeg;
        assert_true(fabs(ev.mean - sum / cells) <= 1e-14 * ev.mean);
        assert_true(fabs(ev.lp_norm - pow(sump / cells, 0.25)) <= 1e-13 * ev.lp_norm);
        assert_true(ev.lp_norm <= ev.e2 && ev.lp_norm >= ev.mean);
        aa_evaluation_free(&ev);

        mp.lp = 0.0;
        assert_int_equal(aa_evaluate(&p, &mp, &ev, &err), AA_OK);
        assert_true(isnan(ev.lp_norm));
        aa_evaluation_free(&ev);
        aa_pattern_free(&p);
    }
}

static void test_custom_angles_and_uniform(void **state)
{
    (void)state;
    aa_pattern p;
    preset_pattern(&p, "rgss");
    const double angles[5] = {12.5, 0.0, 45.0, 97.25, 179.9};
    aa_acuity uni;
    aa_acuity_uniform(&uni);
    aa_metric_params mp = {
        .filter = &filter, .acuity = &uni, .angles_deg = angles, .angle_count = 5};
    aa_evaluation ev;
    aa_error err;
    assert_int_equal(aa_evaluate(&p, &mp, &ev, &err), AA_OK);
    assert_int_equal(ev.angle_count, 5);
    long double best = 0.0L;
    for (size_t a = 0; a < 5; a++) {
        assert_true(ev.angles_deg[a] == angles[a]);
        assert_true(ev.weight[a] == 1.0);
        long double r = ref_kernel_e1(&p.kernels[0], angles[a]);
        assert_true(fabsl(ev.e1[a] - r) <= 1e-12L * r);
        if (r > best)
            best = r;
    }
    assert_true(fabsl(ev.e2 - best) <= 1e-12L * best);
    aa_evaluation_free(&ev);
    aa_pattern_free(&p);
}

static void test_parameter_errors(void **state)
{
    (void)state;
    aa_pattern p;
    preset_pattern(&p, "rgss");
    aa_evaluation ev;
    aa_error err;
    double bad[3] = {0.0, NAN, 10.0};
    aa_metric_params mp = {
        .filter = &filter, .acuity = &acuity, .angles_deg = bad, .angle_count = 3};
    memset(&err, 0, sizeof err);
    assert_int_equal(aa_evaluate(&p, &mp, &ev, &err), AA_EINVAL);
    assert_string_equal(err.field, "angles[1]");
    bad[1] = INFINITY;
    memset(&err, 0, sizeof err);
    assert_int_equal(aa_evaluate(&p, &mp, &ev, &err), AA_EINVAL);
    assert_string_equal(err.field, "angles[1]");
    double *many = calloc(AA_MAX_ANGLES + 1, sizeof *many);
    mp.angles_deg = many;
    mp.angle_count = AA_MAX_ANGLES + 1;
    memset(&err, 0, sizeof err);
    assert_int_equal(aa_evaluate(&p, &mp, &ev, &err), AA_ERANGE);
    free(many);
    const double lps[4] = {0.5, -1.0, NAN, INFINITY};
    for (int i = 0; i < 4; i++) {
        aa_metric_params q = {.filter = &filter, .acuity = &acuity, .lp = lps[i]};
        memset(&err, 0, sizeof err);
        int rc = aa_evaluate(&p, &q, &ev, &err);
        if (rc == AA_OK) {
            /* p = inf is the max norm, the only sensible reading if accepted */
            assert_true(isinf(lps[i]) && lps[i] > 0);
            assert_true(ev.lp_norm == ev.e2);
            aa_evaluation_free(&ev);
            continue;
        }
        assert_int_equal(rc, AA_EINVAL);
        assert_string_equal(err.field, "lp");
    }
    aa_metric_params one = {.filter = &filter, .acuity = &acuity, .lp = 1.0};
    assert_int_equal(aa_evaluate(&p, &one, &ev, &err), AA_OK);
    assert_true(fabs(ev.lp_norm - ev.mean) <= 1e-14 * ev.mean);
    aa_evaluation_free(&ev);
    aa_pattern_free(&p);
}

/* Dense check against a dense scan with the reference E1 and W. */
static void test_dense_check(void **state)
{
    (void)state;
    const char *names[] = {"quincunx", "hasselgren-b", "diagonal", "tilted pair"};
    int betweens = 0;
    for (size_t t = 0; t < 4; t++) {
        aa_pattern p;
        if (t < 3) {
            preset_pattern(&p, names[t]);
        } else {
            /* two samples on a line at 117.5 degrees tie at 27.5, between table angles; with
             * the uniform table that is the maximum */
            double c = 0.3 * cos(117.5 * REF_PI / 180), sn = 0.3 * sin(117.5 * REF_PI / 180);
            aa_sample pair[2] = {{c, sn, 0.5}, {-c, -sn, 0.5}};
            const aa_sample *ks[1] = {pair};
            size_t counts[1] = {2};
            aa_error e;
            assert_int_equal(aa_pattern_from_kernels(&p, ks, counts, 1, 0, &e), AA_OK);
        }
        aa_acuity uni;
        aa_acuity_uniform(&uni);
        aa_metric_params mp = {.filter = &filter, .acuity = t < 3 ? &acuity : &uni};
        aa_dense_check dc;
        aa_error err;
        assert_int_equal(aa_evaluate_dense(&p, &mp, 0.25, &dc, &err), AA_OK);
        long double best = 0.0L, table = 0.0L;
        for (size_t k = 0; k < p.kernel_count; k++) {
            for (int a = 0; a < 720; a++) {
                double deg = 0.25 * a;
                long double v =
                    (t < 3 ? ref_naiman_weight(deg) : 1.0) * ref_kernel_e1(&p.kernels[k], deg);
                if (v > best)
                    best = v;
                if (a % 20 == 0 && v > table)
                    table = v;
            }
        }
        print_message("%-13s dense max %.6f at kernel %zu %.2f deg, table max %.6f, between: %d "
                      "(reference dense %.6Lf, table %.6Lf)\n",
                      names[t], dc.max_weighted, dc.argmax_kernel, dc.argmax_angle_deg,
                      dc.table_max, dc.between_table_angles, best, table);
        assert_true(dc.step_deg == 0.25);
        assert_true(fabsl(dc.max_weighted - best) <= 1e-12L * best);
        assert_true(fabsl(dc.table_max - table) <= 1e-12L * table);
        assert_true(dc.between_table_angles == (best > table * (1.0L + 1e-9L)));
        long double at = (t < 3 ? ref_naiman_weight(dc.argmax_angle_deg) : 1.0) *
                         ref_kernel_e1(&p.kernels[dc.argmax_kernel], dc.argmax_angle_deg);
        assert_true(fabsl(at - best) <= 1e-12L * best);
        betweens += dc.between_table_angles;
        aa_pattern_free(&p);
    }
    assert_int_equal(betweens, 1); /* the tilted pair */
    aa_pattern p;
    preset_pattern(&p, "rgss");
    aa_metric_params mp = {.filter = &filter, .acuity = &acuity};
    aa_dense_check dc;
    aa_error err;
    const double bad_steps[4] = {0.0, -1.0, NAN, INFINITY};
    for (int i = 0; i < 4; i++)
        assert_true(aa_evaluate_dense(&p, &mp, bad_steps[i], &dc, &err) < 0);
    aa_pattern_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table_and_norms),
        cmocka_unit_test(test_custom_angles_and_uniform),
        cmocka_unit_test(test_parameter_errors),
        cmocka_unit_test(test_dense_check),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
