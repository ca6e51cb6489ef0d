/* Scenes: tie rule, conservative box classification, parameters. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>

#include "aa_render.h"

static double lcg01(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

/* A point on a shared edge belongs to exactly one of the two half-planes. */
static void test_tie_rule_counts_shared_edge_once(void **state)
{
    (void)state;
    const double dirs[][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {1, 1}, {-1, 2}, {3, -1}};
    for (size_t d = 0; d < sizeof dirs / sizeof dirs[0]; d++) {
        aa_edge e = aa_edge_through(2, 3, 2 + dirs[d][0], 3 + dirs[d][1]);
        aa_edge f = {-e.a, -e.b, -e.c};
        for (int k = -3; k <= 3; k++) {
            double x = 2 + k * dirs[d][0], y = 3 + k * dirs[d][1];
            assert_true(aa_edge_inside(&e, x, y) != aa_edge_inside(&f, x, y));
        }
    }
    /* Top-left: a left edge (inward normal +x) owns its boundary, a right edge does not. */
    aa_edge left = aa_edge_from_normal(5, 0, 1, 0), right = aa_edge_from_normal(5, 0, -1, 0);
    assert_true(aa_edge_inside(&left, 5, 1));
    assert_false(aa_edge_inside(&right, 5, 1));
    aa_edge top = aa_edge_from_normal(0, 5, 0, 1);
    assert_true(aa_edge_inside(&top, 1, 5));
}

/* Whenever the box test says "uniform", every point of the box has that value. */
static void test_box_uniform_is_conservative(void **state)
{
    (void)state;
    uint64_t rng = 7;
    for (int pass = 0; pass < 2 * AA_SCENE_SHAPE_COUNT; pass++) {
        int shape = pass % AA_SCENE_SHAPE_COUNT;
        aa_scene_params p = aa_scene_params_default((aa_scene_shape)shape);
        p.width = 64;
        p.height = 48;
        p.angle_deg = 13;
        p.frame = 3;
        p.mirror_x = pass >= AA_SCENE_SHAPE_COUNT; /* mirrored boxes too */
        p.mirror_y = pass >= AA_SCENE_SHAPE_COUNT && shape % 2;
        aa_scene s;
        assert_int_equal(aa_scene_init(&s, &p, NULL), AA_OK);
        int uniform = 0;
        for (int trial = 0; trial < 3000; trial++) {
            double x0 = lcg01(&rng) * 70 - 3, y0 = lcg01(&rng) * 54 - 3;
            double w = lcg01(&rng) * (trial % 3 == 0 ? 20 : 4), h = lcg01(&rng) * 4;
            double v;
            if (!aa_scene_box_uniform(&s, x0, y0, x0 + w, y0 + h, &v))
                continue;
            uniform++;
            for (int k = 0; k < 40; k++) {
                double x = x0 + w * (k < 4 ? k % 2 : lcg01(&rng));
                double y = y0 + h * (k < 4 ? k / 2 : lcg01(&rng));
                assert_true(aa_scene_value(&s, x, y) == v);
            }
        }
        assert_true(uniform > 100); /* the test is not vacuous */
    }
}

static void test_scene_names_and_validation(void **state)
{
    (void)state;
    for (int k = 0; k < AA_SCENE_SHAPE_COUNT; k++)
        assert_int_equal(aa_scene_shape_from_name(aa_scene_shape_name((aa_scene_shape)k)), k);
    assert_int_equal(aa_scene_shape_from_name("teapot"), -1);
    aa_scene s;
    aa_error err = {0};
    aa_scene_params p = aa_scene_params_default(AA_SCENE_SIEMENS_STAR);
    p.wedges = 0;
    assert_int_equal(aa_scene_init(&s, &p, &err), AA_EINVAL);
    assert_string_equal(err.field, "wedges");
    p = aa_scene_params_default(AA_SCENE_TRANSLATING_CIRCLE);
    p.frame = p.frames;
    assert_int_equal(aa_scene_init(&s, &p, &err), AA_EINVAL);
    assert_string_equal(err.field, "frame");
    p.frame = 0;
    p.zoom = NAN;
    assert_int_equal(aa_scene_init(&s, &p, &err), AA_EINVAL);
    assert_string_equal(err.field, "zoom");
}

/* The same parameters give the same picture at any resolution (coordinates scale). */
static void test_scene_is_resolution_independent(void **state)
{
    (void)state;
    for (int shape = 0; shape < AA_SCENE_SHAPE_COUNT; shape++) {
        aa_scene_params p = aa_scene_params_default((aa_scene_shape)shape);
        aa_scene a, b;
        p.width = p.height = 100;
        assert_int_equal(aa_scene_init(&a, &p, NULL), AA_OK);
        p.width = p.height = 400;
        assert_int_equal(aa_scene_init(&b, &p, NULL), AA_OK);
        int same = 0;
        for (int k = 0; k < 400; k++) {
            double x = 0.37 + (k % 20) * 4.93, y = 0.61 + (k / 20) * 4.87;
            same += aa_scene_value(&a, x, y) == aa_scene_value(&b, 4 * x, 4 * y);
        }
        assert_true(same >= 398); /* up to rounding exactly on an edge */
    }
}

static void test_checkerboard_has_sky_and_both_colours(void **state)
{
    (void)state;
    aa_scene_params p = aa_scene_params_default(AA_SCENE_CHECKERBOARD);
    aa_scene s;
    assert_int_equal(aa_scene_init(&s, &p, NULL), AA_OK);
    assert_true(aa_scene_value(&s, 128, 10) == 1.0); /* above the horizon */
    int dark = 0;
    for (int x = 0; x < 256; x++)
        dark += aa_scene_value(&s, x + 0.5, 250.5) == 0.0;
    assert_true(dark > 50 && dark < 206);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tie_rule_counts_shared_edge_once),
        cmocka_unit_test(test_box_uniform_is_conservative),
        cmocka_unit_test(test_scene_names_and_validation),
        cmocka_unit_test(test_scene_is_resolution_independent),
        cmocka_unit_test(test_checkerboard_has_sky_and_both_colours),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
