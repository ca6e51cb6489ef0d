/* The render job kinds' and the sleep kind's codecs (proto/job_compare.h, job_animation.h,
 * job_reference_convergence.h, job_sleep.h): spec defaults, the one unknown-key check naming
 * the key, ranges naming the field, and result round trips: decode(encode(x)) encodes to the
 * same bytes, and a result with an unknown key or a bad value is refused naming the field. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>

#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "codec_check.h"
#include "job_animation.h"
#include "job_compare.h"
#include "job_reference_convergence.h"
#include "job_sleep.h"
#include "job_temporal_render.h"
#include "codec_predict.h"

/* A changed copy of j (path set to value, or deleted when value is NULL) fails to decode with
 * field want. */
static json_t *with(const json_t *j, const char *key, json_t *value)
{
    json_t *c = json_deep_copy(j);
    if (value)
        json_object_set_new(c, key, value);
    else
        json_object_del(c, key);
    return c;
}

#define RESULT_FAILS(T, decode, free_fn, j, want)                                                  \
    do {                                                                                           \
        T r_;                                                                                      \
        aa_error e_ = {0};                                                                         \
        json_t *j_ = (j);                                                                          \
        assert_int_not_equal(decode(j_, &r_, &e_), AA_OK);                                         \
        assert_string_equal(e_.field, want);                                                       \
        json_decref(j_);                                                                           \
    } while (0)

static void some_diff(aa_diff_stats *d)
{
    aa_diff_init(d);
    d->pixels = 4;
    d->histogram[0] = 2;
    d->histogram[10] = 2;
    d->sum_sq = 2 * 9.8 * 9.8;
    d->max_dev = 10.2;
    aa_diff_finish(d);
}

static void test_compare_spec(void **state)
{
    (void)state;
    json_t *j = parse("{\"patterns\":[\"flipquad\",{\"preset\":\"rgss\"},{\"name\":\"mine\","
                      "\"kernels\":[[[0,0,1]]]}],\"size\":[32,24]}");
    proto_compare_spec s;
    aa_error err = {0};
    assert_int_equal(proto_decode_compare_spec(j, &s, &err), AA_OK);
    assert_int_equal(s.count, 3);
    assert_string_equal(s.names[0], "flipquad");
    assert_string_equal(s.names[1], "rgss");
    assert_string_equal(s.names[2], "mine");
    assert_int_equal(s.common.scene.width, 32);
    assert_int_equal(s.common.scene.height, 24);
    assert_true(s.common.tiles);
    assert_string_equal(s.common.acuity.name, "naiman");
    proto_compare_spec_free(&s);
    json_decref(j);
    DECODE_FAILS(proto_compare_spec, proto_decode_compare_spec,
                 "{\"patterns\":[\"flipquad\"],\"levels\":[16]}", AA_EINVAL, "levels");
    DECODE_FAILS(proto_compare_spec, proto_decode_compare_spec, "{\"patterns\":[]}", AA_EINVAL,
                 "patterns");
    DECODE_FAILS(proto_compare_spec, proto_decode_compare_spec,
                 "{\"patterns\":[\"flipquad\",\"flipqaud\"]}", AA_EINVAL, "patterns[1]");
    DECODE_FAILS(proto_compare_spec, proto_decode_compare_spec,
                 "{\"patterns\":[\"flipquad\"],\"tiles\":1}", AA_EINVAL, "tiles");
}

/* The "acuity" a result records: absent in results stored before it was, so it decodes to no
 * name; a named table without its version is refused naming acuity.version. decode returns the
 * decoded name (or NULL on error) through the result it frees. */
typedef int (*acuity_decode_fn)(const json_t *j, char *name, size_t cap, aa_error *err);
static int decode_compare_acuity(const json_t *j, char *name, size_t cap, aa_error *err)
{
    proto_compare_result r;
    int rc = proto_decode_compare_result(j, &r, err);
    snprintf(name, cap, "%s", rc ? "" : r.acuity_name);
    proto_compare_result_free(&r);
    return rc;
}
static int decode_animation_acuity(const json_t *j, char *name, size_t cap, aa_error *err)
{
    proto_animation_result r;
    int rc = proto_decode_animation_result(j, &r, err);
    snprintf(name, cap, "%s", rc ? "" : r.acuity_name);
    proto_animation_result_free(&r);
    return rc;
}
static void assert_acuity_optional(const json_t *j, acuity_decode_fn decode)
{
    char name[24];
    aa_error err = {0};
    json_t *old = with(j, "acuity", NULL);
    assert_int_equal(decode(old, name, sizeof name, &err), AA_OK);
    assert_string_equal(name, "");
    json_decref(old);
    json_t *bad = with(j, "acuity", parse("{\"name\":\"naiman\"}"));
    assert_int_not_equal(decode(bad, name, sizeof name, &err), AA_OK);
    assert_string_equal(err.field, "acuity.version");
    json_decref(bad);
    bad = with(j, "acuity", json_string("naiman"));
    assert_int_not_equal(decode(bad, name, sizeof name, &err), AA_OK);
    assert_string_equal(err.field, "acuity");
    json_decref(bad);
}

static void test_compare_result(void **state)
{
    (void)state;
    proto_compare_result r;
    memset(&r, 0, sizeof r);
    aa_error err = {0};
    assert_int_equal(proto_decode_scene(NULL, &r.scene, "scene", &err), AA_OK);
    r.reference_spp = 1024;
    r.reference_seed = 3;
    strcpy(r.filter, "mitchell");
    r.render_count = 2;
    r.renders[0] = (proto_compare_render){0.5, 0.25, 100, 4000, 90000, parse("{\"id\":\"a1\"}")};
    r.renders[1] = (proto_compare_render){1, 0.5, 120, 4100, 91000, NULL};
    proto_compare_row rows[2];
    memset(rows, 0, sizeof rows);
    strcpy(rows[0].name, "flipquad");
    strcpy(rows[0].family, "P(2,1,1)");
    rows[0].samples_per_pixel = 2;
    rows[0].e2 = 0.364;
    some_diff(&rows[0].stats);
    rows[0].rmse = rows[0].stats.rmse;
    rows[0].max_dev = rows[0].stats.max_dev;
    rows[0].render_seconds = 0.01;
    rows[0].predicted_rmse = 3.5;
    rows[0].subpixel_error_share = 0.125;
    rows[0].pixels_sampled = 7;
    rows[0].coverage_samples = 14;
    rows[0].have_tiles = true;
    rows[0].tile_pattern = parse("{\"id\":\"p\"}");
    rows[1] = rows[0];
    strcpy(rows[1].name, "second");
    rows[1].predicted_rmse = NAN; /* absent: an older result, or the model could not say */
    rows[1].subpixel_error_share = NAN;
    rows[1].have_tiles = false;
    rows[1].tile_pattern = NULL;
    r.rows = rows;
    r.row_count = 2;
    r.have_prediction = true;
    r.spearman_predicted = NAN; /* encoded as null */
    r.subpixel_area_share = 0.25;
    aa_acuity naiman;
    aa_acuity_naiman(&naiman);
    proto_acuity_ref_set(&naiman, r.acuity_name, sizeof r.acuity_name, &r.acuity_version);
    json_t *j;
    ROUND_TRIP(proto_compare_result, proto_encode_compare_result, proto_decode_compare_result,
               proto_compare_result_free, &r, j);
    assert_string_equal(json_string_value(json_object_get(json_object_get(j, "acuity"), "name")),
                        "naiman");
    assert_int_equal(json_integer_value(json_object_get(json_object_get(j, "acuity"), "version")),
                     naiman.version);
    assert_acuity_optional(j, decode_compare_acuity);
    json_t *row0 = json_array_get(json_object_get(j, "rows"), 0);
    assert_non_null(json_object_get(json_object_get(row0, "tiles"), "pattern"));
    assert_null(json_object_get(json_object_get(row0, "tiles"), "difference"));
    assert_null(json_object_get(json_array_get(json_object_get(j, "rows"), 1), "tiles"));
    assert_true(json_is_null(json_object_get(json_object_get(j, "prediction"), "spearman")));
    assert_float_equal(json_real_value(json_object_get(row0, "predicted_rmse")), 3.5, 0);
    assert_float_equal(json_real_value(json_object_get(row0, "subpixel_error_share")), 0.125, 0);
    assert_null(json_object_get(json_array_get(json_object_get(j, "rows"), 1), "predicted_rmse"));
    assert_int_equal(json_array_size(json_object_get(json_object_get(j, "reference"), "renders")),
                     2);

    RESULT_FAILS(proto_compare_result, proto_decode_compare_result, proto_compare_result_free,
                 with(j, "extra", json_true()), "extra");
    RESULT_FAILS(proto_compare_result, proto_decode_compare_result, proto_compare_result_free,
                 with(j, "rows", NULL), "rows");
    json_t *bad = json_deep_copy(j);
    json_object_set_new(json_array_get(json_object_get(bad, "rows"), 1), "rmse", json_string("x"));
    RESULT_FAILS(proto_compare_result, proto_decode_compare_result, proto_compare_result_free, bad,
                 "rows[1].rmse");
    bad = json_deep_copy(j);
    json_t *hist =
        json_object_get(json_object_get(json_array_get(json_object_get(bad, "rows"), 0), "stats"),
                        "penalised_histogram");
    json_array_set_new(hist, 10, json_real(1.0));
    RESULT_FAILS(proto_compare_result, proto_decode_compare_result, proto_compare_result_free, bad,
                 "rows[0].stats.penalised_histogram[10]");
    bad = json_deep_copy(j);
    json_object_set_new(
        json_array_get(json_object_get(json_object_get(bad, "reference"), "renders"), 0), "tile",
        json_string("a1"));
    RESULT_FAILS(proto_compare_result, proto_decode_compare_result, proto_compare_result_free, bad,
                 "reference.renders[0].tile");
    json_decref(j);
    json_decref(r.renders[0].tile);
    json_decref(rows[0].tile_pattern);
}

static void test_animation(void **state)
{
    (void)state;
    DECODE_FAILS(proto_animation_spec, proto_decode_animation_spec, "{\"pattern\":\"flipquad\"}",
                 AA_EINVAL, "scene.name");
    DECODE_FAILS(proto_animation_spec, proto_decode_animation_spec,
                 "{\"scene\":\"siemens-star\",\"pattern\":\"flipquad\"}", AA_EINVAL, "scene.name");
    DECODE_FAILS(proto_animation_spec, proto_decode_animation_spec,
                 "{\"scene\":\"rotating-triangle\"}", AA_EINVAL, "pattern");
    DECODE_FAILS(proto_animation_spec, proto_decode_animation_spec,
                 "{\"scene\":\"rotating-triangle\",\"pattern\":\"flipquad\",\"patterns\":[]}",
                 AA_EINVAL, "patterns");
    json_t *j = parse("{\"scene\":{\"name\":\"translating-circle\",\"frames\":3},"
                      "\"pattern\":{\"preset\":\"rgss\"},\"tiles\":false}");
    proto_animation_spec s;
    aa_error err = {0};
    assert_int_equal(proto_decode_animation_spec(j, &s, &err), AA_OK);
    assert_int_equal(s.common.scene.frames, 3);
    assert_false(s.common.tiles);
    json_decref(j);

    proto_animation_result r;
    memset(&r, 0, sizeof r);
    r.scene = s.common.scene;
    snprintf(r.family, sizeof r.family, "%s", s.pattern.family);
    r.samples_per_pixel = s.pattern.cost_spp;
    r.e2 = 0.3;
    proto_animation_frame frames[2] = {
        {0, 1.5, 20, 100, 90, 30, 0.01, 0.02, NULL},
        {1, 1.25, 18, 50, 45, 20, 0.01, 0.02, parse("{\"pattern\":{\"id\":\"x\"}}")}};
    r.frames = frames;
    r.frame_count = 2;
    some_diff(&r.total);
    r.pattern_seconds = 0.02;
    r.reference_seconds = 0.04;
    r.pixels_recomputed = 150;
    r.pixels_all_frames = 600;
    strcpy(r.acuity_name, "custom"); /* knots given in the spec */
    ROUND_TRIP(proto_animation_result, proto_encode_animation_result, proto_decode_animation_result,
               proto_animation_result_free, &r, j);
    assert_string_equal(json_string_value(json_object_get(json_object_get(j, "acuity"), "name")),
                        "custom");
    assert_null(json_object_get(json_object_get(j, "acuity"), "version"));
    assert_acuity_optional(j, decode_animation_acuity);
    assert_string_equal(json_string_value(json_object_get(json_object_get(j, "scene"), "name")),
                        "translating-circle");
    RESULT_FAILS(proto_animation_result, proto_decode_animation_result, proto_animation_result_free,
                 with(j, "frame", json_integer(1)), "frame");
    json_t *bad = json_deep_copy(j);
    json_object_set_new(json_object_get(bad, "pixels"), "recomputed", json_integer(-1));
    RESULT_FAILS(proto_animation_result, proto_decode_animation_result, proto_animation_result_free,
                 bad, "pixels.recomputed");
    bad = json_deep_copy(j);
    /* a pixel counted twice */
    json_array_set_new(json_object_get(json_object_get(bad, "total"), "histogram"), 0,
                       json_integer(3));
    RESULT_FAILS(proto_animation_result, proto_decode_animation_result, proto_animation_result_free,
                 bad, "total.histogram");
    json_decref(j);
    json_decref(frames[1].tiles);
    proto_animation_spec_free(&s);
}

static void test_reference_convergence(void **state)
{
    (void)state;
    json_t *j = parse("{}");
    proto_reference_convergence_spec s;
    aa_error err = {0};
    assert_int_equal(proto_decode_reference_convergence_spec(j, &s, &err), AA_OK);
    assert_int_equal(s.level_count, 4);
    assert_int_equal(s.levels[3], 1024);
    assert_int_equal(s.baseline_spp, 4096);
    assert_int_equal(s.kernel_size, 1);
    json_decref(j);
    DECODE_FAILS(proto_reference_convergence_spec, proto_decode_reference_convergence_spec,
                 "{\"levels\":[16,50]}", AA_EINVAL, "levels[1]");
    DECODE_FAILS(proto_reference_convergence_spec, proto_decode_reference_convergence_spec,
                 "{\"levels\":[1,4,9,16,25,36,49,64,81]}", AA_EINVAL, "levels");
    DECODE_FAILS(proto_reference_convergence_spec, proto_decode_reference_convergence_spec,
                 "{\"baseline_spp\":4095}", AA_EINVAL, "baseline_spp");
    DECODE_FAILS(proto_reference_convergence_spec, proto_decode_reference_convergence_spec,
                 "{\"kernel_size\":0}", AA_EINVAL, "kernel_size");
    /* acuity and tiles belong to the other render kinds only */
    DECODE_FAILS(proto_reference_convergence_spec, proto_decode_reference_convergence_spec,
                 "{\"tiles\":false}", AA_EINVAL, "tiles");

    proto_reference_convergence_result r;
    memset(&r, 0, sizeof r);
    r.scene = s.common.scene;
    r.output_offset = 0.5;
    r.baseline = (proto_convergence_level){4096, 0, 0, 1.5, 300, 9000000};
    r.rows[0] = (proto_convergence_level){16, 3.25, 40, 0.01, 300, 40000};
    r.rows[1] = (proto_convergence_level){64, 1.5, 20, 0.02, 300, 160000};
    r.row_count = 2;
    ROUND_TRIP(proto_reference_convergence_result, proto_encode_reference_convergence_result,
               proto_decode_reference_convergence_result, proto_reference_convergence_result_free,
               &r, j);
    assert_null(json_object_get(json_object_get(j, "baseline"), "rmse"));
    json_t *bad = json_deep_copy(j);
    json_object_set_new(json_object_get(bad, "baseline"), "rmse", json_real(0));
    RESULT_FAILS(proto_reference_convergence_result, proto_decode_reference_convergence_result,
                 proto_reference_convergence_result_free, bad, "baseline.rmse");
    bad = json_deep_copy(j);
    json_object_set_new(json_array_get(json_object_get(bad, "rows"), 1), "spp", json_integer(0));
    RESULT_FAILS(proto_reference_convergence_result, proto_decode_reference_convergence_result,
                 proto_reference_convergence_result_free, bad, "rows[1].spp");
    RESULT_FAILS(proto_reference_convergence_result, proto_decode_reference_convergence_result,
                 proto_reference_convergence_result_free, with(j, "output_offset", json_real(0.75)),
                 "output_offset");
    json_decref(j);
    proto_reference_convergence_spec_free(&s);
}

static void test_sleep(void **state)
{
    (void)state;
    DECODE_FAILS(proto_sleep_spec, proto_decode_sleep_spec, "{}", AA_EINVAL, "seconds");
    DECODE_FAILS(proto_sleep_spec, proto_decode_sleep_spec, "{\"seconds\":3601}", AA_ERANGE,
                 "seconds");
    DECODE_FAILS(proto_sleep_spec, proto_decode_sleep_spec, "{\"seconds\":1,\"fail\":\"yes\"}",
                 AA_EINVAL, "fail");
    DECODE_FAILS(proto_sleep_spec, proto_decode_sleep_spec, "{\"seconds\":1,\"nap\":true}",
                 AA_EINVAL, "nap");
    json_t *j = parse("{\"seconds\":0.5,\"fail\":true,\"pattern\":{\"preset\":\"flipquad\"}}");
    proto_sleep_spec s;
    aa_error err = {0};
    assert_int_equal(proto_decode_sleep_spec(j, &s, &err), AA_OK);
    assert_true(s.fail);
    assert_true(s.have_pattern);
    json_decref(j);

    proto_sleep_result r = {.slept_seconds = 0.5, .steps = 40};
    ROUND_TRIP(proto_sleep_result, proto_encode_sleep_result, proto_decode_sleep_result,
               proto_sleep_result_free, &r, j);
    assert_null(json_object_get(j, "pattern"));
    json_decref(j);
    r.have_pattern = true;
    r.pattern = s.pattern;
    ROUND_TRIP(proto_sleep_result, proto_encode_sleep_result, proto_decode_sleep_result,
               proto_sleep_result_free, &r, j);
    assert_non_null(json_object_get(j, "pattern"));
    RESULT_FAILS(proto_sleep_result, proto_decode_sleep_result, proto_sleep_result_free,
                 with(j, "steps", json_integer(-1)), "steps");
    RESULT_FAILS(proto_sleep_result, proto_decode_sleep_result, proto_sleep_result_free,
                 with(j, "woke", json_true()), "woke");
    json_decref(j);
    proto_sleep_spec_free(&s);
}

/* The temporal-render spec: a temporal pattern and a still scene; K defaults to 4 N and is capped;
 * errors name the field. The result encodes every phase, the steady state, the after-cut curve and
 * the flicker, with the predictions and ratios where they exist. */
static void test_temporal_render(void **state)
{
    (void)state;
    DECODE_FAILS(proto_temporal_render_spec, proto_decode_temporal_render_spec,
                 "{\"scene\":\"rings\",\"pattern\":\"rgss\"}", AA_EINVAL, "pattern");
    DECODE_FAILS(proto_temporal_render_spec, proto_decode_temporal_render_spec,
                 "{\"scene\":\"rings\"}", AA_EINVAL, "pattern");
    DECODE_FAILS(proto_temporal_render_spec, proto_decode_temporal_render_spec,
                 "{\"scene\":\"translating-circle\",\"pattern\":{\"temporal\":{\"preset\":"
                 "\"halton23-8\"}}}",
                 AA_EINVAL, "scene.name");
    DECODE_FAILS(proto_temporal_render_spec, proto_decode_temporal_render_spec,
                 "{\"pattern\":{\"temporal\":{\"jitter\":[[0,0]],\"blend\":{\"kind\":"
                 "\"exponential\",\"alpha\":1.5}}}}",
                 AA_EINVAL, "pattern.temporal.blend.alpha");
    DECODE_FAILS(proto_temporal_render_spec, proto_decode_temporal_render_spec,
                 "{\"pattern\":{\"temporal\":{\"jitter\":{\"generator\":\"halton\",\"count\":1024},"
                 "\"resolve\":{\"filter\":{\"name\":\"gaussian\"},\"radius\":3}}}}",
                 AA_ERANGE, "pattern.temporal");
    json_t *j = parse("{\"scene\":\"rings\",\"size\":[16,16],\"pattern\":{\"temporal\":"
                      "{\"jitter\":{\"generator\":\"halton\",\"count\":1024}}}}");
    proto_temporal_render_spec s;
    aa_error err = {0};
    assert_int_equal(proto_decode_temporal_render_spec(j, &s, &err), AA_OK);
    assert_int_equal(s.built.phase_count, 1024);
    assert_int_equal(s.cut_frames, AA_TEMPORAL_MAX_CUT_FRAMES); /* 4 N, capped */
    proto_temporal_render_spec_free(&s);
    json_decref(j);
    j = parse("{\"pattern\":{\"temporal\":{\"preset\":\"halton23-8\",\"cut_frames\":5}}}");
    assert_int_equal(proto_decode_temporal_render_spec(j, &s, &err), AA_OK);
    assert_int_equal(s.cut_frames, 5);
    assert_string_equal(s.temporal.preset, "halton23-8");

    proto_temporal_render_result r;
    memset(&r, 0, sizeof r);
    r.scene = s.common.scene;
    r.phase_count = 2;
    r.group_count = 1;
    r.cut_count = 3;
    r.blend = (aa_blend){AA_BLEND_EXPONENTIAL, 0.1};
    r.jitter = calloc(2, sizeof *r.jitter);
    r.phase_e2 = calloc(2, sizeof *r.phase_e2);
    r.phase_rmse = calloc(2, sizeof *r.phase_rmse);
    r.phase_max_dev = calloc(2, sizeof *r.phase_max_dev);
    r.phase_predicted = calloc(2, sizeof *r.phase_predicted);
    r.cut_rmse = calloc(3, sizeof *r.cut_rmse);
    r.phase_rmse[0] = 2;
    r.phase_rmse[1] = 4;
    r.worst_phase = 1;
    r.phase_predicted[0] = 2.2;
    r.phase_predicted[1] = NAN; /* no prediction: no ratio, none in steady either */
    r.flicker_mean_rmse = 0.5;
    r.flicker_predicted = 0.55;
    r.flicker_step_predicted = NAN;
    r.frames_to_5pct = -1;
    json_t *out = proto_encode_temporal_render_result(&r);
    assert_non_null(out);
    json_t *phases = json_object_get(out, "phases");
    assert_int_equal(json_array_size(phases), 2);
    assert_true(fabs(json_real_value(json_object_get(json_array_get(phases, 0), "ratio")) - 1.1) <
                1e-15);
    assert_null(json_object_get(json_array_get(phases, 1), "predicted_rmse"));
    json_t *steady = json_object_get(out, "steady");
    assert_int_equal(json_integer_value(json_object_get(steady, "worst_phase")), 1);
    assert_true(json_real_value(json_object_get(steady, "rmse")) == 4);
    assert_true(fabs(json_real_value(json_object_get(steady, "mean_rmse")) - sqrt(10)) < 1e-15);
    assert_null(json_object_get(steady, "predicted_rmse"));
    assert_true(json_is_null(json_object_get(out, "frames_to_5pct")));
    assert_int_equal(json_array_size(json_object_get(out, "after_cut")), 3);
    assert_true(fabs(json_real_value(json_object_get(json_object_get(out, "flicker"), "ratio")) -
                     1.1) < 1e-15);
    assert_string_equal(
        json_string_value(json_object_get(json_object_get(out, "pattern"), "family")), "T(2)");
    json_decref(out);
    proto_temporal_render_result_free(&r);
    proto_temporal_render_spec_free(&s);
    json_decref(j);
}

/* POST /v1/predict expands a temporal pattern into one pattern per phase, beside spatial ones. */
static void test_predict_temporal(void **state)
{
    (void)state;
    json_t *j =
        parse("{\"patterns\":[\"rgss\",{\"temporal\":{\"preset\":\"halton23-8\"}},"
              "{\"temporal\":{\"jitter\":[[0,0],[0.25,0.25]],\"blend\":{\"kind\":\"box\"}}}]}");
    proto_predict_request rq;
    aa_error err = {0};
    assert_int_equal(proto_decode_predict_request(j, &rq, &err), AA_OK);
    assert_int_equal(rq.pattern_count, 1 + 8 + 2);
    assert_int_equal(rq.phase[0], -1);
    for (size_t p = 0; p < 8; p++) {
        assert_int_equal(rq.source[1 + p], 1);
        assert_int_equal(rq.phase[1 + p], (long)p);
        assert_int_equal(rq.phase_count[1 + p], 8);
        assert_string_equal(rq.names[1 + p], "halton23-8");
    }
    assert_int_equal(rq.source[10], 2);
    assert_int_equal(rq.phase[10], 1);
    char field[32];
    proto_predict_pattern_field(&rq, 10, field, sizeof field);
    assert_string_equal(field, "patterns[2]");
    /* A box blend: every phase has the same kernel (weights 1/2). */
    assert_int_equal(rq.patterns[9].kernels[0].count, 2);
    assert_true(rq.patterns[9].kernels[0].samples[1].w == 0.5);
    proto_predict_request_free(&rq);
    json_decref(j);
    DECODE_FAILS(proto_predict_request, proto_decode_predict_request,
                 "{\"patterns\":[\"rgss\",{\"temporal\":{\"jitter\":[[0.7,0]]}}]}", AA_EINVAL,
                 "patterns[1].temporal.jitter[0]");
}

/* A compare job's temporal pattern: one row per phase, named after its preset. */
static void test_compare_temporal(void **state)
{
    (void)state;
    json_t *j = parse("{\"patterns\":[\"rgss\",{\"temporal\":{\"preset\":\"halton23-8\"}},"
                      "{\"temporal\":{\"jitter\":[[0,0],[0.25,0]]}}]}");
    proto_compare_spec s;
    aa_error err = {0};
    assert_int_equal(proto_decode_compare_spec(j, &s, &err), AA_OK);
    assert_int_equal(s.count, 1 + 8 + 2);
    assert_string_equal(s.names[0], "rgss");
    assert_string_equal(s.names[1], "halton23-8 phase 0");
    assert_string_equal(s.names[8], "halton23-8 phase 7");
    assert_string_equal(s.names[10], "temporal phase 1");
    /* Phase 1 of two offsets at alpha 0.1: the newest frame (offset 1) weighs 0.1 / (1 - 0.81). */
    const aa_kernel *k = &s.patterns[10].kernels[0];
    assert_int_equal(k->count, 2);
    assert_true(fabs(k->samples[1].w - 0.1 / 0.19) < 1e-15);
    proto_compare_spec_free(&s);
    json_decref(j);
    DECODE_FAILS(proto_compare_spec, proto_decode_compare_spec,
                 "{\"patterns\":[{\"temporal\":{\"jitter\":{\"generator\":\"halton\",\"count\":"
                 "1024}}},{\"temporal\":{\"jitter\":{\"generator\":\"halton\",\"count\":8}}}]}",
                 AA_ERANGE, "patterns[1].temporal");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_compare_spec),
        cmocka_unit_test(test_compare_result),
        cmocka_unit_test(test_animation),
        cmocka_unit_test(test_reference_convergence),
        cmocka_unit_test(test_sleep),
        cmocka_unit_test(test_temporal_render),
        cmocka_unit_test(test_predict_temporal),
        cmocka_unit_test(test_compare_temporal),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
