/* Edge histograms: each analytic histogram's total against the scene's known edge length, the
 * angle convention, locked (lattice-direction) edges, mirroring. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include "aa_render.h"

#define PI 3.14159265358979323846

static aa_edge_histogram histogram_of(aa_scene_params p, aa_scene *s)
{
    aa_error err = {0};
    assert_int_equal(aa_scene_init(s, &p, &err), AA_OK);
    aa_edge_histogram h;
    assert_int_equal(aa_edge_histogram_of_scene(s, &h, &err), AA_OK);
    double sum = 0;
    for (int d = 0; d < AA_EDGE_BINS; d++) {
        assert_true(h.length[d] >= 0);
        sum += h.length[d];
    }
    for (size_t k = 0; k < h.locked_count; k++)
        sum += h.locked[k].length;
    assert_true(fabs(sum - h.total) <= 1e-9 * (1 + h.total));
    return h;
}

static void assert_rel(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol * fabs(want)))
        fail_msg("got %.9g, want %.9g (relative tolerance %g)", got, want, tol);
}

static void test_bins(void **state)
{
    (void)state;
    assert_int_equal(aa_edge_bin(0), 0);
    assert_int_equal(aa_edge_bin(0.49), 0);
    assert_int_equal(aa_edge_bin(0.5), 1);
    assert_int_equal(aa_edge_bin(-0.4), 0);
    assert_int_equal(aa_edge_bin(179.6), 0);
    assert_int_equal(aa_edge_bin(210), 30);
    assert_int_equal(aa_edge_bin(-30), 150);
}

/* A line through the centre at normal angle 30°: the chord 256 / cos 30°, all in bin 30. */
static void test_half_plane(void **state)
{
    (void)state;
    aa_scene s;
    aa_scene_params p = aa_scene_params_default(AA_SCENE_HALF_PLANE);
    p.angle_deg = 30;
    aa_edge_histogram h = histogram_of(p, &s);
    assert_rel(h.total, 256 / cos(30 * PI / 180), 1e-12);
    assert_rel(h.length[30], h.total, 1e-12);
    assert_int_equal(h.locked_count, 0);
    /* 120°: the same line turned; 3.7 px off centre still crosses top and bottom. */
    p.angle_deg = 120;
    p.offset = 3.7;
    h = histogram_of(p, &s);
    assert_rel(h.length[120], 256 / cos(30 * PI / 180), 1e-12);
    /* Default: the vertical edge x = 128 is pixel-locked, no bin holds it. */
    h = histogram_of(aa_scene_params_default(AA_SCENE_HALF_PLANE), &s);
    assert_int_equal(h.locked_count, 1);
    assert_int_equal(h.locked[0].q, 0);
    assert_rel(h.locked[0].c / h.locked[0].p, 128, 1e-12);
    assert_rel(h.locked[0].length, 256, 1e-12);
    assert_rel(h.total, 256, 1e-12);
    /* 90°: a horizontal edge, 10 px below the centre (offset along the normal). */
    p.angle_deg = 90;
    p.offset = 10;
    h = histogram_of(p, &s);
    assert_int_equal(h.locked_count, 1);
    assert_int_equal(h.locked[0].p, 0);
    assert_rel(h.locked[0].c / h.locked[0].q, 138, 1e-9);
    /* 45°: the normal (1, 1) is a lattice direction, locked too; 30° is not. */
    p.angle_deg = 45;
    p.offset = 0.37;
    h = histogram_of(p, &s);
    assert_int_equal(h.locked_count, 1);
    assert_int_equal(abs(h.locked[0].p), 1);
    assert_int_equal(h.locked[0].q, h.locked[0].p);
    assert_int_equal(aa_locked_edge_bin(&h.locked[0]), 45);
    assert_rel(h.total, sqrt(2.0) * (256 - 0.37 * sqrt(2.0)), 1e-9);
}

static double dist(double ax, double ay, double bx, double by)
{
    return hypot(ax - bx, ay - by);
}

/* The sliver's vertices in scene units (scene.c), rotated by the angle: perimeter × unit. */
static void test_sliver(void **state)
{
    (void)state;
    const double u[3][2] = {{-0.9, 0.45}, {0.9, -0.2}, {0.9, -0.05}};
    double perimeter = 0;
    for (int k = 0; k < 3; k++)
        perimeter += dist(u[k][0], u[k][1], u[(k + 1) % 3][0], u[(k + 1) % 3][1]);
    aa_scene s;
    aa_scene_params p = aa_scene_params_default(AA_SCENE_SLIVER);
    aa_edge_histogram h = histogram_of(p, &s);
    assert_rel(h.total, perimeter * 128, 1e-9);
    /* At the default angle the short side x = 0.9 u is vertical: locked, 0.15 u long. */
    assert_int_equal(h.locked_count, 1);
    assert_rel(h.locked[0].length, 0.15 * 128, 1e-9);
    assert_int_equal(h.locked[0].q, 0);
    assert_rel(h.locked[0].c / h.locked[0].p, 128 + 0.9 * 128, 1e-9);
    /* The long sides' normals: 90° plus their slopes' angles. */
    assert_true(h.length[aa_edge_bin(90 + atan2(-0.65, 1.8) * 180 / PI)] > 0);
    p.angle_deg = 8;
    h = histogram_of(p, &s);
    assert_rel(h.total, perimeter * 128, 1e-9);
    assert_int_equal(h.locked_count, 0);
    assert_rel(h.length[8], 0.15 * 128, 1e-9); /* the short side turned by 8° */
}

static void test_triangle_and_circle(void **state)
{
    (void)state;
    aa_scene s;
    aa_scene_params p = aa_scene_params_default(AA_SCENE_ROTATING_TRIANGLE);
    p.frame = 3;
    aa_edge_histogram h = histogram_of(p, &s);
    assert_rel(h.total, 3 * sqrt(3.0) * 0.75 * 128, 1e-9);
    p = aa_scene_params_default(AA_SCENE_TRANSLATING_CIRCLE);
    h = histogram_of(p, &s);
    assert_rel(h.total, 2 * PI * 0.35 * 128, 1e-9);
    /* Every degree of normal angle holds two opposite degrees of arc. */
    for (int d = 0; d < AA_EDGE_BINS; d++)
        assert_rel(h.length[d], 2 * 0.35 * 128 * PI / 180, 1e-9);
    /* Zoom 2, centred: larger, still inside. */
    p.zoom = 2;
    p.frame = 8; /* centred horizontally */
    h = histogram_of(p, &s);
    assert_true(s.ring[0].cy + s.ring[0].r_out < 256);
    assert_rel(h.total, 2 * PI * s.ring[0].r_out, 1e-9);
}

static void test_rings(void **state)
{
    (void)state;
    aa_scene s;
    aa_edge_histogram h = histogram_of(aa_scene_params_default(AA_SCENE_RINGS), &s);
    double want = 0;
    for (int k = 0; k < 9; k++) {
        double r_out = (0.04 + 0.032 * k) * 128;
        want += 2 * PI * (r_out + (k % 2 ? 0.6 * r_out : 0));
    }
    assert_rel(h.total, want, 1e-9);
    assert_int_equal(h.locked_count, 0);
    assert_true(h.subpixel_area == 0);
}

/* 2N rays from r_c = 1 / sector (where neighbours are 1 px apart) to R, and the dark half of the
 * rim; the rays at multiples of 45° are locked. */
static void test_star(void **state)
{
    (void)state;
    aa_scene s;
    aa_edge_histogram h = histogram_of(aa_scene_params_default(AA_SCENE_SIEMENS_STAR), &s);
    double R = 0.95 * 128, sector = PI / 16, r_c = 1 / sector;
    assert_rel(h.total, 32 * (R - r_c) + PI * R, 1e-9);
    assert_int_equal(h.locked_count, 8); /* the rays at multiples of 45° */
    for (size_t k = 0; k < 8; k++)
        assert_rel(h.locked[k].length, R - r_c, 1e-9);
    /* Pixel centres inside r_c: the disc's area within a perimeter's worth. */
    assert_true(fabs(h.subpixel_area - PI * r_c * r_c) <= 2 * PI * r_c);
    /* A ray at 11.25° has its normal at 101.25°: bin 101, with the rim's own degree of arc. */
    assert_true(h.length[101] > R - r_c);
}

/* Archimedean arcs d = b psi, b = pitch / 2 pi, each psi in (0, R / b] covered by two curves,
 * plus half the rim: 2 S(R / b) + pi R with S(psi) = b/2 (psi sqrt(psi² + 1) + asinh psi). */
static void test_spiral(void **state)
{
    (void)state;
    aa_scene s;
    aa_edge_histogram h = histogram_of(aa_scene_params_default(AA_SCENE_SPIRAL), &s);
    double R = 0.95 * 128, b = 0.16 * 128 / (2 * PI), psi = R / b;
    double S = b / 2 * (psi * sqrt(psi * psi + 1) + asinh(psi));
    assert_rel(h.total, 2 * S + PI * R, 1e-3);
    /* Nearly circular arcs: every bin holds some. */
    for (int d = 0; d < AA_EDGE_BINS; d++)
        assert_true(h.length[d] > 0);
}

/* The checkerboard: the horizon (contrast 1/2, length W, weight 1/4) is locked; the board's
 * lines stop where cells get below the pixel; the mirrored board at -a has the same edges as
 * the board at a (mirrored). */
static void test_checkerboard(void **state)
{
    (void)state;
    aa_scene s;
    aa_scene_params p = aa_scene_params_default(AA_SCENE_CHECKERBOARD);
    aa_edge_histogram h = histogram_of(p, &s);
    size_t horizon = 0;
    for (size_t k = 0; k < h.locked_count; k++)
        if (h.locked[k].p == 0 && fabs(h.locked[k].c / h.locked[k].q - s.horizon_y) < 1e-9) {
            horizon++;
            assert_rel(h.locked[k].length, 0.25 * 256, 1e-12);
        }
    assert_int_equal(horizon, 1);
    double ground = 256 * (256 - s.horizon_y);
    assert_true(h.subpixel_area > 0.01 * ground && h.subpixel_area < 0.5 * ground);
    assert_true(h.total > 10 * 256);
    aa_scene_params q = p;
    q.angle_deg = -20;
    q.mirror_x = true;
    aa_scene t;
    aa_edge_histogram g = histogram_of(q, &t);
    assert_rel(g.total, h.total, 1e-6);
    for (int d = 0; d < AA_EDGE_BINS; d++)
        assert_true(fabs(g.length[d] - h.length[d]) <= 1e-6 * h.total);
    /* Angle 0: the gz lines are rows (locked), the gx lines meet at the vanishing point. */
    p.angle_deg = 0;
    h = histogram_of(p, &s);
    assert_true(h.locked_count > 2);
    assert_true(h.locked_excess == 0);
}

/* Zoomed far in or out, every scene's histogram is bounded by the image (the work too: a
 * spiral at zoom 1000 only integrates the arcs the image shows). */
static void test_zoom_extremes(void **state)
{
    (void)state;
    for (int k = 0; k < AA_SCENE_SHAPE_COUNT; k++)
        for (int z = 0; z < 2; z++) {
            aa_scene_params p = aa_scene_params_default((aa_scene_shape)k);
            p.width = p.height = 512;
            p.zoom = z ? 1000 : 0.001;
            aa_scene s;
            aa_edge_histogram h = histogram_of(p, &s);
            assert_true(h.total >= 0 && isfinite(h.total));
            assert_true(h.subpixel_area <= 512.0 * 512.0);
        }
    /* A spiral zoomed so far that the image shows a few nearly straight arcs: each arc crosses
     * the 512 px image once or not at all, so the total is at most a few image widths. */
    aa_scene_params p = aa_scene_params_default(AA_SCENE_SPIRAL);
    p.width = p.height = 512;
    p.zoom = 1000;
    aa_scene s;
    aa_edge_histogram h = histogram_of(p, &s);
    assert_true(h.total < 4 * 512 * sqrt(2.0));
}

/* Mirroring maps a normal at θ to 180° - θ. */
static void test_mirror(void **state)
{
    (void)state;
    aa_scene s;
    aa_scene_params p = aa_scene_params_default(AA_SCENE_HALF_PLANE);
    p.angle_deg = 30;
    p.mirror_x = true;
    aa_edge_histogram h = histogram_of(p, &s);
    assert_rel(h.length[150], h.total, 1e-12);
    p.mirror_y = true;
    h = histogram_of(p, &s);
    assert_rel(h.length[30], h.total, 1e-12);
    p = aa_scene_params_default(AA_SCENE_HALF_PLANE);
    p.offset = 20.5;
    p.mirror_x = true;
    h = histogram_of(p, &s);
    assert_rel(h.locked[0].c / h.locked[0].p, 256 - 148.5, 1e-12);
}

/* The analytic histograms against the ones measured on the reference's gradients: same total
 * within the filter's lobes and the reference's noise, same angles. */
static void test_gradients_agree(void **state)
{
    (void)state;
    aa_scene_params p = aa_scene_params_default(AA_SCENE_HALF_PLANE);
    p.width = p.height = 96;
    p.angle_deg = 30;
    p.offset = 0.4;
    /* Not the sliver: near its tip the two long sides cancel within the filter. */
    const aa_scene_shape shapes[] = {AA_SCENE_HALF_PLANE, AA_SCENE_RINGS,
                                     AA_SCENE_ROTATING_TRIANGLE};
    for (size_t k = 0; k < 3; k++) {
        aa_scene_params q = p;
        q.shape = shapes[k];
        if (shapes[k] != AA_SCENE_HALF_PLANE) {
            q.angle_deg = 0;
            q.offset = 0;
        }
        aa_scene s;
        aa_edge_histogram h = histogram_of(q, &s), g;
        aa_image img;
        assert_int_equal(aa_image_init(&img, 96, 96, NULL), AA_OK);
        aa_reference_params rp = aa_reference_params_default();
        rp.spp = 64;
        assert_int_equal(aa_render_reference(&s, &rp, 0.5, &img, NULL, NULL, NULL), AA_OK);
        assert_int_equal(aa_edge_histogram_from_image(&img, &g, NULL), AA_OK);
        /* The border rows and columns are not measured: up to 2 px per crossing of the edge. */
        double ratio = g.total / h.total;
        if (!(ratio > 0.9 && ratio < 1.1))
            fail_msg("%s: gradient total %.1f, analytic %.1f", aa_scene_shape_name(shapes[k]),
                     g.total, h.total);
        if (shapes[k] == AA_SCENE_HALF_PLANE) {
            double near = 0;
            for (int d = 27; d <= 33; d++)
                near += g.length[d];
            assert_true(near > 0.9 * g.total);
        }
        aa_image_free(&img);
    }
    aa_image tiny;
    assert_int_equal(aa_image_init(&tiny, 2, 5, NULL), AA_OK);
    aa_edge_histogram g;
    assert_int_equal(aa_edge_histogram_from_image(&tiny, &g, NULL), AA_EINVAL);
    aa_image_free(&tiny);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bins),          cmocka_unit_test(test_half_plane),
        cmocka_unit_test(test_sliver),        cmocka_unit_test(test_triangle_and_circle),
        cmocka_unit_test(test_rings),         cmocka_unit_test(test_star),
        cmocka_unit_test(test_spiral),        cmocka_unit_test(test_checkerboard),
        cmocka_unit_test(test_mirror),        cmocka_unit_test(test_gradients_agree),
        cmocka_unit_test(test_zoom_extremes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
