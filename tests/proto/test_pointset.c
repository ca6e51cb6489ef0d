/* proto/pointset: the point-set formats (utk, xyw, csv, json), the "points" pattern form, the
 * coordinate conventions between the forms, and export -> import round trips (engine + codec,
 * no daemon): the same E2 to 1e-12 for every preset and for patterns of P(4,1+,2), P(16,16,4). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "aa_metric.h"
#include "aa_pattern.h"
#include "codec.h"
#include "codec_check.h"
#include "pointset.h"

#define ROUND_TRIP_TOLERANCE 1e-12

static double e2_of(const aa_pattern *p)
{
    aa_filter f;
    aa_filter_default(&f);
    aa_acuity a;
    aa_acuity_naiman(&a);
    aa_metric_params mp = {.filter = &f, .acuity = &a};
    aa_evaluation ev;
    aa_error err = {0};
    assert_int_equal(aa_evaluate(p, &mp, &ev, &err), AA_OK);
    double e2 = ev.e2;
    aa_evaluation_free(&ev);
    return e2;
}

/* {"points":{"format":fmt,"text":text, extra...}} decoded; rc and err for the caller. */
static int decode_points(const char *fmt, const char *text, const char *extra_json, aa_pattern *p,
                         aa_error *err)
{
    json_t *o = json_pack("{s:{s:s,s:s}}", "points", "format", fmt, "text", text);
    assert_non_null(o);
    if (extra_json) {
        json_t *x = parse(extra_json);
        json_object_update(json_object_get(o, "points"), x);
        json_decref(x);
    }
    int rc = proto_decode_pattern(o, 0, p, "pattern", err);
    json_decref(o);
    return rc;
}

static void expect_error(const char *fmt, const char *text, const char *extra, const char *field,
                         const char *message_part)
{
    aa_pattern p;
    aa_error err = {0};
    int rc = decode_points(fmt, text, extra, &p, &err);
    if (rc == AA_OK)
        fail_msg("decoded %s: %s", fmt, text);
    assert_string_equal(err.field, field);
    if (!strstr(err.message, message_part))
        fail_msg("message '%s' lacks '%s'", err.message, message_part);
}

static void parse_ok(const char *text, proto_points_format fmt, proto_pointset *ps)
{
    aa_error err = {0};
    int rc = proto_pointset_parse(text, strlen(text), fmt, ps, "t", &err);
    if (rc)
        fail_msg("%s: %s", err.field, err.message);
}

static void test_parse_formats(void **state)
{
    (void)state;
    proto_pointset ps;
    parse_ok("# UTK\n\n0.25 0.5\r\n  0.75\t0.125  \n# end\n", PROTO_POINTS_UTK, &ps);
    assert_int_equal(ps.count, 2);
    assert_false(ps.has_weights);
    assert_null(ps.header);
    assert_true(ps.points[1].x == 0.75 && ps.points[1].y == 0.125);
    assert_int_equal(ps.where[1], 4);
    proto_pointset_free(&ps);

    parse_ok("0.1 0.2 0.5\n0.3 0.4 0.5\n", PROTO_POINTS_XYW, &ps);
    assert_true(ps.has_weights);
    assert_true(ps.points[1].w == 0.5);
    proto_pointset_free(&ps);

    parse_ok("# aalab-pattern {\"tile\":2}\n y , W,x\n0.2,0.5,0.1\n\"0.4\",0.5,0.3\n",
             PROTO_POINTS_CSV, &ps);
    assert_int_equal(ps.count, 2);
    assert_true(ps.has_weights);
    assert_true(ps.points[0].x == 0.1 && ps.points[0].y == 0.2 && ps.points[0].w == 0.5);
    assert_true(ps.points[1].y == 0.4);
    assert_non_null(ps.header);
    assert_int_equal(json_integer_value(json_object_get(ps.header, "tile")), 2);
    proto_pointset_free(&ps);

    parse_ok("[[0.1,0.2],{\"y\":0.4,\"x\":0.3}]", PROTO_POINTS_JSON, &ps);
    assert_int_equal(ps.count, 2);
    assert_true(ps.points[1].x == 0.3 && ps.points[1].y == 0.4);
    proto_pointset_free(&ps);

    parse_ok("{\"aalab\":{\"tile\":1},\"points\":[[0.5,0.5,1]]}", PROTO_POINTS_JSON, &ps);
    assert_non_null(ps.header);
    assert_true(ps.has_weights);
    proto_pointset_free(&ps);
}

static void test_parse_errors(void **state)
{
    (void)state;
    const char *F = "pattern.points.text";
    expect_error("utk", "0.1 0.2\n\n0.3\n", NULL, F, "line 3: expected 2 numbers (x y)");
    expect_error("utk", "0.1 0.2 0.3\n", NULL, F, "line 1: expected 2 numbers");
    expect_error("xyw", "0.1 0.2\n0.3 0.4 1\n", NULL, F, "line 2: 3 numbers, but line 1 has 2");
    expect_error("xyw", "0.1 0.2 0.3 0.4\n", NULL, F, "line 1: expected 2 or 3 numbers");
    expect_error("xyw", "0.1 abc\n", NULL, F, "line 1: 'abc' is not a number");
    expect_error("xyw", "0.1 nan\n", NULL, F, "line 1: 'nan' is not a number");
    expect_error("xyw", "0.1 1e999\n", NULL, F, "line 1: '1e999' is not a number");
    expect_error("xyw", "# only a comment\n", NULL, F, "no points");
    expect_error("csv", "x,y,z\n0,0,0\n", NULL, F, "line 1: unknown column 'z'");
    expect_error("csv", "x,x\n", NULL, F, "line 1: column x twice");
    expect_error("csv", "x,y,w,z\n0,0,0,0\n", NULL, F, "line 1: unknown column 'z'");
    expect_error("csv", "x,y,w,,\n", NULL, F, "line 1: unknown column ''");
    expect_error("csv", "x,w\n", NULL, F, "line 1: the header line must name columns x and y");
    expect_error("csv", "0.1,0.2\n", NULL, F, "line 1: unknown column '0.1'");
    expect_error("csv", "x,y\n0.1,0.2\n0.3\n", NULL, F,
                 "line 3: 1 field, but the header (line 1) names 2");
    expect_error("csv", "x,y\n0.1,0.2,0.3\n", NULL, F,
                 "line 2: 3 fields, but the header (line 1) names 2");
    expect_error("csv", "x,y\n0.1,\n", NULL, F, "line 2: y: '' is not a number");
    expect_error("json", "[[0.1,0.2],[0.3]]", NULL, F, "point 1: a point is [x, y] or [x, y, w]");
    expect_error("json", "[[0.1,0.2],[0.3,0.4,1]]", NULL, F, "point 1: has w but point 0 has not");
    expect_error("json", "[{\"x\":0.1,\"z\":0}]", NULL, F, "point 0: unknown key 'z'");
    expect_error("json", "[[0.1,0.2]", NULL, F, "line 1: not valid JSON");
    expect_error("json", "[]", NULL, F, "no points");
    expect_error("utk", "# aalab-pattern {\"tile\":\n0.5 0.5\n", NULL, F,
                 "line 1: the aalab-pattern header is not a JSON object");
    expect_error("utk", "0.5 0.5\n# aalab-pattern {}\n", NULL, F,
                 "line 2: the aalab-pattern header must come before the points");
    expect_error("utk", "# aalab-pattern {}\n# aalab-pattern {}\n0.5 0.5\n", NULL, F,
                 "line 2: a second aalab-pattern header");
    /* Non-ASCII bytes never reach the message (it goes into JSON). */
    aa_pattern p;
    aa_error err = {0};
    assert_int_not_equal(decode_points("xyw", "0.5 \xc3\xa9\n", NULL, &p, &err), AA_OK);
    assert_non_null(strstr(err.message, "'?\?' is not a number"));
    /* Long multi-byte keys are cut at a character boundary: the message stays UTF-8. */
    memset(&err, 0, sizeof err);
    assert_int_not_equal(decode_points("json",
                                       "[{\"a\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9"
                                       "\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9"
                                       "\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9"
                                       "x\":1}]",
                                       "{\"weights\":\"equal\"}", &p, &err),
                         AA_OK);
    json_t *msg = json_string(err.message);
    assert_non_null(msg);
    json_decref(msg);
    /* So are unknown keys in a field path (proto_check_keys, the one unknown-key check). */
    json_t *o = json_pack("{s:s,s:i}", "preset", "rgss",
                          "a\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9"
                          "\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9"
                          "\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9"
                          "\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9",
                          1);
    assert_non_null(o);
    assert_int_equal(proto_decode_pattern(o, 0, &p, "pattern", &err), AA_EINVAL);
    msg = json_string(err.field);
    assert_non_null(msg);
    json_decref(msg);
    assert_true(!strncmp(err.field, "pattern.a\xc3\xa9", 10));
    json_decref(o);
    /* More than a tile's worth of points. */
    char *big = malloc(8 * (PROTO_POINTS_MAX + 1) + 1);
    assert_non_null(big);
    big[0] = 0;
    for (int i = 0; i <= PROTO_POINTS_MAX; i++)
        strcat(big, "0.5 0.5\n");
    expect_error("utk", big, NULL, F, "line 4097: more than 4096 points");
    free(big);
}

/* jansson's error text echoes the input as it is: bytes that are not UTF-8 come out as '?', so
 * the message can go into a JSON answer (found by fuzz_pointset_parser). */
static void test_error_text_is_utf8(void **state)
{
    (void)state;
    const char text[] = "{\"aal\\\xcf\x9d\xdd\xc5\x84\x82\xd0\"poi\x19s\":1}";
    proto_pointset ps;
    aa_error err = {0};
    assert_int_not_equal(
        proto_pointset_parse(text, sizeof text - 1, PROTO_POINTS_JSON, &ps, "t", &err), AA_OK);
    json_t *js = json_string(err.message);
    if (!js)
        fail_msg("message is not UTF-8: %s", err.message);
    json_decref(js);
    if (!strstr(err.message, "near '\"aal\\?'")) /* jansson stops after the lone 0xcf */
        fail_msg("message '%s' lacks the '?'", err.message);
}

static void test_points_form_errors(void **state)
{
    (void)state;
    expect_error("utk", "0.5 0.5\n", NULL, "pattern.points.weights",
                 "the points have no weights; choose filter or equal");
    expect_error("xyw", "0.5 0.5 1\n", "{\"kernel\":2}", "pattern.points.weights", "need kernel 1");
    expect_error("utk", "0.5 0.5\n0.25 1.5\n", "{\"weights\":\"equal\"}", "pattern.points.text",
                 "line 2: (0.25, 1.5) lies outside the unit square");
    expect_error("utk", "0.5 0.5\n0.5 0.5\n", "{\"weights\":\"equal\"}", "pattern.points.text",
                 "line 2: two samples at the same tile position");
    expect_error("utk", "0.1 0.1\n", "{\"weights\":\"equal\",\"tile\":2}", "pattern.points.text",
                 "pixel (1, 0) of the tile: kernel 1 reads no sample");
    expect_error("xyw", "0.25 0.25 0.5\n0.75 0.75 0.25\n", NULL, "pattern.points.text",
                 "pixel (0, 0) of the tile: weights sum to 0.75");
    expect_error("utk", "0.5 0.5\n", "{\"weights\":\"equal\",\"tile\":17}", "pattern.points.tile",
                 "must be in 1..16");
    expect_error("utk", "0.5 0.5\n", "{\"weights\":\"some\"}", "pattern.points.weights",
                 "must be file, filter or equal");
    expect_error("utk", "0.5 0.5\n", "{\"bogus\":1}", "pattern.points.bogus", "unknown field");
    expect_error("dat", "0.5 0.5\n", NULL, "pattern.points.format",
                 "must be utk, xyw, csv, json, bin or rps");
    expect_error("utk", "0.5 0.5\n", "{\"data\":[[0.5,0.5]]}", "pattern.points.data",
                 "give exactly one of text");
    expect_error("utk", "# aalab-pattern {\"tile\":2,\"weights\":[]}\n0.25 0.25\n", "{\"tile\":4}",
                 "pattern.points.tile", "is 4 but the file's aalab-pattern header says 2");
    expect_error("utk", "# aalab-pattern {\"tile\":1,\"weights\":[[0.5]]}\n0.25 0.25\n", NULL,
                 "pattern.points.text",
                 "line 1: aalab-pattern header: weights of pixel (0, 0): weights sum to 0.5");
    expect_error("utk", "# aalab-pattern {\"tile\":1,\"colour\":1}\n0.25 0.25\n", NULL,
                 "pattern.points.text", "line 1: aalab-pattern header: unknown key 'colour'");
    expect_error("utk", "# aalab-pattern {\"pattern\":{\"kernels\":[[[0,0,1]]]}}\n0.25 0.25\n",
                 NULL, "pattern.points.text",
                 "line 1: aalab-pattern header: the points are not those");
    expect_error(
        "utk",
        "# aalab-pattern {\"pattern\":{\"points\":{\"format\":\"utk\",\"text\":\"\"}}}"
        "\n0.25 0.25\n",
        NULL, "pattern.points.text",
        "line 1: aalab-pattern header: pattern must be a preset, kernels, mirrored or tile");

    /* data: the index is in the field. */
    json_t *o = parse("{\"points\":{\"format\":\"json\",\"weights\":\"equal\","
                      "\"data\":[[0.5,0.5],[0.1,\"a\"]]}}");
    aa_pattern p;
    aa_error err = {0};
    assert_int_equal(proto_decode_pattern(o, 0, &p, "pattern", &err), AA_EINVAL);
    assert_string_equal(err.field, "pattern.points.data[1]");
    json_decref(o);
    o = parse("{\"points\":{\"format\":\"json\",\"weights\":\"equal\","
              "\"data\":[[0.5,0.5],[0.5,2]]}}");
    assert_int_equal(proto_decode_pattern(o, 0, &p, "pattern", &err), AA_EINVAL);
    assert_string_equal(err.field, "pattern.points.data[1]");
    assert_non_null(strstr(err.message, "outside the unit square"));
    json_decref(o);
    o = parse("{\"points\":{\"format\":\"csv\",\"weights\":\"equal\",\"data\":[[0.5,0.5]]}}");
    assert_int_equal(proto_decode_pattern(o, 0, &p, "pattern", &err), AA_EINVAL);
    assert_string_equal(err.field, "pattern.points.data");
    json_decref(o);
}

/* Point sets are in [0,1) of the whole tile; kernels relative to the output point in pixels;
 * tile.samples in [0,T) pixels; mirrored relative to the pixel centre. */
static void test_coordinate_conventions(void **state)
{
    (void)state;
    aa_pattern p, q;
    aa_error err = {0};
    /* points -> kernels: T = 1, K = 1: output point at the pixel centre (0.5, 0.5). */
    assert_int_equal(decode_points("xyw", "0.25 0.75 1\n", NULL, &p, &err), AA_OK);
    assert_int_equal(p.tile, 1);
    assert_true(p.kernels[0].samples[0].x == -0.25 && p.kernels[0].samples[0].y == 0.25);
    assert_true(p.tile_samples[0].x == 0.25 && p.tile_samples[0].y == 0.75);
    aa_pattern_free(&p);
    /* points -> tile.samples: scaled by T. */
    assert_int_equal(decode_points("utk", "0.1 0.2\n0.6 0.2\n0.1 0.7\n0.6 0.7\n",
                                   "{\"tile\":2,\"weights\":\"equal\"}", &p, &err),
                     AA_OK);
    assert_int_equal(p.tile, 2);
    assert_true(fabs(p.tile_samples[0].x - 0.2) < 1e-15 && fabs(p.tile_samples[0].y - 0.4) < 1e-15);
    json_t *enc = proto_encode_pattern(&p);
    const json_t *s0 = json_array_get(json_object_get(json_object_get(enc, "tile"), "samples"), 0);
    assert_true(fabs(json_real_value(json_array_get(s0, 0)) - 0.2) < 1e-15);
    json_decref(enc);
    /* tile.samples -> points: divided by T. */
    proto_pointset ps;
    assert_int_equal(proto_pointset_of_pattern(&p, &ps, &err), AA_OK);
    assert_true(fabs(ps.points[3].x - 0.6) < 1e-15 && fabs(ps.points[3].y - 0.7) < 1e-15);
    assert_true(ps.has_weights);
    assert_true(ps.points[0].w == 1.0);
    proto_pointset_free(&ps);
    aa_pattern_free(&p);
    /* Even K: the output point is the pixel's corner (1, 1) for pixel (0, 0). */
    assert_int_equal(
        decode_points("utk", "0.25 0.25\n", "{\"kernel\":2,\"weights\":\"equal\"}", &p, &err),
        AA_OK);
    assert_true(p.kernels[0].out_x == 1 && p.kernels[0].out_y == 1);
    assert_int_equal(p.kernels[0].count, 4); /* the sample and its copies in the 2x2 block */
    assert_true(p.kernels[0].samples[0].x == -0.75 && p.kernels[0].samples[0].y == -0.75);
    assert_true(p.kernels[0].samples[3].x == 0.25 && p.kernels[0].samples[3].y == 0.25);
    aa_pattern_free(&p);
    /* kernels (s = 1) -> points: +0.5; a mirrored pixel -> its 2x2 tile / 2. */
    json_t *kj = parse("{\"kernels\":[[[-0.25,0.125,0.5],[0.25,-0.125,0.5]]]}");
    assert_int_equal(proto_decode_pattern(kj, 0, &q, "", &err), AA_OK);
    assert_int_equal(proto_pointset_of_pattern(&q, &ps, &err), AA_OK);
    assert_true(ps.points[0].x == 0.25 && ps.points[0].y == 0.625);
    assert_true(ps.points[0].w == 0.5);
    proto_pointset_free(&ps);
    aa_pattern_free(&q);
    json_decref(kj);
    json_t *mj = parse("{\"mirrored\":[[-0.25,-0.25,1]]}");
    assert_int_equal(proto_decode_pattern(mj, 0, &q, "", &err), AA_OK);
    assert_int_equal(proto_pointset_of_pattern(&q, &ps, &err), AA_OK);
    assert_int_equal(ps.count, 4);
    /* Pixel (1,0) mirrors x: centre 1.5 + 0.25 = 1.75 -> 0.875 of the tile. */
    bool found = false;
    for (size_t i = 0; i < ps.count; i++)
        found = found || (ps.points[i].x == 0.875 && ps.points[i].y == 0.125);
    assert_true(found);
    proto_pointset_free(&ps);
    /* Vulkan: [0,1) within the pixel; D3D12: 1/16 pixel from the pixel centre. */
    json_t *vk = proto_export_gpu(&q, false), *dx = proto_export_gpu(&q, true);
    assert_true(json_is_true(json_object_get(vk, "representable")));
    const json_t *l1 = json_array_get(json_object_get(vk, "pSampleLocations"), 1);
    assert_true(json_real_value(json_object_get(l1, "x")) == 0.75);
    assert_true(json_real_value(json_object_get(l1, "y")) == 0.25);
    const json_t *d1 = json_array_get(json_object_get(dx, "SamplePositions"), 1);
    assert_int_equal(json_integer_value(json_object_get(d1, "X")), 4);
    assert_int_equal(json_integer_value(json_object_get(d1, "Y")), -4);
    json_decref(vk);
    json_decref(dx);
    aa_pattern_free(&q);
    json_decref(mj);
}

static const proto_points_format formats[] = {PROTO_POINTS_UTK, PROTO_POINTS_XYW, PROTO_POINTS_CSV,
                                              PROTO_POINTS_JSON};

/* Export p in every format, import it back; returns the worst |E2 difference|. */
static double round_trip(const aa_pattern *p, const char *what)
{
    double want = e2_of(p), worst = 0;
    for (size_t f = 0; f < 4; f++) {
        size_t len;
        aa_error err = {0};
        char *text = proto_export_points(p, formats[f], &len, &err);
        assert_non_null(text);
        assert_int_equal(strlen(text), len);
        aa_pattern q;
        int rc = decode_points(proto_points_format_name(formats[f]), text, NULL, &q, &err);
        if (rc)
            fail_msg("%s as %s: %s: %s", what, proto_points_format_name(formats[f]), err.field,
                     err.message);
        assert_string_equal(q.family, p->family);
        double d = fabs(e2_of(&q) - want);
        if (!(d <= ROUND_TRIP_TOLERANCE))
            fail_msg("%s as %s: E2 %.17g back as %.17g", what, proto_points_format_name(formats[f]),
                     want, e2_of(&q));
        worst = fmax(worst, d);
        /* The writer is the one the client uses: the same bytes again from the import. */
        size_t len2;
        char *again = proto_export_points(&q, formats[f], &len2, &err);
        assert_non_null(again);
        free(again);
        aa_pattern_free(&q);
        free(text);
    }
    return worst;
}

static void test_round_trip_presets(void **state)
{
    (void)state;
    double worst = 0;
    for (size_t i = 0; i < aa_preset_count(); i++) {
        aa_pattern p;
        aa_error err = {0};
        assert_int_equal(aa_pattern_from_preset(&p, aa_preset_at(i), &err), AA_OK);
        worst = fmax(worst, round_trip(&p, aa_preset_at(i)->name));
        aa_pattern_free(&p);
    }
    printf("round trip: %zu presets x 4 formats, worst |dE2| = %.3g\n", aa_preset_count(), worst);
}

/* Seeds of the families the optimizer starts from: the forms its best patterns have. */
static void test_round_trip_families(void **state)
{
    (void)state;
    static const char *const families[] = {"P(4,1+,2)",  "P(16,16,4)", "P(4,4,2)", "P(1,1,3)",
                                           "P(16,4+,2)", "P(9,1,2)",   "P(9,4,3)"};
    aa_filter f;
    aa_filter_default(&f);
    double worst = 0;
    for (size_t i = 0; i < sizeof families / sizeof *families; i++) {
        aa_family fam;
        aa_error err = {0};
        assert_int_equal(aa_family_parse(families[i], &fam, &err), AA_OK);
        for (uint64_t seed = 1; seed <= 3; seed++) {
            aa_rng rng;
            aa_rng_seed(&rng, seed, 0);
            aa_pattern p;
            assert_int_equal(aa_family_seed(&fam, AA_SEED_JITTERED, &f, &rng, &p, &err), AA_OK);
            worst = fmax(worst, round_trip(&p, families[i]));
            aa_pattern_free(&p);
        }
    }
    printf("round trip: family seeds x 4 formats, worst |dE2| = %.3g\n", worst);
}

/* Without the header the user's options decide: a kernel-1 tile read back from its x y w text
 * with weights from the file is the same pattern. */
static void test_without_header(void **state)
{
    (void)state;
    aa_filter f;
    aa_filter_default(&f);
    aa_family fam;
    aa_error err = {0};
    assert_int_equal(aa_family_parse("P(4,1,2)", &fam, &err), AA_OK);
    aa_rng rng;
    aa_rng_seed(&rng, 7, 0);
    aa_pattern p, q;
    assert_int_equal(aa_family_seed(&fam, AA_SEED_NROOKS, &f, &rng, &p, &err), AA_OK);
    size_t len;
    char *text = proto_export_points(&p, PROTO_POINTS_XYW, &len, &err);
    assert_non_null(text);
    const char *body = strchr(text, '\n') + 1; /* drop the header line */
    if (decode_points("xyw", body, "{\"tile\":2}", &q, &err))
        fail_msg("%s: %s\n%s", err.field, err.message, body);
    assert_true(fabs(e2_of(&q) - e2_of(&p)) <= ROUND_TRIP_TOLERANCE);
    aa_pattern_free(&q);
    /* Weights from the filter: the tile form without weights, the same E2 exactly. */
    assert_int_equal(decode_points("xyw", body, "{\"tile\":2,\"weights\":\"filter\"}", &q, &err),
                     AA_OK);
    json_t *enc = proto_encode_pattern(&q);
    json_t *tile = json_object_get(enc, "tile");
    json_object_del(tile, "weights");
    aa_pattern r;
    assert_int_equal(proto_decode_pattern(enc, 0, &r, "", &err), AA_OK);
    assert_true(e2_of(&q) == e2_of(&r));
    json_decref(enc);
    aa_pattern_free(&r);
    aa_pattern_free(&q);
    /* Equal weights: 1/n in every kernel. */
    assert_int_equal(decode_points("xyw", body, "{\"tile\":2,\"weights\":\"equal\"}", &q, &err),
                     AA_OK);
    for (size_t k = 0; k < q.kernel_count; k++)
        for (size_t m = 0; m < q.kernels[k].count; m++)
            assert_true(q.kernels[k].samples[m].w == 1.0 / (double)q.kernels[k].count);
    aa_pattern_free(&q);
    /* With the header, weights "equal" replace the header's and keep its tile. */
    assert_int_equal(decode_points("xyw", text, "{\"weights\":\"equal\"}", &q, &err), AA_OK);
    assert_int_equal(q.tile, 2);
    assert_true(q.kernels[0].samples[0].w == 1.0 / (double)q.kernels[0].count);
    aa_pattern_free(&q);
    free(text);
    aa_pattern_free(&p);
}

/* The export format names the daemon and the client accept. */
static void test_export_formats(void **state)
{
    (void)state;
    proto_export_writer k;
    proto_points_format f = PROTO_POINTS_UTK;
    assert_true(proto_export_format_parse("json", &k, &f) && k == PROTO_EXPORT_PATTERN);
    assert_true(proto_export_format_parse("points-json", &k, &f) && k == PROTO_EXPORT_POINTS &&
                f == PROTO_POINTS_JSON);
    assert_true(proto_export_format_parse("csv", &k, &f) && k == PROTO_EXPORT_POINTS &&
                f == PROTO_POINTS_CSV);
    assert_true(proto_export_format_parse("d3d12", &k, &f) && k == PROTO_EXPORT_D3D12);
    assert_false(proto_export_format_parse("png", &k, &f));
    assert_false(proto_export_format_parse(NULL, &k, &f));
    /* CSV and UTK text of a known pattern, byte for byte. */
    aa_pattern p;
    aa_error err = {0};
    json_t *j = parse("{\"kernels\":[[[-0.25,-0.25,0.5],[0.25,0.25,0.5]]]}");
    assert_int_equal(proto_decode_pattern(j, 0, &p, "", &err), AA_OK);
    size_t len;
    char *csv = proto_export_points(&p, PROTO_POINTS_CSV, &len, &err);
    const char *nl = strchr(csv, '\n');
    assert_true(!strncmp(csv, "# aalab-pattern {\"version\":1,\"family\":\"P(1,1,2)\"", 48));
    assert_string_equal(nl + 1, "x,y,w\n0.25,0.25,0.5\n0.75,0.75,0.5\n");
    char *utk = proto_export_points(&p, PROTO_POINTS_UTK, &len, &err);
    assert_string_equal(strchr(utk, '\n') + 1, "0.25 0.25\n0.75 0.75\n");
    free(csv);
    free(utk);
    aa_pattern_free(&p);
    json_decref(j);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_formats),      cmocka_unit_test(test_parse_errors),
        cmocka_unit_test(test_points_form_errors), cmocka_unit_test(test_coordinate_conventions),
        cmocka_unit_test(test_round_trip_presets), cmocka_unit_test(test_round_trip_families),
        cmocka_unit_test(test_without_header),     cmocka_unit_test(test_export_formats),
        cmocka_unit_test(test_error_text_is_utf8),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
