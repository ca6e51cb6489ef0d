/* proto codec of the renderer (codec_scene.h, codec_render.h): every bad field named by its
 * full path, defaults, the scene encoding decoding back, and the POST /v1/render request. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

#include "codec_render.h"
#include "codec_scene.h"

static json_t *parse(const char *text)
{
    json_error_t e;
    json_t *j = json_loads(text, JSON_REJECT_DUPLICATES | JSON_DECODE_ANY, &e);
    if (!j)
        fail_msg("%s: %s", text, e.text);
    return j;
}

typedef int (*decode_fn)(const json_t *j, aa_error *err);

static int scene(const json_t *j, aa_error *err)
{
    aa_scene_params sp;
    return proto_decode_scene(j, &sp, "scene", err);
}

static int scene_request(const json_t *j, aa_error *err)
{
    aa_scene_params sp;
    return proto_decode_scene_request(j, &sp, err);
}

static int reference(const json_t *j, aa_error *err)
{
    proto_reference_spec rs;
    return proto_decode_reference(j, &rs, "reference", err);
}

static int crop64x48(const json_t *j, aa_error *err)
{
    proto_crop c;
    return proto_decode_crop(j, 64, 48, &c, "crop", err);
}

static int render(const json_t *j, aa_error *err)
{
    proto_render_request rq;
    int rc = proto_decode_render_request(j, &rq, err);
    if (!rc)
        proto_render_request_free(&rq);
    return rc;
}

static void expect_bad(decode_fn fn, const char *text, const char *field)
{
    json_t *j = parse(text);
    aa_error err = {0};
    int rc = fn(j, &err);
    if (rc != AA_EINVAL)
        fail_msg("%s: rc %d, expected AA_EINVAL", text, rc);
    if (strcmp(err.field, field))
        fail_msg("%s: field \"%s\", expected \"%s\"", text, err.field, field);
    assert_true(strlen(err.message) > 0);
    json_decref(j);
}

static void expect_good(decode_fn fn, const char *text)
{
    json_t *j = parse(text);
    aa_error err = {0};
    if (fn(j, &err))
        fail_msg("%s: %s (%s)", text, err.message, err.field);
    json_decref(j);
}

static void test_scene_fields(void **state)
{
    (void)state;
    expect_good(scene, "{\"name\":\"rings\",\"width\":32,\"height\":16,\"mirror_x\":true}");
    expect_bad(scene, "[]", "scene");
    expect_bad(scene, "{\"colour\":1}", "scene.colour");
    expect_bad(scene, "{\"name\":7}", "scene.name");
    expect_bad(scene, "{\"height\":1.5}", "scene.height");
    expect_bad(scene, "{\"angle\":\"up\"}", "scene.angle");
    expect_bad(scene, "{\"mirror_y\":1}", "scene.mirror_y");
    expect_bad(scene, "{\"wedges\":0}", "scene.wedges");
    aa_scene_params sp;
    assert_int_equal(proto_decode_scene(NULL, &sp, "scene", NULL), AA_OK);
    assert_int_equal(sp.shape, AA_SCENE_SIEMENS_STAR);

    json_t *j = parse("{\"scene\":\"spiral\",\"size\":[64,48]}");
    assert_int_equal(proto_decode_scene_request(j, &sp, NULL), AA_OK);
    assert_int_equal(sp.shape, AA_SCENE_SPIRAL);
    assert_int_equal(sp.width, 64);
    assert_int_equal(sp.height, 48);
    json_decref(j);
    expect_good(scene_request, "{\"scene\":{\"name\":\"checkerboard\",\"zoom\":2}}");
    expect_bad(scene_request, "{\"scene\":\"teapot\"}", "scene");
    expect_bad(scene_request, "{\"scene\":{\"name\":\"teapot\"}}", "scene.name");
    expect_bad(scene_request, "{\"scene\":3,\"size\":[8,8]}", "scene");
    expect_bad(scene_request, "{\"size\":[8]}", "size");
    expect_bad(scene_request, "{\"size\":[0,8]}", "size[0]");
    expect_bad(scene_request, "{\"size\":[8,-1]}", "size[1]");
    expect_bad(scene_request, "{\"scene\":{\"width\":8},\"size\":[8,8]}", "size");
    expect_bad(scene_request, "{\"scene\":{\"name\":\"rings\",\"tint\":1},\"size\":[8,8]}",
               "scene.tint");
}

static void test_reference_fields(void **state)
{
    (void)state;
    proto_reference_spec rs;
    assert_int_equal(proto_decode_reference(NULL, &rs, "reference", NULL), AA_OK);
    assert_null(rs.params.filter);
    json_t *j = parse("{\"spp\":64,\"seed\":3,\"filter\":\"gaussian\"}");
    assert_int_equal(proto_decode_reference(j, &rs, "reference", NULL), AA_OK);
    assert_int_equal(rs.params.spp, 64);
    assert_int_equal(rs.params.seed, 3);
    assert_ptr_equal(rs.params.filter, &rs.filter);
    json_decref(j);
    expect_bad(reference, "{\"spp\":1000}", "reference.spp");
    expect_bad(reference, "{\"spp\":\"many\"}", "reference.spp");
    expect_bad(reference, "{\"seed\":-1}", "reference.seed");
    expect_bad(reference, "{\"rays\":4}", "reference.rays");
    expect_bad(reference, "{\"filter\":3}", "reference.filter");
    expect_bad(reference, "{\"filter\":{\"B\":0}}", "reference.filter.name");
    expect_bad(reference, "{\"filter\":{\"name\":\"mitchell\",\"D\":0}}", "reference.filter.D");
    expect_bad(reference, "{\"filter\":{\"name\":\"mitchell\",\"B\":\"x\"}}", "reference.filter.B");
    expect_bad(reference, "{\"filter\":{\"name\":\"box\",\"radius\":9}}", "reference.filter");
}

static void test_crop_fields(void **state)
{
    (void)state;
    proto_crop c;
    assert_int_equal(proto_decode_crop(NULL, 64, 48, &c, "crop", NULL), AA_OK);
    assert_false(c.enabled);
    json_t *j = parse("{}");
    assert_int_equal(proto_decode_crop(j, 20, 48, &c, "crop", NULL), AA_OK);
    assert_true(c.enabled);
    assert_int_equal(c.rect.x1 - c.rect.x0, 20); /* the default 32 clipped to the image */
    assert_int_equal(c.rect.y1 - c.rect.y0, 32);
    assert_int_equal(c.scale, 8);
    json_decref(j);
    expect_bad(crop64x48, "{\"x\":60,\"width\":10}", "crop.width");
    expect_bad(crop64x48, "{\"y\":40,\"height\":10}", "crop.height");
    expect_bad(crop64x48, "{\"x\":64}", "crop.x");
    expect_bad(crop64x48, "{\"scale\":33}", "crop.scale");
    expect_bad(crop64x48, "{\"width\":48,\"height\":48,\"scale\":32}", "crop.scale");
    expect_bad(crop64x48, "{\"zoom\":2}", "crop.zoom");
    expect_bad(crop64x48, "7", "crop");
}

static void test_scene_encoding_decodes_back(void **state)
{
    (void)state;
    const char *specs[] = {
        "{\"name\":\"half-plane\",\"width\":40,\"height\":30,\"offset\":0.25,\"angle\":12}",
        "{\"name\":\"rotating-triangle\",\"frames\":8,\"frame\":3,\"zoom\":1.5}",
        "{\"name\":\"siemens-star\",\"wedges\":24,\"mirror_x\":true}",
    };
    for (size_t i = 0; i < sizeof specs / sizeof specs[0]; i++) {
        json_t *j = parse(specs[i]);
        aa_scene_params a, b;
        assert_int_equal(proto_decode_scene(j, &a, "scene", NULL), AA_OK);
        json_t *enc = proto_encode_scene(&a);
        assert_non_null(enc);
        aa_error err = {0};
        if (proto_decode_scene(enc, &b, "scene", &err))
            fail_msg("%s: %s (%s)", specs[i], err.message, err.field);
        assert_int_equal(a.shape, b.shape);
        assert_int_equal(a.width, b.width);
        assert_int_equal(a.height, b.height);
        assert_float_equal(a.zoom, b.zoom, 0);
        assert_float_equal(a.angle_deg, b.angle_deg, 0);
        assert_float_equal(a.offset, b.offset, 0);
        assert_int_equal(a.wedges, b.wedges);
        assert_int_equal(a.frames, b.frames);
        assert_int_equal(a.frame, b.frame);
        assert_int_equal(a.mirror_x, b.mirror_x);
        json_decref(enc);
        json_decref(j);
    }
}

static void test_preset_names(void **state)
{
    (void)state;
    aa_pattern p;
    aa_error err = {0};
    json_t *j = json_string("flipquad");
    assert_int_equal(proto_pattern_from_preset_name(j, &p, "patterns[2]", &err), AA_OK);
    assert_true(p.kernel_count > 0);
    aa_pattern_free(&p);
    json_decref(j);
    j = json_string("flopquad");
    assert_int_equal(proto_pattern_from_preset_name(j, &p, "patterns[2]", &err), AA_EINVAL);
    assert_string_equal(err.field, "patterns[2]");
    assert_non_null(strstr(err.message, "did you mean \"flipquad\""));
    json_decref(j);
    j = parse("{\"preset\":\"flipquad\"}");
    assert_int_equal(proto_pattern_from_preset_name(j, &p, "pattern", &err), 1);
    aa_pattern q;
    assert_int_equal(proto_decode_pattern_or_name(j, 0, &q, "pattern", &err), AA_OK);
    json_decref(j);
    j = json_string("flipquad");
    assert_int_equal(proto_decode_pattern_or_name(j, 0, &p, "pattern", &err), AA_OK);
    assert_int_equal(p.kernel_count, q.kernel_count);
    assert_int_equal(p.kernels[0].count, q.kernels[0].count);
    for (size_t i = 0; i < p.kernels[0].count; i++) {
        assert_float_equal(p.kernels[0].samples[i].x, q.kernels[0].samples[i].x, 0);
        assert_float_equal(p.kernels[0].samples[i].y, q.kernels[0].samples[i].y, 0);
    }
    aa_pattern_free(&p);
    aa_pattern_free(&q);
    json_decref(j);
    j = parse("{\"kernels\":[[[0,0,\"w\"]]]}");
    assert_int_equal(proto_decode_pattern_or_name(j, 0, &p, "patterns[1]", &err), AA_EINVAL);
    assert_string_equal(err.field, "patterns[1].kernels[0][0][2]");
    json_decref(j);
}

static void test_render_request(void **state)
{
    (void)state;
    json_t *j = parse("{\"scene\":\"rings\",\"size\":[24,16],\"pattern\":\"rgss\","
                      "\"reference\":{\"spp\":16,\"filter\":\"gaussian\"},\"crop\":{\"scale\":2},"
                      "\"acuity\":{\"name\":\"uniform\"},\"visibility\":\"private\"}");
    proto_render_request rq;
    aa_error err = {0};
    if (proto_decode_render_request(j, &rq, &err))
        fail_msg("%s (%s)", err.message, err.field);
    json_decref(j);
    assert_int_equal(rq.scene.shape, AA_SCENE_RINGS);
    assert_int_equal(rq.scene.width, 24);
    assert_true(rq.private_tiles);
    assert_true(rq.crop.enabled);
    assert_int_equal(rq.crop.rect.x1, 24); /* the default width clipped to the image */
    assert_true(rq.pattern.kernel_count > 0);
    aa_render_params rp = proto_render_params(&rq);
    assert_int_equal(rp.reference.spp, 16);
    assert_ptr_equal(rp.reference.filter, &rq.reference.filter);
    assert_ptr_equal(rp.acuity, &rq.acuity);
    assert_int_equal(rp.scene.height, 16);
    proto_render_request_free(&rq);

    expect_good(render, "{\"pattern\":{\"preset\":\"rgss\"},\"visibility\":\"team\"}");
    expect_bad(render, "[1]", "");
    expect_bad(render, "{\"scene\":\"rings\"}", "pattern");
    expect_bad(render, "{\"pattern\":\"rgss\",\"bogus\":1}", "bogus");
    expect_bad(render, "{\"pattern\":\"rgss\",\"visibility\":\"world\"}", "visibility");
    expect_bad(render, "{\"pattern\":\"rgss\",\"visibility\":true}", "visibility");
    expect_bad(render, "{\"pattern\":{\"preset\":\"nope\"}}", "pattern.preset");
    expect_bad(render, "{\"pattern\":\"rgss\",\"size\":[8,8],\"crop\":{\"x\":8}}", "crop.x");
    expect_bad(render, "{\"pattern\":\"rgss\",\"acuity\":{\"name\":\"eagle\"}}", "acuity.name");
    expect_bad(render, "{\"pattern\":\"rgss\",\"reference\":{\"spp\":2}}", "reference.spp");
}

static void test_render_answer(void **state)
{
    (void)state;
    aa_render_params rp = aa_render_params_default(AA_SCENE_CHECKERBOARD);
    rp.scene.width = 16;
    rp.scene.height = 12;
    rp.reference.spp = 16;
    aa_pattern p;
    json_t *name = json_string("rgss");
    assert_int_equal(proto_pattern_from_preset_name(name, &p, "pattern", NULL), AA_OK);
    json_decref(name);
    aa_render_result r;
    assert_int_equal(aa_render_tile(&rp, &p, &r, NULL), AA_OK);
    assert_null(proto_encode_render_result(&rp, &p, &r, NULL));
    json_t *out = proto_encode_render_result(&rp, &p, &r, json_pack("{s:s}", "pattern", "t"));
    assert_non_null(out);
    assert_float_equal(json_real_value(json_object_get(out, "e2")), r.e2, 0);
    assert_string_equal(json_string_value(json_object_get(json_object_get(out, "scene"), "name")),
                        "checkerboard");
    assert_int_equal(json_integer_value(json_object_get(json_object_get(out, "reference"), "spp")),
                     16);
    assert_string_equal(
        json_string_value(json_object_get(json_object_get(out, "reference"), "filter")),
        "mitchell");
    assert_int_equal(json_integer_value(json_object_get(json_object_get(out, "pixels"), "total")),
                     (json_int_t)r.ref.pixels);
    json_t *stats = json_object_get(out, "stats");
    assert_float_equal(json_real_value(json_object_get(stats, "rmse")), r.diff.rmse, 0);
    assert_int_equal(json_array_size(json_object_get(stats, "histogram")), 256);
    assert_string_equal(
        json_string_value(json_object_get(json_object_get(out, "tiles"), "pattern")), "t");
    json_decref(out);
    aa_render_result_free(&r);
    aa_pattern_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scene_fields),  cmocka_unit_test(test_reference_fields),
        cmocka_unit_test(test_crop_fields),   cmocka_unit_test(test_scene_encoding_decodes_back),
        cmocka_unit_test(test_preset_names),  cmocka_unit_test(test_render_request),
        cmocka_unit_test(test_render_answer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
