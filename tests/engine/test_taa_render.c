/* The TAA loop on a static scene (render/taa_render.h) against independent computations:
 *  - the loop itself, run here over many periods from the frame images, equals the spatial
 *    renderer's image of each phase's kernels (aa_taa_phase_pattern, aa_render_pattern: the
 *    shared-sample rasteriser, another code path) to float rounding, as does the engine's
 *    steady-state image; with and without a resolve, exponential and box;
 *  - the measured per-phase RMSE equals aa_diff of those kernel renders against the reference;
 *    the after-cut RMSE at k = 1 is frame 0's, and at every k the loop's own image's;
 *  - flicker: 0 for a repeated offset; the frame-to-frame sum equals the images' differences;
 *  - alpha = 1: each phase is its frame; cancellation;
 *  - the edge model predicts each phase's steady-state RMSE from its kernels as the spatial
 *    predictor is checked (test_predict.c, docs/predict.md): on the 27-degree half-plane the
 *    median over phases of predicted/rendered within 0.9-1.1 and each phase within 0.85-1.15; on
 *    the pixel-locked 0, 90, 45 and 2:1 half-planes each within 0.97-1.03; for Halton(2,3) x 8 and
 *    the optimized sequence of docs/temporal.md section 7. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aa_pattern.h"
#include "aa_render.h"
#include "aa_temporal.h"

enum { W = 48 };

static aa_scene make_scene(aa_scene_shape shape)
{
    aa_scene_params sp = aa_scene_params_default(shape);
    sp.width = sp.height = W;
    if (shape == AA_SCENE_HALF_PLANE) {
        sp.angle_deg = 27;
        sp.offset = 0.37;
    }
    aa_scene s;
    assert_int_equal(aa_scene_init(&s, &sp, NULL), AA_OK);
    return s;
}

typedef struct case_spec {
    size_t n;
    aa_blend blend;
    bool resolve;
    const char *frame; /* a preset as the frame pattern, or NULL: one sample at the centre */
} case_spec;

static void build(aa_temporal *t, const case_spec *c, aa_point *jitter)
{
    assert_int_equal(aa_jitter_halton(jitter, c->n, 2, 3, 1, 1.0, NULL), AA_OK);
    aa_temporal_resolve rs = {.radius = 1};
    assert_int_equal(aa_filter_by_name(&rs.filter, "gaussian", NULL, NULL), AA_OK);
    aa_pattern frame = {0};
    if (c->frame) {
        const aa_preset *pr = aa_preset_find(c->frame);
        assert_non_null(pr);
        assert_int_equal(aa_pattern_from_preset(&frame, pr, NULL), AA_OK);
    }
    aa_temporal_spec spec = {.count = c->n,
                             .jitter = jitter,
                             .frame = c->frame ? &frame : NULL,
                             .resolve = c->resolve ? &rs : NULL,
                             .blend = c->blend};
    assert_int_equal(aa_temporal_build(t, &spec, NULL), AA_OK);
    aa_pattern_free(&frame);
}

static aa_image new_image(void)
{
    aa_image img;
    assert_int_equal(aa_image_init(&img, W, W, NULL), AA_OK);
    return img;
}

static void reference_of(const aa_scene *s, const aa_taa *r, aa_image *ref)
{
    *ref = new_image();
    aa_reference_params rp = aa_reference_params_default();
    rp.spp = 64;
    assert_int_equal(aa_render_reference(s, &rp, r->offset, ref, NULL, NULL, NULL), AA_OK);
}

/* The loop, literally: H = F_0, then H = a F_{t mod N} + b H, over `periods` periods, stopping
 * with phase p the newest (box: the mean of the last N frames). */
static void run_loop(const aa_taa *r, const aa_image *frames, size_t periods, size_t p, double *h)
{
    const aa_temporal *t = r->t;
    size_t N = t->phase_count, px = (size_t)W * W;
    if (t->blend.kind == AA_BLEND_BOX) {
        for (size_t k = 0; k < px; k++) {
            h[k] = 0;
            for (size_t f = 0; f < N; f++)
                h[k] += frames[f].px[k];
            h[k] /= (double)N;
        }
        return;
    }
    double a = t->blend.alpha;
    for (size_t k = 0; k < px; k++)
        h[k] = frames[0].px[k];
    for (size_t step = 1; step <= periods * N + p; step++)
        for (size_t k = 0; k < px; k++)
            h[k] = a * frames[step % N].px[k] + (1 - a) * h[k];
}

static void check_case(aa_scene_shape shape, const case_spec *c)
{
    aa_scene s = make_scene(shape);
    aa_point jitter[16];
    aa_temporal t;
    build(&t, c, jitter);
    aa_taa r;
    assert_int_equal(aa_taa_init(&r, &s, &t, true, NULL), AA_OK);
    size_t N = t.phase_count, px = (size_t)W * W;
    aa_image *frames = calloc(N, sizeof *frames);
    for (size_t f = 0; f < N; f++) {
        frames[f] = new_image();
        assert_int_equal(aa_taa_frame_image(&r, f, &frames[f], NULL), AA_OK);
    }
    aa_image ref, kimg = new_image(), simg = new_image();
    reference_of(&s, &r, &ref);
    aa_taa_stats st;
    size_t K = 3 * N;
    assert_int_equal(aa_taa_measure(&r, &ref, K, NULL, NULL, &st, NULL), AA_OK);
    double *h = malloc(px * sizeof *h), worst = 0, worst_kernel = 0;
    for (size_t p = 0; p < N; p++) {
        run_loop(&r, frames, 60, p, h);
        aa_pattern pat;
        assert_int_equal(aa_taa_phase_pattern(&t, p, &pat, NULL), AA_OK);
        assert_true(aa_output_offset(pat.kernel_size) == r.offset);
        assert_int_equal(aa_render_pattern(&s, &pat, true, &kimg, NULL, NULL, NULL), AA_OK);
        assert_int_equal(aa_taa_phase_image(&r, p, &simg, NULL), AA_OK);
        for (size_t k = 0; k < px; k++) {
            worst = fmax(worst, fabs(h[k] - kimg.px[k]));
            worst_kernel = fmax(worst_kernel, fabs((double)simg.px[k] - kimg.px[k]));
        }
        aa_diff_stats d;
        aa_diff_init(&d);
        aa_diff_add(&d, &kimg, &ref);
        aa_diff_finish(&d);
        assert_true(fabs(aa_taa_rmse(&st, st.phase_sum_sq[p]) - d.rmse) < 1e-4);
        assert_true(fabs(st.phase_max_dev[p] - d.max_dev) < 1e-3);
        aa_pattern_free(&pat);
    }
    /* Float images: half an ulp of values near 1 is 6e-8, plus the sums' rounding. */
    assert_true(worst < 1e-6);
    assert_true(worst_kernel < 1e-6);

    /* After a cut: frame k of the loop, against the same sums. */
    double a = t.blend.kind == AA_BLEND_BOX ? 0 : t.blend.alpha;
    for (size_t k = 1; k <= K; k++) {
        if (t.blend.kind == AA_BLEND_BOX) {
            size_t m = k < N ? k : N;
            for (size_t q = 0; q < px; q++) {
                h[q] = 0;
                for (size_t i = k - m; i < k; i++)
                    h[q] += frames[i % N].px[q];
                h[q] /= (double)m;
            }
        } else {
            for (size_t q = 0; q < px; q++)
                h[q] = k == 1 ? frames[0].px[q] : a * frames[(k - 1) % N].px[q] + (1 - a) * h[q];
        }
        double sum = 0;
        for (size_t q = 0; q < px; q++) {
            double d = 255.0 * (h[q] - ref.px[q]);
            sum += d * d;
        }
        assert_true(fabs(sqrt(sum / px) - aa_taa_rmse(&st, st.cut_sum_sq[k - 1])) < 1e-4);
    }
    /* Flicker from the steady-state images. */
    double step = 0;
    aa_image prev = new_image();
    assert_int_equal(aa_taa_phase_image(&r, N - 1, &prev, NULL), AA_OK);
    for (size_t p = 0; p < N; p++) {
        assert_int_equal(aa_taa_phase_image(&r, p, &simg, NULL), AA_OK);
        for (size_t q = 0; q < px; q++) {
            double d = 255.0 * ((double)simg.px[q] - prev.px[q]);
            step += d * d;
        }
        memcpy(prev.px, simg.px, px * sizeof *prev.px);
    }
    assert_true(fabs(step - st.flicker_step_sum_sq) <= 1e-4 * (1 + step));
    if (t.blend.kind == AA_BLEND_BOX)
        assert_true(st.flicker_step_sum_sq == 0);
    else
        assert_true(st.flicker_step_sum_sq > 0);
    aa_image_free(&prev);
    aa_taa_stats_free(&st);
    free(h);
    for (size_t f = 0; f < N; f++)
        aa_image_free(&frames[f]);
    free(frames);
    aa_image_free(&ref);
    aa_image_free(&kimg);
    aa_image_free(&simg);
    aa_temporal_free(&t);
}

static void test_loop_equals_phase_kernels(void **state)
{
    (void)state;
    const case_spec cases[] = {
        {8, {AA_BLEND_EXPONENTIAL, 0.1}, false, NULL},
        {8, {AA_BLEND_EXPONENTIAL, 0.1}, true, NULL},
        {5, {AA_BLEND_EXPONENTIAL, 0.3}, false, NULL},
        {4, {AA_BLEND_BOX, 0}, false, NULL},
        /* Frame patterns: a 2 x 2 tile of mirrored kernels, kernels over 2 x 2 pixels (even K),
         * and a tile under a resolve (4 groups). */
        {4, {AA_BLEND_EXPONENTIAL, 0.2}, false, "flipquad"},
        {3, {AA_BLEND_EXPONENTIAL, 0.2}, false, "quincunx"},
        {3, {AA_BLEND_EXPONENTIAL, 0.5}, true, "flipquad"},
    };
    const aa_scene_shape shapes[] = {AA_SCENE_RINGS, AA_SCENE_HALF_PLANE, AA_SCENE_SIEMENS_STAR};
    for (size_t k = 0; k < 3; k++)
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++)
            check_case(shapes[k], &cases[c]);
}

static void test_repeated_offset_has_no_flicker(void **state)
{
    (void)state;
    aa_scene s = make_scene(AA_SCENE_RINGS);
    aa_point jitter[6];
    for (int f = 0; f < 6; f++)
        jitter[f] = (aa_point){0.21, -0.13};
    aa_temporal t;
    aa_temporal_spec spec = {.count = 6, .jitter = jitter, .blend = {AA_BLEND_EXPONENTIAL, 0.1}};
    assert_int_equal(aa_temporal_build(&t, &spec, NULL), AA_OK);
    aa_taa r;
    assert_int_equal(aa_taa_init(&r, &s, &t, true, NULL), AA_OK);
    aa_image ref;
    reference_of(&s, &r, &ref);
    aa_taa_stats st;
    assert_int_equal(aa_taa_measure(&r, &ref, 10, NULL, NULL, &st, NULL), AA_OK);
    assert_true(st.flicker_step_sum_sq < 1e-18);
    assert_true(st.flicker_mean_sum_sq < 1e-18);
    for (size_t k = 0; k < 10; k++) /* every frame is the same image from the cut on */
        assert_true(fabs(st.cut_sum_sq[k] - st.phase_sum_sq[0]) <= 1e-9 * st.phase_sum_sq[0]);
    aa_taa_stats_free(&st);
    aa_image_free(&ref);
    aa_temporal_free(&t);
}

static void test_alpha_one_phase_is_its_frame(void **state)
{
    (void)state;
    aa_scene s = make_scene(AA_SCENE_SIEMENS_STAR);
    case_spec c = {8, {AA_BLEND_EXPONENTIAL, 1}, false, NULL};
    aa_point jitter[8];
    aa_temporal t;
    build(&t, &c, jitter);
    aa_taa r;
    assert_int_equal(aa_taa_init(&r, &s, &t, true, NULL), AA_OK);
    aa_image a = new_image(), b = new_image();
    for (size_t p = 0; p < 8; p++) {
        assert_int_equal(aa_taa_frame_image(&r, p, &a, NULL), AA_OK);
        assert_int_equal(aa_taa_phase_image(&r, p, &b, NULL), AA_OK);
        assert_memory_equal(a.px, b.px, sizeof(float) * W * W);
    }
    aa_image_free(&a);
    aa_image_free(&b);
    aa_temporal_free(&t);
}

static int cancel_at_half(void *user, double fraction)
{
    (*(int *)user)++;
    return fraction >= 0.5;
}

static void test_cancel(void **state)
{
    (void)state;
    aa_scene s = make_scene(AA_SCENE_RINGS);
    case_spec c = {8, {AA_BLEND_EXPONENTIAL, 0.1}, false, NULL};
    aa_point jitter[8];
    aa_temporal t;
    build(&t, &c, jitter);
    aa_taa r;
    assert_int_equal(aa_taa_init(&r, &s, &t, true, NULL), AA_OK);
    aa_image ref = new_image();
    aa_taa_stats st;
    int calls = 0;
    aa_error err = {0};
    assert_int_equal(aa_taa_measure(&r, &ref, 8, cancel_at_half, &calls, &st, &err), AA_ECANCELED);
    assert_int_equal(calls, W / 2);
    assert_null(st.phase_sum_sq);
    assert_int_equal(aa_taa_measure(&r, &ref, 0, NULL, NULL, &st, &err), AA_EINVAL);
    assert_string_equal(err.field, "cut_frames");
    aa_image_free(&ref);
    aa_temporal_free(&t);
}

/* docs/temporal.md section 7, on a 1/16-pixel grid (E2 0.3032). */
static const aa_point optimized8[8] = {{0.25, 0.375},    {-0.0625, -0.4375}, {-0.5, 0.1875},
                                       {0.375, -0.1875}, {0.0625, 0.5},      {-0.375, -0.0625},
                                       {0.5, -0.5},      {-0.25, 0.0625}};

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void check_prediction(const aa_scene_params *sp, const aa_point *jitter, double lo,
                             double hi, bool flicker, const char *what)
{
    aa_scene s;
    assert_int_equal(aa_scene_init(&s, sp, NULL), AA_OK);
    aa_temporal t;
    aa_temporal_spec spec = {.count = 8, .jitter = jitter, .blend = {AA_BLEND_EXPONENTIAL, 0.1}};
    assert_int_equal(aa_temporal_build(&t, &spec, NULL), AA_OK);
    aa_taa r;
    assert_int_equal(aa_taa_init(&r, &s, &t, true, NULL), AA_OK);
    aa_image ref;
    assert_int_equal(aa_image_init(&ref, sp->width, sp->height, NULL), AA_OK);
    aa_reference_params rp = aa_reference_params_default();
    rp.spp = 256;
    assert_int_equal(aa_render_reference(&s, &rp, r.offset, &ref, NULL, NULL, NULL), AA_OK);
    aa_taa_stats st;
    assert_int_equal(aa_taa_measure(&r, &ref, 1, NULL, NULL, &st, NULL), AA_OK);
    aa_edge_histogram *h = malloc(sizeof *h);
    assert_int_equal(aa_edge_histogram_of_scene(&s, h, NULL), AA_OK);
    double ratios[8];
    for (size_t p = 0; p < 8; p++) {
        aa_pattern pat;
        aa_prediction pred;
        assert_int_equal(aa_taa_phase_pattern(&t, p, &pat, NULL), AA_OK);
        assert_int_equal(aa_predict_rmse(&pat, NULL, h, &pred, NULL), AA_OK);
        double rendered = aa_taa_rmse(&st, st.phase_sum_sq[p]), ratio = pred.rmse / rendered;
        printf("%-14s phase %zu rendered %.4f predicted %.4f ratio %.3f\n", what, p, rendered,
               pred.rmse, ratio);
        ratios[p] = ratio;
        if (!(ratio >= lo && ratio <= hi))
            fail_msg("%s phase %zu: predicted/rendered %.4f outside [%g, %g]", what, p, ratio, lo,
                     hi);
        aa_pattern_free(&pat);
    }
    /* The flicker from F1 (about the mean) and from the phases' differences (frame to frame),
     * on generic edges only (a locked edge's offsets are not spread). */
    double fm, fs;
    assert_int_equal(aa_taa_predict_flicker(&t, h, &fm, &fs, NULL), AA_OK);
    double rm = fm / aa_taa_rmse(&st, st.flicker_mean_sum_sq / 8);
    double rs = fs / aa_taa_rmse(&st, st.flicker_step_sum_sq / 8);
    printf("%-14s flicker predicted/rendered: about the mean %.3f, frame to frame %.3f\n", what, rm,
           rs);
    if (flicker && !(rm >= 0.9 && rm <= 1.1 && rs >= 0.9 && rs <= 1.1))
        fail_msg("%s: flicker predicted/rendered %.4f, %.4f outside [0.9, 1.1]", what, rm, rs);
    qsort(ratios, 8, sizeof ratios[0], by_value);
    double median = (ratios[3] + ratios[4]) / 2;
    if (!(median >= 0.9 && median <= 1.1))
        fail_msg("%s: median predicted/rendered %.4f outside [0.9, 1.1]", what, median);
    free(h);
    aa_taa_stats_free(&st);
    aa_image_free(&ref);
    aa_temporal_free(&t);
}

static void test_predicted_phases_match_render(void **state)
{
    (void)state;
    aa_point halton[8];
    assert_int_equal(aa_jitter_halton(halton, 8, 2, 3, 1, 1.0, NULL), AA_OK);
    const aa_point *seqs[2] = {halton, optimized8};
    const char *names[2] = {"halton", "optimized"};
    for (int q = 0; q < 2; q++) {
        char what[32];
        aa_scene_params sp = aa_scene_params_default(AA_SCENE_HALF_PLANE);
        sp.width = sp.height = 128;
        sp.angle_deg = 27;
        sp.offset = 0.37;
        snprintf(what, sizeof what, "half-27 %s", names[q]);
        check_prediction(&sp, seqs[q], 0.85, 1.15, true, what);
        sp = aa_scene_params_default(AA_SCENE_HALF_PLANE);
        sp.width = sp.height = 128;
        snprintf(what, sizeof what, "half-0 %s", names[q]);
        check_prediction(&sp, seqs[q], 0.97, 1.03, false, what);
        sp.angle_deg = 90;
        sp.offset = 0.3;
        snprintf(what, sizeof what, "half-90 %s", names[q]);
        check_prediction(&sp, seqs[q], 0.97, 1.03, false, what);
        sp.angle_deg = 45;
        sp.offset = 0.37;
        snprintf(what, sizeof what, "half-45 %s", names[q]);
        check_prediction(&sp, seqs[q], 0.97, 1.03, false, what);
        sp.angle_deg = 180 - atan(0.5) * 180 / 3.14159265358979323846;
        sp.offset = -2.1;
        snprintf(what, sizeof what, "half-153 %s", names[q]);
        check_prediction(&sp, seqs[q], 0.97, 1.03, false, what);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_loop_equals_phase_kernels),
        cmocka_unit_test(test_repeated_offset_has_no_flicker),
        cmocka_unit_test(test_alpha_one_phase_is_its_frame),
        cmocka_unit_test(test_cancel),
        cmocka_unit_test(test_predicted_phases_match_render),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
