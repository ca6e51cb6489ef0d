/* proto codec: decode errors name full JSON paths; encode -> decode round-trips. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

#include "codec.h"
#include "codec_temporal.h"
#include "export_temporal.h"
#include "aa_pattern.h"
#include <stdlib.h>

static json_t *parse(const char *text)
{
    json_error_t e;
    json_t *j = json_loads(text, JSON_REJECT_DUPLICATES, &e);
    assert_non_null(j);
    return j;
}

static void expect_field(const char *text, const char *field, int code)
{
    json_t *j = parse(text);
    aa_pattern p;
    aa_error err = {0};
    int rc = proto_decode_pattern(j, 0, &p, "pattern", &err);
    if (rc == AA_OK)
        fail_msg("decoded %s", text);
    assert_int_equal(rc, code);
    assert_string_equal(err.field, field);
    assert_true(strlen(err.message) > 0);
    aa_pattern_free(&p);
    json_decref(j);
}

static void test_decode_errors(void **state)
{
    (void)state;
    expect_field("{\"kernels\":[[[0,0,0.5],[0,0,0.25],[0,\"a\",0.25]]]}",
                 "pattern.kernels[0][2][1]", AA_EINVAL);
    expect_field("{\"kernels\":[[[0,0,1]],[[0,0]]]}", "pattern.kernels[1][0]", AA_EINVAL);
    expect_field("{\"kernels\":[[[0,0,0.5]]]}", "pattern.kernels[0]", AA_EINVAL);
    expect_field("{\"kernels\":[]}", "pattern.kernels", AA_EINVAL);
    expect_field("{\"mirrored\":[[0,0,1],[0,0,true]]}", "pattern.mirrored[1][2]", AA_EINVAL);
    expect_field("{\"preset\":\"nope\"}", "pattern.preset", AA_EINVAL);
    expect_field("{\"preset\":\"rgss\",\"kernels\":[]}", "pattern.kernels", AA_EINVAL);
    expect_field("{\"bogus\":1}", "pattern.bogus", AA_EINVAL);
    expect_field("{}", "pattern", AA_EINVAL);
    expect_field("{\"tile\":{\"size\":0,\"samples\":[[0,0]]}}", "pattern.tile.size", AA_ERANGE);
    expect_field("{\"tile\":{\"size\":1,\"samples\":[[0.5,0.5],[0.5,\"x\"]]}}",
                 "pattern.tile.samples[1][1]", AA_EINVAL);
    expect_field("{\"tile\":{\"size\":1,\"samples\":[[0.5,0.5]],\"weights\":[[1,0]]}}",
                 "pattern.tile.weights[0]", AA_EINVAL);
    expect_field("{\"preset\":\"rgss\",\"normalize\":1}", "pattern.normalize", AA_EINVAL);
}

static void test_filter_acuity_errors(void **state)
{
    (void)state;
    aa_filter f;
    aa_acuity a;
    aa_error err = {0};
    json_t *j = parse("{\"name\":\"gaussian\",\"sigma\":-1}");
    assert_int_not_equal(proto_decode_filter(j, &f, "filter", &err), AA_OK);
    assert_string_equal(err.field, "filter.sigma");
    json_decref(j);
    j = parse("{\"name\":\"mitchell\",\"sigma\":1}");
    assert_int_not_equal(proto_decode_filter(j, &f, "filter", &err), AA_OK);
    assert_string_equal(err.field, "filter.sigma");
    json_decref(j);
    j = parse("{\"name\":\"lanczos\",\"a\":3}");
    assert_int_equal(proto_decode_filter(j, &f, "filter", &err), AA_OK);
    assert_int_equal(f.formula, AA_FILTER_LANCZOS);
    json_decref(j);
    assert_int_equal(proto_decode_filter(NULL, &f, "filter", &err), AA_OK);
    assert_string_equal(f.name, "mitchell");

    j = parse("{\"knots\":[[0,1],[45,\"x\"]]}");
    assert_int_not_equal(proto_decode_acuity(j, &a, "acuity", &err), AA_OK);
    assert_string_equal(err.field, "acuity.knots[1][1]");
    json_decref(j);
    j = parse("{\"name\":\"nope\"}");
    assert_int_not_equal(proto_decode_acuity(j, &a, "acuity", &err), AA_OK);
    assert_string_equal(err.field, "acuity.name");
    json_decref(j);
    assert_int_equal(proto_decode_acuity(NULL, &a, "acuity", &err), AA_OK);
    assert_string_equal(a.name, "naiman");

    double *angles;
    size_t n;
    j = parse("[0, 10, null]");
    assert_int_not_equal(proto_decode_angles(j, &angles, &n, "angles", &err), AA_OK);
    assert_string_equal(err.field, "angles[2]");
    json_decref(j);
}

/* Two patterns are equal: same form, family, and kernels sample for sample. */
static void assert_patterns_equal(const aa_pattern *a, const aa_pattern *b)
{
    assert_int_equal(a->form, b->form);
    assert_string_equal(a->family, b->family);
    assert_true(a->cost_spp == b->cost_spp);
    assert_int_equal(a->kernel_count, b->kernel_count);
    for (size_t k = 0; k < a->kernel_count; k++) {
        assert_int_equal(a->kernels[k].count, b->kernels[k].count);
        for (size_t i = 0; i < a->kernels[k].count; i++) {
            assert_true(a->kernels[k].samples[i].x == b->kernels[k].samples[i].x);
            assert_true(a->kernels[k].samples[i].y == b->kernels[k].samples[i].y);
            assert_true(fabs(a->kernels[k].samples[i].w - b->kernels[k].samples[i].w) < 1e-15);
        }
    }
}

static void round_trip(const aa_pattern *p)
{
    json_t *enc = proto_encode_pattern(p);
    assert_non_null(enc);
    /* through text, as on the wire */
    char *text = json_dumps(enc, JSON_COMPACT);
    json_decref(enc);
    json_t *back = parse(text);
    free(text);
    aa_pattern q;
    aa_error err = {0};
    int rc = proto_decode_pattern(back, 0, &q, "", &err);
    if (rc)
        fail_msg("round trip failed: %s at %s", err.message, err.field);
    assert_patterns_equal(p, &q);
    aa_pattern_free(&q);
    json_decref(back);
}

static void test_round_trip_presets(void **state)
{
    (void)state;
    for (size_t i = 0; i < aa_preset_count(); i++) {
        aa_pattern p;
        aa_error err = {0};
        assert_int_equal(aa_pattern_from_preset(&p, aa_preset_at(i), &err), AA_OK);
        round_trip(&p);
        aa_pattern_free(&p);
    }
}

static void test_round_trip_forms(void **state)
{
    (void)state;
    const char *inputs[] = {
        "{\"kernels\":[[[0.1,0.2,0.7],[-0.3,0.4,0.3]]]}",
        "{\"kernels\":[[[0,0,1]],[[0.1,0,1]],[[0,0.1,1]],[[0.2,0.2,1]]]}",
        "{\"mirrored\":[[-0.5,0.25,0.25],[-0.25,-0.5,0.25],[0.5,-0.25,0.25],[0.25,0.5,0.25]]}",
        /* One literal: clang's -Wstring-concatenation flags split literals in arrays. */
        // clang-format off
        "{\"tile\":{\"size\":2,\"kernel\":1,\"border\":true,\"samples\":[[0.5,0.5],[1.5,0.5],[0.5,1.5],[1.5,1.5]]}}",
        // clang-format on
        "{\"kernels\":[[[0,0,2],[0.25,0.25,2]]],\"normalize\":true}",
    };
    for (size_t i = 0; i < sizeof inputs / sizeof inputs[0]; i++) {
        json_t *j = parse(inputs[i]);
        aa_pattern p;
        aa_error err = {0};
        int rc = proto_decode_pattern(j, 0, &p, "pattern", &err);
        if (rc)
            fail_msg("%s: %s at %s", inputs[i], err.message, err.field);
        round_trip(&p);
        aa_pattern_free(&p);
        json_decref(j);
    }
}

/* Every named filter encodes to JSON that decodes to the same filter. */
static void test_filter_round_trip(void **state)
{
    (void)state;
    for (size_t i = 0; aa_filter_names[i]; i++) {
        aa_filter f, g;
        aa_error err = {0};
        assert_int_equal(aa_filter_by_name(&f, aa_filter_names[i], NULL, &err), AA_OK);
        json_t *j = proto_encode_filter(&f);
        int rc = proto_decode_filter(j, &g, "filter", &err);
        if (rc)
            fail_msg("%s: %s at %s", aa_filter_names[i], err.message, err.field);
        assert_string_equal(f.name, g.name);
        assert_true(f.radius == g.radius && f.pieces == g.pieces);
        assert_true(aa_filter_cdf(&f, 0.3) == aa_filter_cdf(&g, 0.3));
        json_decref(j);
    }
    json_t *j = parse("{\"name\":\"catmull-rom\",\"B\":0.2}");
    aa_filter f;
    aa_error err = {0};
    assert_int_not_equal(proto_decode_filter(j, &f, "filter", &err), AA_OK);
    assert_string_equal(err.field, "filter.B");
    json_decref(j);
}

static void test_encode_evaluation(void **state)
{
    (void)state;
    aa_pattern p;
    aa_error err = {0};
    assert_int_equal(aa_pattern_from_preset(&p, aa_preset_find("quincunx"), &err), AA_OK);
    aa_filter f;
    aa_acuity a;
    aa_filter_default(&f);
    aa_acuity_naiman(&a);
    aa_metric_params mp = {.filter = &f, .acuity = &a};
    aa_evaluation ev;
    assert_int_equal(aa_evaluate(&p, &mp, &ev, &err), AA_OK);
    json_t *o = proto_encode_evaluation(&ev, &p, true);
    assert_true(fabs(json_real_value(json_object_get(o, "e2")) - 0.518) < 5e-4);
    json_t *arg = json_object_get(o, "argmax");
    assert_true(json_real_value(json_object_get(arg, "angle_deg")) == 45.0);
    assert_string_equal(json_string_value(json_object_get(o, "family")), p.family);
    json_t *detail = json_object_get(o, "detail");
    assert_int_equal(json_array_size(detail), ev.kernel_count);
    json_t *angles = json_object_get(json_array_get(detail, 0), "angles");
    assert_int_equal(json_array_size(angles), ev.angle_count);
    json_decref(o);
    aa_evaluation_free(&ev);
    aa_pattern_free(&p);

    json_t *fj = proto_encode_filter(&f);
    aa_filter g;
    assert_int_equal(proto_decode_filter(fj, &g, "filter", &err), AA_OK);
    assert_true(g.B == f.B && g.C == f.C && g.radius == f.radius);
    json_decref(fj);
}

/* A temporal pattern's explicit encoding decodes to the same sequence and setting bit for bit
 * (a preset with a resolve); phase p's pattern holds the N samples with the age weights of
 * phase p; the jitter text's first line is that encoding. */
static void test_temporal_encode_and_export(void **state)
{
    (void)state;
    aa_error err = {0};
    json_t *in = json_loads("{\"temporal\": {\"preset\": \"urp-like\"}}", 0, NULL);
    proto_temporal a, b;
    assert_int_equal(proto_decode_temporal(in, &a, "pattern", &err), AA_OK);
    json_t *enc = proto_encode_temporal(&a);
    assert_non_null(enc);
    char *text = json_dumps(enc, JSON_COMPACT);
    json_t *back = json_loads(text, 0, NULL);
    assert_int_equal(proto_decode_temporal(back, &b, "pattern", &err), AA_OK);
    assert_int_equal(a.count, b.count);
    assert_memory_equal(a.jitter, b.jitter, a.count * sizeof *a.jitter);
    assert_true(a.blend.kind == b.blend.kind && a.blend.alpha == b.blend.alpha);
    assert_true(b.has_resolve && a.resolve.radius == b.resolve.radius);
    assert_true(a.jitter_range == b.jitter_range);
    /* Phase 2 of Halton x 8 without the resolve: offset f weighs the age weight of (2 - f) mod 8.
     */
    a.has_resolve = false;
    aa_pattern p;
    assert_int_equal(proto_temporal_phase_pattern(&a, 2, &p, &err), AA_OK);
    double w[8];
    assert_int_equal(aa_blend_weights(&a.blend, 8, w, &err), AA_OK);
    assert_int_equal(p.kernel_count, 1);
    assert_int_equal(p.kernels[0].count, 8);
    for (size_t f = 0; f < 8; f++) {
        const aa_sample *s = &p.kernels[0].samples[f];
        size_t k = 0;
        while (k < 8 && !(a.jitter[k].x == s->x && a.jitter[k].y == s->y))
            k++;
        assert_true(k < 8);
        assert_true(fabs(s->w - w[(2 + 8 - k) % 8]) < 1e-15);
    }
    aa_pattern_free(&p);
    assert_int_equal(proto_temporal_phase_pattern(&a, 8, &p, &err), AA_EINVAL);
    assert_string_equal(err.field, "phase");
    size_t len = 0;
    char *c = proto_export_jitter_text(&b, false, &len, &err);
    assert_non_null(c);
    assert_int_equal(strlen(c), len);
    assert_non_null(strstr(c, "#define AALAB_JITTER_COUNT 8"));
    const char *nl = strchr(c, '\n');
    json_t *first = json_loadb(c + 18, (size_t)(nl - c - 18), 0, NULL);
    assert_true(!strncmp(c, "// aalab-temporal ", 18) && json_equal(first, enc));
    bool hlsl = false;
    assert_true(proto_jitter_format_parse("jitter-hlsl", &hlsl) && hlsl);
    assert_false(proto_jitter_format_parse("csv", &hlsl));
    json_decref(first);
    free(c);
    free(text);
    json_decref(back);
    json_decref(enc);
    json_decref(in);
    proto_temporal_free(&a);
    proto_temporal_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_decode_errors),
        cmocka_unit_test(test_filter_acuity_errors),
        cmocka_unit_test(test_round_trip_presets),
        cmocka_unit_test(test_round_trip_forms),
        cmocka_unit_test(test_encode_evaluation),
        cmocka_unit_test(test_filter_round_trip),
        cmocka_unit_test(test_temporal_encode_and_export),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
