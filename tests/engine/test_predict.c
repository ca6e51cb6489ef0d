/* The edge model's prediction against real renders: a long edge at a generic angle (the model's
 * assumption holds), a pixel-locked edge (evaluated as a sampled sum), and the bookkeeping. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdbool.h>
#include <stdio.h>

#include "aa_render.h"

static const char *const presets[] = {"centroid", "diagonal", "grid-2x2", "rgss",
                                      "quincunx", "flipquad", "d3d-8x"};
#define PRESET_COUNT (sizeof presets / sizeof presets[0])

static aa_pattern preset(const char *name)
{
    aa_pattern p;
    const aa_preset *pr = aa_preset_find(name);
    assert_non_null(pr);
    assert_int_equal(aa_pattern_from_preset(&p, pr, NULL), AA_OK);
    return p;
}

static double predicted(const aa_pattern *p, const aa_scene_params *sp, aa_prediction *pred)
{
    aa_scene s;
    aa_edge_histogram h;
    assert_int_equal(aa_scene_init(&s, sp, NULL), AA_OK);
    assert_int_equal(aa_edge_histogram_of_scene(&s, &h, NULL), AA_OK);
    assert_int_equal(aa_predict_rmse(p, NULL, &h, pred, NULL), AA_OK);
    return pred->rmse;
}

static double measured(const aa_pattern *p, const aa_scene_params *sp)
{
    aa_render_params rp = aa_render_params_default(sp->shape);
    rp.scene = *sp;
    rp.reference.spp = 256;
    aa_render_result r;
    assert_int_equal(aa_render_tile(&rp, p, &r, NULL), AA_OK);
    double rmse = r.diff.rmse;
    aa_render_result_free(&r);
    return rmse;
}

/* Ratios measured / predicted over the presets, within [lo, hi]. */
static void check_scene(const aa_scene_params *sp, double lo, double hi, const char *what)
{
    for (size_t k = 0; k < PRESET_COUNT; k++) {
        aa_pattern p = preset(presets[k]);
        aa_prediction pred;
        double want = measured(&p, sp), got = predicted(&p, sp, &pred);
        double ratio = want / got;
        printf("%-12s %-10s measured %.4f predicted %.4f ratio %.3f\n", what, presets[k], want, got,
               ratio);
        if (!(ratio >= lo && ratio <= hi))
            fail_msg("%s, %s: measured/predicted %.3f outside [%g, %g]", what, presets[k], ratio,
                     lo, hi);
        aa_pattern_free(&p);
    }
}

/* A 128 x 128 half-plane at 27°: one long edge at a generic angle. */
static void test_long_edge_matches_render(void **state)
{
    (void)state;
    aa_scene_params sp = aa_scene_params_default(AA_SCENE_HALF_PLANE);
    sp.width = sp.height = 128;
    sp.angle_deg = 27;
    sp.offset = 0.37;
    check_scene(&sp, 0.85, 1.15, "half-27");
}

/* Locked edges: the default half-plane (a vertical edge on a pixel boundary), a row, a diagonal
 * and a (2, 1) direction. The integral model would be off; the sampled sum over the lattice
 * period is exact up to the reference's noise. */
static void test_locked_edge_matches_render(void **state)
{
    (void)state;
    aa_scene_params sp = aa_scene_params_default(AA_SCENE_HALF_PLANE);
    sp.width = sp.height = 128;
    check_scene(&sp, 0.97, 1.03, "half-0");
    sp.angle_deg = 90;
    sp.offset = 0.3;
    check_scene(&sp, 0.97, 1.03, "half-90");
    /* A diagonal edge meets the grid at offsets 1/sqrt(2) apart: locked too. */
    sp.angle_deg = 45;
    sp.offset = 0.37;
    check_scene(&sp, 0.97, 1.03, "half-45");
    sp.angle_deg = 180 - atan(0.5) * 180 / 3.14159265358979323846; /* normal (-2, 1) */
    sp.offset = -2.1;
    check_scene(&sp, 0.97, 1.03, "half-153.4");
}

/* The model against the render's own reference (predict.h, AA_PREDICT_EXACT_REFERENCE): the
 * half-plane's line summed over its pixels against g_θ is what the render measures, up to the
 * reference's noise, at 27° (2:1 + 0.4°, where L·E1² misranks presets), mirrored, and on the
 * triangle (sides summed, corners not modelled). The histogram keeps the segments. */
static void check_reference_model(const aa_scene_params *sp, double lo, double hi, const char *what)
{
    aa_scene s;
    aa_edge_histogram h;
    assert_int_equal(aa_scene_init(&s, sp, NULL), AA_OK);
    assert_int_equal(aa_edge_histogram_of_scene(&s, &h, NULL), AA_OK);
    aa_predict_tables *t = NULL;
    assert_int_equal(aa_predict_tables_new(NULL, &h, NULL, &t, NULL), AA_OK);
    for (size_t k = 0; k < PRESET_COUNT; k++) {
        aa_pattern p = preset(presets[k]);
        aa_prediction pred, fresh;
        assert_int_equal(
            aa_predict_rmse_tables(&p, NULL, &h, AA_PREDICT_EXACT_REFERENCE, t, &pred, NULL),
            AA_OK);
        /* Shared tables or built for the call: the same. */
        assert_int_equal(
            aa_predict_rmse_with(&p, NULL, &h, AA_PREDICT_EXACT_REFERENCE, &fresh, NULL), AA_OK);
        assert_true(pred.rmse == fresh.rmse);
        assert_true(pred.segment_sq > 0 && pred.segment_sq <= pred.sum_sq);
        double ratio = measured(&p, sp) / pred.rmse;
        printf("%-12s %-10s reference model: ratio %.4f\n", what, presets[k], ratio);
        if (!(ratio >= lo && ratio <= hi))
            fail_msg("%s, %s: measured/predicted %.4f outside [%g, %g]", what, presets[k], ratio,
                     lo, hi);
        aa_pattern_free(&p);
    }
    aa_predict_tables_free(t);
}

static void test_reference_model_matches_render(void **state)
{
    (void)state;
    aa_scene_params sp = aa_scene_params_default(AA_SCENE_HALF_PLANE);
    sp.width = sp.height = 128;
    sp.angle_deg = 27;
    sp.offset = 0.37;
    aa_scene s;
    aa_edge_histogram h;
    assert_int_equal(aa_scene_init(&s, &sp, NULL), AA_OK);
    assert_int_equal(aa_edge_histogram_of_scene(&s, &h, NULL), AA_OK);
    assert_int_equal(h.segment_count, 1);
    assert_true(h.segment[0].open0 && h.segment[0].open1);
    assert_true(fabs(h.segment[0].length - h.total) < 1e-9);
    check_reference_model(&sp, 0.99, 1.01, "half-27");
    sp.mirror_x = true;
    check_reference_model(&sp, 0.99, 1.01, "half-27-mx");
    aa_scene_params tri = aa_scene_params_default(AA_SCENE_ROTATING_TRIANGLE);
    tri.width = tri.height = 128;
    tri.angle_deg = 11;
    check_reference_model(&tri, 0.98, 1.02, "triangle-11");
    /* The locked default half-plane keeps no segment. */
    aa_scene_params locked = aa_scene_params_default(AA_SCENE_HALF_PLANE);
    assert_int_equal(aa_scene_init(&s, &locked, NULL), AA_OK);
    assert_int_equal(aa_edge_histogram_of_scene(&s, &h, NULL), AA_OK);
    assert_int_equal(h.segment_count, 0);
}

static void test_bookkeeping(void **state)
{
    (void)state;
    aa_pattern p = preset("rgss");
    aa_scene_params sp = aa_scene_params_default(AA_SCENE_SIEMENS_STAR);
    aa_prediction pred;
    predicted(&p, &sp, &pred);
    double sum = 0;
    for (int d = 0; d < AA_EDGE_BINS; d++)
        sum += pred.bin_sq[d];
    assert_true(fabs(sum - pred.sum_sq) <= 1e-12 * sum);
    assert_true(pred.locked_sq > 0 && pred.locked_sq < pred.sum_sq);
    assert_true(fabs(pred.rmse - 255 * sqrt(pred.sum_sq / (256.0 * 256.0))) < 1e-12);
    assert_true(pred.subpixel_area_share > 0 && pred.subpixel_area_share < 0.01);
    /* A bin's part is its length times the mean squared E1 there. */
    aa_scene s;
    aa_edge_histogram h;
    assert_int_equal(aa_scene_init(&s, &sp, NULL), AA_OK);
    assert_int_equal(aa_edge_histogram_of_scene(&s, &h, NULL), AA_OK);
    assert_true(fabs(pred.bin_sq[101] - h.length[101] * pred.e1_rms[101] * pred.e1_rms[101]) <
                1e-12 * pred.bin_sq[101]);
    /* An empty pattern is an error naming the pattern. */
    aa_pattern empty = {0};
    aa_error err = {0};
    assert_int_equal(aa_predict_rmse(&empty, NULL, &h, &pred, &err), AA_EINVAL);
    assert_string_equal(err.field, "pattern");
    aa_pattern_free(&p);
}

/* E1 at every bin: the prediction's values where the scene has edges, and a value everywhere. */
static void test_e1_at_every_bin(void **state)
{
    (void)state;
    aa_pattern p = preset("quincunx");
    aa_scene_params sp = aa_scene_params_default(AA_SCENE_SLIVER);
    aa_prediction pred;
    predicted(&p, &sp, &pred);
    double all[AA_EDGE_BINS];
    assert_int_equal(aa_predict_e1_rms(&p, NULL, NULL, all, NULL), AA_OK);
    int with_edges = 0;
    for (int d = 0; d < AA_EDGE_BINS; d++) {
        assert_true(all[d] > 0);
        if (pred.e1_rms[d] > 0) {
            with_edges++;
            assert_true(fabs(all[d] - pred.e1_rms[d]) <= 1e-12 * pred.e1_rms[d]);
        }
    }
    assert_true(with_edges >= 3); /* the sliver's three sides */
    /* Only the bins asked for; the others stay 0. */
    bool want[AA_EDGE_BINS] = {false};
    want[30] = true;
    double some[AA_EDGE_BINS];
    assert_int_equal(aa_predict_e1_rms(&p, NULL, want, some, NULL), AA_OK);
    assert_true(fabs(some[30] - all[30]) <= 1e-12 * all[30]);
    assert_true(some[29] == 0 && some[31] == 0);
    aa_pattern empty = {0};
    aa_error err = {0};
    assert_int_equal(aa_predict_e1_rms(&empty, NULL, NULL, all, &err), AA_EINVAL);
    assert_string_equal(err.field, "pattern");
    /* Against g_θ with tables shared by the caller (as POST /v1/predict does): the values of
     * tables built in the call, and different from E1 against g off the axes. */
    aa_predict_tables *t = NULL;
    assert_int_equal(aa_predict_tables_new(NULL, NULL, NULL, &t, NULL), AA_OK);
    double own[AA_EDGE_BINS], shared[AA_EDGE_BINS];
    assert_int_equal(
        aa_predict_e1_rms_with(&p, NULL, NULL, AA_PREDICT_REFERENCE_PROFILE, own, NULL), AA_OK);
    assert_int_equal(
        aa_predict_e1_rms_tables(&p, NULL, NULL, AA_PREDICT_REFERENCE_PROFILE, t, shared, NULL),
        AA_OK);
    for (int d = 0; d < AA_EDGE_BINS; d++)
        assert_true(own[d] == shared[d]);
    assert_true(fabs(shared[30] - all[30]) > 1e-6 * all[30]);
    aa_predict_tables_free(t);
    /* Tables lacking a bin are refused. */
    assert_int_equal(aa_predict_tables_new(NULL, NULL, want, &t, NULL), AA_OK);
    assert_int_equal(
        aa_predict_e1_rms_tables(&p, NULL, NULL, AA_PREDICT_REFERENCE_PROFILE, t, shared, &err),
        AA_EINVAL);
    assert_string_equal(err.field, "tables");
    assert_int_equal(
        aa_predict_e1_rms_tables(&p, NULL, want, AA_PREDICT_REFERENCE_PROFILE, t, shared, NULL),
        AA_OK);
    assert_true(shared[30] == own[30]);
    aa_predict_tables_free(t);
    aa_pattern_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_long_edge_matches_render),
        cmocka_unit_test(test_locked_edge_matches_render),
        cmocka_unit_test(test_reference_model_matches_render),
        cmocka_unit_test(test_bookkeeping),
        cmocka_unit_test(test_e1_at_every_bin),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
