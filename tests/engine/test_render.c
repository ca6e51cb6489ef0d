/* Renderer: reference against analytic values, exact constants, Quincunx by hand, mirroring,
 * sparse == dense, incremental animation == full frames, every scene with every preset. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "aa_pattern.h"
#include "aa_render.h"

#define PI 3.14159265358979323846

static aa_pattern preset(const char *name)
{
    aa_pattern p;
    const aa_preset *pr = aa_preset_find(name);
    assert_non_null(pr);
    assert_int_equal(aa_pattern_from_preset(&p, pr, NULL), AA_OK);
    return p;
}

static aa_scene make_scene(aa_scene_params p)
{
    aa_scene s;
    assert_int_equal(aa_scene_init(&s, &p, NULL), AA_OK);
    return s;
}

/* P(X cos a + Y sin a < -t) for X, Y iid with density h: the filtered half-plane, by
 * composite Simpson over Y on [-R, R] (nodes on the cubic's knots). */
static double analytic_edge(const aa_filter *f, double a, double t)
{
    double c = cos(a), sn = sin(a);
    if (fabs(sn) < 1e-15)
        return aa_filter_cdf(f, -t / c);
    if (fabs(c) < 1e-15)
        return aa_filter_cdf(f, -t / sn);
    const int n = 4000;
    double sum = 0, mass = 0, hstep = 2 * f->radius / n;
    for (int k = 0; k <= n; k++) {
        double y = -f->radius + k * hstep;
        double w = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
        sum += w * aa_filter_eval(f, y) * aa_filter_cdf(f, (-t - y * sn) / c);
        mass += w * aa_filter_eval(f, y);
    }
    return sum / mass; /* the density normalised here, whatever scale eval has */
}

/* The reference's sampling error is measured, not assumed: each pixel is rendered with
 * SEEDS independent seeds; the seed mean must match the analytic value within 5 standard
 * errors (plus the O(1/N) bias of the ratio estimator), and each single render within 6
 * standard deviations. Constant pixels must be exact. */
#define SEEDS 6
static void test_half_plane_matches_analytic_filtered_edge(void **state)
{
    (void)state;
    aa_filter mitchell, gaussian, f;
    aa_filter_default(&mitchell);
    assert_int_equal(aa_filter_by_name(&gaussian, "gaussian", NULL, NULL), AA_OK);
    const double angles[] = {0, 30, 90, 30};
    enum { W = 20 };
    for (size_t ai = 0; ai < 4; ai++) {
        f = ai < 3 ? mitchell : gaussian; /* the generic filter path too */
        aa_scene_params sp = aa_scene_params_default(AA_SCENE_HALF_PLANE);
        sp.width = sp.height = W;
        sp.angle_deg = angles[ai];
        sp.offset = 0.37;
        aa_scene s = make_scene(sp);
        aa_image img[SEEDS];
        aa_reference_stats st;
        for (int k = 0; k < SEEDS; k++) {
            assert_int_equal(aa_image_init(&img[k], W, W, NULL), AA_OK);
            aa_reference_params rp = aa_reference_params_default(); /* 1024 spp */
            rp.seed = 100 + k;
            rp.filter = &f;
            assert_int_equal(aa_render_reference(&s, &rp, 0.5, &img[k], NULL, &st, NULL), AA_OK);
        }
        double a = angles[ai] * PI / 180, worst_z = 0, worst_sd = 0;
        for (int j = 0; j < W; j++)
            for (int i = 0; i < W; i++) {
                /* Signed distance of the output point along the normal, from the edge. */
                double t = (i + 0.5 - W / 2) * cos(a) + (j + 0.5 - W / 2) * sin(a) - sp.offset;
                double want = analytic_edge(&f, a, t), mean = 0, var = 0;
                for (int k = 0; k < SEEDS; k++)
                    mean += img[k].px[j * W + i] / (double)SEEDS;
                for (int k = 0; k < SEEDS; k++) {
                    double d = img[k].px[j * W + i] - mean;
                    var += d * d / (SEEDS - 1);
                }
                double sd = sqrt(var);
                if (sd == 0) {
                    assert_true(want == 0 || want == 1 || fabs(want - mean) < 1e-12);
                    assert_true(mean == 0 || mean == 1);
                    continue;
                }
                worst_sd = fmax(worst_sd, sd);
                double z = fabs(mean - want) / (sd / sqrt(SEEDS) + 2e-5);
                worst_z = fmax(worst_z, z);
                if (z >= 5)
                    print_message("pixel %d,%d t=%.3f mean %.6f want %.6f sd %.2g\n", i, j, t, mean,
                                  want, sd);
                assert_true(z < 5);
                for (int k = 0; k < SEEDS; k++)
                    assert_true(fabs(img[k].px[j * W + i] - want) < 6 * sd + 2e-5);
            }
        print_message("%s, angle %g: max sampling sd %.2g, max |mean-analytic|/se %.2f\n", f.name,
                      angles[ai], worst_sd, worst_z);
        assert_true(worst_sd < 4e-3); /* 1024 spp: under one grey level (255 scale) */
        assert_true(st.pixels_supersampled > 0 && st.pixels_supersampled < W * W);
        for (int k = 0; k < SEEDS; k++)
            aa_image_free(&img[k]);
    }
}

static void test_far_pixels_are_exact_and_not_sampled(void **state)
{
    (void)state;
    aa_scene_params sp = aa_scene_params_default(AA_SCENE_SIEMENS_STAR);
    sp.width = sp.height = 48;
    aa_scene s = make_scene(sp);
    aa_image img;
    assert_int_equal(aa_image_init(&img, 48, 48, NULL), AA_OK);
    aa_reference_params rp = aa_reference_params_default();
    rp.spp = 64;
    aa_reference_stats st;
    assert_int_equal(aa_render_reference(&s, &rp, 0.5, &img, NULL, &st, NULL), AA_OK);
    assert_true(img.px[0] == 1.0f); /* corner: background, footprint far from the star */
    assert_true(st.pixels_supersampled < 48 * 48);
    /* A wedge interior well away from the centre and the sector edges is exact too. */
    aa_scene_params big = sp;
    big.width = big.height = 400;
    big.wedges = 4;
    aa_scene sb = make_scene(big);
    aa_image im2;
    assert_int_equal(aa_image_init(&im2, 400, 400, NULL), AA_OK);
    aa_rect one = {300, 250, 301, 251};
    assert_int_equal(aa_render_reference(&sb, &rp, 0.5, &im2, &one, &st, NULL), AA_OK);
    assert_int_equal(st.pixels_supersampled, 0);
    assert_true(im2.px[250 * 400 + 300] == (float)aa_scene_value(&sb, 300.5, 250.5));
    aa_image_free(&img);
    aa_image_free(&im2);
}

/* Quincunx: centre 1/2, four shared corners 1/8. Vertical edge, value 1 left of it. */
static void test_quincunx_vertical_edge_by_hand(void **state)
{
    (void)state;
    aa_pattern q = preset("quincunx");
    const struct {
        double edge_x;
        float want[4]; /* pixels 8..11 */
    } cases[] = {
        {10.3, {1, 1, 0.25f, 0}}, /* pixel 10: only its two left corners (x = 10) covered */
        {10.7, {1, 1, 0.75f, 0}}, /* pixel 10: centre 10.5 and left corners */
        {10.0, {1, 0.75f, 0, 0}}, /* tie: a right edge does not own x = 10 */
    };
    for (size_t c = 0; c < 3; c++) {
        aa_scene_params sp = aa_scene_params_default(AA_SCENE_HALF_PLANE);
        sp.width = sp.height = 16;
        sp.offset = cases[c].edge_x - 8;
        aa_scene s = make_scene(sp);
        aa_image img;
        assert_int_equal(aa_image_init(&img, 16, 16, NULL), AA_OK);
        aa_raster_stats st;
        assert_int_equal(aa_render_pattern(&s, &q, true, &img, NULL, &st, NULL), AA_OK);
        for (int j = 0; j < 16; j++)
            for (int i = 8; i < 12; i++)
                assert_float_equal(img.px[j * 16 + i], cases[c].want[i - 8], 1e-6);
        /* Shared corners: 2 samples per pixel evaluated at most, 16 x 2 per sampled column. */
        assert_true(st.samples_evaluated <= 2 * 17 * 3 + 17);
        aa_image_free(&img);
    }
    aa_pattern_free(&q);
}

static void assert_mirror_equal(const aa_image *a, const aa_image *b, bool mx, bool my)
{
    int W = a->width, H = a->height;
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            int si = mx ? W - 1 - i : i, sj = my ? H - 1 - j : j;
            assert_float_equal(a->px[j * W + i], b->px[sj * W + si], 1e-6);
        }
}

static void test_mirrored_patterns_render_mirror_images(void **state)
{
    (void)state;
    const char *names[] = {"flipquad", "fliptri"};
    const aa_scene_shape shapes[] = {AA_SCENE_SIEMENS_STAR, AA_SCENE_SLIVER, AA_SCENE_RINGS};
    for (size_t n = 0; n < 2; n++) {
        aa_pattern p = preset(names[n]);
        assert_int_equal(p.form, AA_FORM_MIRRORED);
        for (size_t k = 0; k < 3; k++) {
            aa_scene_params sp = aa_scene_params_default(shapes[k]);
            sp.width = 40;
            sp.height = 36;
            sp.angle_deg = 7.3; /* no sample exactly on an edge */
            aa_image base, other;
            assert_int_equal(aa_image_init(&base, 40, 36, NULL), AA_OK);
            assert_int_equal(aa_image_init(&other, 40, 36, NULL), AA_OK);
            aa_scene s = make_scene(sp);
            assert_int_equal(aa_render_pattern(&s, &p, true, &base, NULL, NULL, NULL), AA_OK);
            for (int m = 1; m < 4; m++) {
                aa_scene_params mp = sp;
                mp.mirror_x = m & 1;
                mp.mirror_y = (m & 2) != 0;
                aa_scene ms = make_scene(mp);
                assert_int_equal(aa_render_pattern(&ms, &p, true, &other, NULL, NULL, NULL), AA_OK);
                assert_mirror_equal(&base, &other, mp.mirror_x, mp.mirror_y);
            }
            aa_image_free(&base);
            aa_image_free(&other);
        }
        aa_pattern_free(&p);
    }
}

/* Leaving out constant pixels changes nothing for patterns (bit-identical), and for the
 * reference only replaces sampling noise by exact integrals: equal within the sampling error. */
static void test_sparse_equals_dense(void **state)
{
    (void)state;
    aa_pattern p = preset("rgss");
    for (int shape = 0; shape < AA_SCENE_SHAPE_COUNT; shape++) {
        aa_scene_params sp = aa_scene_params_default((aa_scene_shape)shape);
        sp.width = 40;
        sp.height = 32;
        aa_scene s = make_scene(sp);
        aa_image a, b;
        assert_int_equal(aa_image_init(&a, 40, 32, NULL), AA_OK);
        assert_int_equal(aa_image_init(&b, 40, 32, NULL), AA_OK);
        aa_reference_params rp = aa_reference_params_default();
        rp.spp = 256;
        aa_reference_stats st;
        assert_int_equal(aa_render_reference(&s, &rp, 0.5, &a, NULL, &st, NULL), AA_OK);
        rp.skip = false;
        assert_int_equal(aa_render_reference(&s, &rp, 0.5, &b, NULL, NULL, NULL), AA_OK);
        for (size_t k = 0; k < 40 * 32; k++)
            assert_float_equal(a.px[k], b.px[k], 0.01); /* 256 spp */
        assert_int_equal(aa_render_pattern(&s, &p, true, &a, NULL, NULL, NULL), AA_OK);
        assert_int_equal(aa_render_pattern(&s, &p, false, &b, NULL, NULL, NULL), AA_OK);
        for (size_t k = 0; k < 40 * 32; k++)
            assert_float_equal(a.px[k], b.px[k], 1e-6);
        aa_image_free(&a);
        aa_image_free(&b);
    }
    aa_pattern_free(&p);
}

static void test_animation_recomputes_only_changes(void **state)
{
    (void)state;
    aa_pattern p = preset("flipquad");
    const aa_scene_shape shapes[] = {AA_SCENE_TRANSLATING_CIRCLE, AA_SCENE_ROTATING_TRIANGLE};
    for (size_t k = 0; k < 2; k++) {
        aa_render_params rp = aa_render_params_default(shapes[k]);
        rp.scene.width = 64;
        rp.scene.height = 48;
        rp.scene.zoom = 0.6;
        rp.scene.frames = 4;
        rp.reference.spp = 16;
        aa_animation an;
        assert_int_equal(aa_animation_init(&an, &rp, &p, NULL), AA_OK);
        size_t recomputed_later = 0;
        for (int f = 0; f < 4; f++) {
            aa_animation_frame_stats fs;
            assert_int_equal(aa_animation_frame(&an, &fs, NULL), AA_OK);
            if (f > 0)
                recomputed_later += fs.pixels_recomputed;
            aa_render_params full = rp;
            full.scene.frame = f;
            aa_render_result r;
            assert_int_equal(aa_render_tile(&full, &p, &r, NULL), AA_OK);
            assert_memory_equal(r.reference.px, an.reference_img.px, 64 * 48 * sizeof(float));
            assert_memory_equal(r.pattern.px, an.pattern_img.px, 64 * 48 * sizeof(float));
            assert_true(fabs(r.diff.rmse - fs.diff.rmse) < 1e-9);
            aa_render_result_free(&r);
        }
        assert_true(recomputed_later < 3 * 64 * 48);
        assert_int_not_equal(aa_animation_frame(&an, &(aa_animation_frame_stats){0}, NULL), AA_OK);
        aa_animation_free(&an);
    }
    aa_pattern_free(&p);
}

static void test_every_scene_with_every_preset(void **state)
{
    (void)state;
    for (size_t pi = 0; pi < aa_preset_count(); pi++) {
        aa_pattern p;
        assert_int_equal(aa_pattern_from_preset(&p, aa_preset_at(pi), NULL), AA_OK);
        for (int shape = 0; shape < AA_SCENE_SHAPE_COUNT; shape++) {
            aa_render_params rp = aa_render_params_default((aa_scene_shape)shape);
            rp.scene.width = 20;
            rp.scene.height = 18;
            rp.reference.spp = 4;
            aa_render_result r;
            aa_error err = {0};
            assert_int_equal(aa_render_tile(&rp, &p, &r, &err), AA_OK);
            assert_true(r.e2 > 0 && isfinite(r.e2));
            for (size_t k = 0; k < 20 * 18; k++) {
                assert_true(r.pattern.px[k] > -0.5f && r.pattern.px[k] < 1.5f);
                assert_true(r.reference.px[k] > -0.5f && r.reference.px[k] < 1.5f);
            }
            assert_true(r.diff.rmse >= 0 && r.diff.max_dev <= 255 * 2);
            aa_render_result_free(&r);
        }
        aa_pattern_free(&p);
    }
}

static void test_reference_is_deterministic_and_spp_validated(void **state)
{
    (void)state;
    aa_scene_params sp = aa_scene_params_default(AA_SCENE_SPIRAL);
    sp.width = sp.height = 24;
    aa_scene s = make_scene(sp);
    aa_image a, b;
    assert_int_equal(aa_image_init(&a, 24, 24, NULL), AA_OK);
    assert_int_equal(aa_image_init(&b, 24, 24, NULL), AA_OK);
    aa_reference_params rp = aa_reference_params_default();
    rp.spp = 64;
    rp.seed = 42;
    assert_int_equal(aa_render_reference(&s, &rp, 1.0, &a, NULL, NULL, NULL), AA_OK);
    assert_int_equal(aa_render_reference(&s, &rp, 1.0, &b, NULL, NULL, NULL), AA_OK);
    assert_memory_equal(a.px, b.px, sizeof(float) * 24 * 24);
    rp.seed = 43;
    assert_int_equal(aa_render_reference(&s, &rp, 1.0, &b, NULL, NULL, NULL), AA_OK);
    assert_true(memcmp(a.px, b.px, sizeof(float) * 24 * 24) != 0);
    aa_error err = {0};
    rp.spp = 1000;
    assert_int_equal(aa_render_reference(&s, &rp, 1.0, &b, NULL, NULL, &err), AA_EINVAL);
    assert_string_equal(err.field, "spp");
    aa_image_free(&a);
    aa_image_free(&b);
}

static void test_diff_stats_and_difference_image(void **state)
{
    (void)state;
    aa_image a, r;
    assert_int_equal(aa_image_init(&a, 2, 2, NULL), AA_OK);
    assert_int_equal(aa_image_init(&r, 2, 2, NULL), AA_OK);
    a.px[1] = 10.0f / 255; /* deviation 10 */
    a.px[2] = 0.05f;       /* deviation 12.75, half of the 10% full scale */
    aa_diff_stats st;
    aa_diff_init(&st);
    assert_int_equal(aa_diff_add(&st, &a, &r), AA_OK);
    aa_diff_finish(&st);
    assert_float_equal(st.max_dev, 12.75, 1e-4);
    assert_float_equal(st.rmse, sqrt((100 + 12.75 * 12.75) / 4), 1e-4);
    assert_int_equal(st.histogram[0], 2);
    assert_int_equal(st.histogram[10], 1);
    assert_int_equal(st.histogram[13], 1);
    assert_float_equal(st.penalised[10], 100.0 / 4, 1e-12);
    uint8_t g[4];
    aa_image_difference_gray8(&a, &r, 0.1, g);
    assert_int_equal(g[0], 255);
    assert_true(g[2] == 127 || g[2] == 128);
    aa_image_free(&a);
    aa_image_free(&r);
}

/* Even kernels reconstruct at pixel corners (L&A Fig. 3): a P(4,4,16) pattern with weights
 * from the filter matches the reference on the shifted grid, and clearly not on the
 * unshifted one. */
static void test_even_kernel_uses_shifted_output_grid(void **state)
{
    (void)state;
    aa_filter f;
    aa_filter_default(&f);
    aa_point pts[4 * 16];
    for (int k = 0; k < 64; k++)
        pts[k] = (aa_point){(k % 8 + 0.5) / 4, (k / 8 + 0.5) / 4}; /* 4 x 4 per pixel */
    aa_tile_spec spec = {2, 2, false, 64, pts, NULL, NULL, &f};
    aa_pattern p;
    assert_int_equal(aa_pattern_from_tile(&p, &spec, 0, NULL), AA_OK);
    assert_int_equal(p.kernel_size, 2);
    assert_float_equal(aa_output_offset(2), 1.0, 0);
    aa_scene_params sp = aa_scene_params_default(AA_SCENE_HALF_PLANE);
    sp.width = sp.height = 24;
    sp.angle_deg = 30;
    aa_scene s = make_scene(sp);
    aa_image pat, ref;
    assert_int_equal(aa_image_init(&pat, 24, 24, NULL), AA_OK);
    assert_int_equal(aa_image_init(&ref, 24, 24, NULL), AA_OK);
    assert_int_equal(aa_render_pattern(&s, &p, true, &pat, NULL, NULL, NULL), AA_OK);
    aa_reference_params rp = aa_reference_params_default();
    rp.spp = 256;
    aa_diff_stats good, bad;
    assert_int_equal(aa_render_reference(&s, &rp, 1.0, &ref, NULL, NULL, NULL), AA_OK);
    aa_diff_init(&good);
    aa_diff_add(&good, &pat, &ref);
    aa_diff_finish(&good);
    assert_int_equal(aa_render_reference(&s, &rp, 0.5, &ref, NULL, NULL, NULL), AA_OK);
    aa_diff_init(&bad);
    aa_diff_add(&bad, &pat, &ref);
    aa_diff_finish(&bad);
    print_message("P(4,4,16) filter weights: RMSE %.2f on the shifted grid, %.2f unshifted\n",
                  good.rmse, bad.rmse);
    assert_true(good.rmse < 0.4 * bad.rmse);
    aa_image_free(&pat);
    aa_image_free(&ref);
    aa_pattern_free(&p);
}

/* s not a square: kernels cycle over the pixels in row-major order, nothing shared. */
static void test_unshared_kernels_cycle_over_pixels(void **state)
{
    (void)state;
    const aa_sample k0[] = {{0, 0, 1}}, k1[] = {{0.3, 0, 1}}, k2[] = {{-0.3, 0, 1}};
    const aa_sample *ks[] = {k0, k1, k2};
    const size_t counts[] = {1, 1, 1};
    aa_pattern p;
    assert_int_equal(aa_pattern_from_kernels(&p, ks, counts, 3, 0, NULL), AA_OK);
    assert_int_equal(p.tile, 0);
    aa_scene_params sp = aa_scene_params_default(AA_SCENE_HALF_PLANE);
    sp.width = sp.height = 8;
    sp.offset = 0.75; /* edge at x = 4.75: value 1 left of it */
    aa_scene s = make_scene(sp);
    aa_image img;
    assert_int_equal(aa_image_init(&img, 8, 8, NULL), AA_OK);
    assert_int_equal(aa_render_pattern(&s, &p, true, &img, NULL, NULL, NULL), AA_OK);
    for (int j = 0; j < 8; j++) {
        size_t k = ((size_t)j * 8 + 4) % 3; /* kernel of pixel (4, j), centre 4.5 */
        float want = k == 1 ? 0.0f : 1.0f;  /* 4.8 is past the edge, 4.2 and 4.5 are not */
        assert_float_equal(img.px[j * 8 + 4], want, 0);
    }
    aa_image_free(&img);
    aa_pattern_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_half_plane_matches_analytic_filtered_edge),
        cmocka_unit_test(test_far_pixels_are_exact_and_not_sampled),
        cmocka_unit_test(test_quincunx_vertical_edge_by_hand),
        cmocka_unit_test(test_mirrored_patterns_render_mirror_images),
        cmocka_unit_test(test_sparse_equals_dense),
        cmocka_unit_test(test_animation_recomputes_only_changes),
        cmocka_unit_test(test_every_scene_with_every_preset),
        cmocka_unit_test(test_reference_is_deterministic_and_spp_validated),
        cmocka_unit_test(test_diff_stats_and_difference_image),
        cmocka_unit_test(test_even_kernel_uses_shifted_output_grid),
        cmocka_unit_test(test_unshared_kernels_cycle_over_pixels),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
