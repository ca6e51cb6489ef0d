/* proto/pointset: the sampling tools' formats (issue 31): UTK's binary .bin, PSA's raw float32
 * .rps (both base64 in the "points" form), several '#'-separated sets in one text file, and
 * Metal's MTLSamplePosition export. Round trips keep E2 to 1e-12 for every preset and family
 * seeds (rps: patterns whose points are float32 numbers, the format's precision). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
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

/* {"points":{"format":fmt, key: content, extra...}} decoded. */
static int decode_form(const char *fmt, const char *key, const char *content,
                       const char *extra_json, aa_pattern *p, aa_error *err)
{
    json_t *o = json_pack("{s:{s:s,s:s}}", "points", "format", fmt, key, content);
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

/* Bytes as the points form's base64. */
static int decode_bytes(const char *fmt, const void *b, size_t n, const char *extra, aa_pattern *p,
                        aa_error *err)
{
    char *s = proto_base64_encode(b, n);
    assert_non_null(s);
    int rc = decode_form(fmt, "base64", s, extra, p, err);
    free(s);
    return rc;
}

static void expect_bytes_error(const char *fmt, const void *b, size_t n, const char *extra,
                               const char *field, const char *part)
{
    aa_pattern p;
    aa_error err = {0};
    if (decode_bytes(fmt, b, n, extra, &p, &err) == AA_OK)
        fail_msg("decoded %zu bytes of %s", n, fmt);
    assert_string_equal(err.field, field);
    if (!strstr(err.message, part))
        fail_msg("message '%s' lacks '%s'", err.message, part);
}

static void put32(unsigned char *b, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        b[i] = (unsigned char)(v >> (8 * i));
}

static void put64f(unsigned char *b, double d)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    put32(b, (uint32_t)u);
    put32(b + 4, (uint32_t)(u >> 32));
}

static void put32f(unsigned char *b, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put32(b, u);
}

/* A UTK header: magic, dtype, m, N, d. */
static void utk_header(unsigned char *b, unsigned dtype, uint32_t m, uint32_t n, uint32_t d)
{
    memset(b, 0, 20);
    put32(b, 0x214B5455u);
    b[4] = (unsigned char)dtype;
    put32(b + 8, m);
    put32(b + 12, n);
    put32(b + 16, d);
}

static void test_base64(void **state)
{
    (void)state;
    const char *plain[] = {"", "f", "fo", "foo", "foob", "fooba", "foobar"};
    const char *enc[] = {"", "Zg==", "Zm8=", "Zm9v", "Zm9vYg==", "Zm9vYmE=", "Zm9vYmFy"};
    for (int i = 0; i < 7; i++) { /* RFC 4648's test vectors */
        char *e = proto_base64_encode((const unsigned char *)plain[i], strlen(plain[i]));
        assert_string_equal(e, enc[i]);
        free(e);
        size_t n, bad;
        unsigned char *d = proto_base64_decode(enc[i], strlen(enc[i]), &n, &bad);
        assert_non_null(d);
        assert_int_equal(n, strlen(plain[i]));
        assert_memory_equal(d, plain[i], n);
        free(d);
    }
    size_t n, bad = 0;
    assert_null(proto_base64_decode("Zm9", 3, &n, &bad));
    assert_int_equal(bad, 3);
    assert_null(proto_base64_decode("Zm=v", 4, &n, &bad));
    assert_int_equal(bad, 2);
    assert_null(proto_base64_decode("Zm9v\nZm9v", 9, &n, &bad));
    assert_null(proto_base64_decode("Zg==Zg==", 8, &n, &bad));
}

/* UTK .bin as UTK writes it (float and double, one and two sets) reads back its points. */
static void test_bin_read(void **state)
{
    (void)state;
    unsigned char b[20 + 2 * 3 * 2 * 8];
    double xy[2][3][2] = {{{0.125, 0.25}, {0.5, 0.75}, {0.875, 0.0625}},
                          {{0.1, 0.2}, {0.3, 0.4}, {0.6, 0.9}}};
    utk_header(b, 5, 2, 3, 2);
    for (int s = 0; s < 2; s++)
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 2; k++)
                put64f(b + 20 + ((s * 3 + i) * 2 + k) * 8, xy[s][i][k]);
    proto_pointset ps;
    aa_error err = {0};
    size_t sets = 0;
    assert_int_equal(
        proto_pointset_parse_binary(b, sizeof b, PROTO_POINTS_BIN, 1, &ps, &sets, "f", "s", &err),
        AA_OK);
    assert_int_equal(sets, 2);
    assert_int_equal(ps.count, 3);
    assert_true(ps.points[2].x == 0.6 && ps.points[2].y == 0.9 && !ps.has_weights);
    proto_pointset_free(&ps);
    /* Two sets without a set number: which one? */
    assert_int_equal(proto_pointset_parse_binary(b, sizeof b, PROTO_POINTS_BIN, PROTO_POINTS_WHOLE,
                                                 &ps, NULL, "f", "s", &err),
                     AA_EINVAL);
    assert_string_equal(err.field, "s");
    assert_non_null(strstr(err.message, "2 sets"));
    /* float32, one set */
    unsigned char f[20 + 3 * 2 * 4];
    utk_header(f, 4, 1, 3, 2);
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 2; k++)
            put32f(f + 20 + (i * 2 + k) * 4, (float)xy[0][i][k]);
    aa_pattern p;
    assert_int_equal(decode_bytes("bin", f, sizeof f, "{\"weights\":\"equal\"}", &p, &err), AA_OK);
    assert_int_equal(p.tile_count, 3);
    assert_true(p.tile_samples[1].x == 0.5 && p.tile_samples[1].y == 0.75);
    aa_pattern_free(&p);
    /* the set count over the wire form's helper */
    size_t count;
    assert_int_equal(
        proto_pointset_count_sets((const char *)b, sizeof b, PROTO_POINTS_BIN, &count, "f", &err),
        AA_OK);
    assert_int_equal(count, 2);
}

static void test_bin_errors(void **state)
{
    (void)state;
    const char *F = "pattern.points.base64";
    unsigned char b[20 + 4097 * 16 + 8];
    memset(b, 0, sizeof b);
    utk_header(b, 5, 1, 2, 2);
    put64f(b + 20, 0.5);
    put64f(b + 28, 0.5);
    put64f(b + 36, 0.25);
    put64f(b + 44, 0.25);
    aa_pattern p;
    aa_error err = {0};
    assert_int_equal(decode_bytes("bin", b, 52, "{\"weights\":\"equal\"}", &p, &err), AA_OK);
    aa_pattern_free(&p);
    expect_bytes_error("bin", b, 19, NULL, F, "truncated: 19 bytes");
    expect_bytes_error("bin", b, 51, NULL, F, "truncated: the header says m = 1 sets of N = 2");
    expect_bytes_error("bin", b, 53, NULL, F, "count mismatch");
    b[0] = 'X';
    expect_bytes_error("bin", b, 52, NULL, F, "magic is 0x214B5458");
    b[0] = 0x55;
    b[4] = 0;
    expect_bytes_error("bin", b, 52, NULL, F, "dtype is 0 (int32)");
    b[4] = 5;
    put32(b + 16, 3);
    expect_bytes_error("bin", b, 52, NULL, F, "dimension d is 3");
    put32(b + 16, 2);
    put64f(b + 44, NAN);
    expect_bytes_error("bin", b, 52, NULL, F, "point 1: y is not a finite number");
    put64f(b + 44, 0.25);
    put32(b + 12, 4097);
    expect_bytes_error("bin", b, 20 + 4097 * 16, NULL, F, "N is 4097");
    put32(b + 12, 2);
    expect_bytes_error("bin", b, 52, "{\"set\":1}", "pattern.points.set", "holds 1 set");
    expect_bytes_error("bin", b, 52, "{\"weights\":\"file\"}", "pattern.points.weights",
                       "no weights");
    /* not base64; bytes given as text */
    assert_int_equal(decode_form("bin", "base64", "AAA*", NULL, &p, &err), AA_EINVAL);
    assert_string_equal(err.field, F);
    assert_non_null(strstr(err.message, "character 3"));
    assert_int_equal(decode_form("rps", "text", "0.5 0.5", NULL, &p, &err), AA_EINVAL);
    assert_string_equal(err.field, "pattern.points.text");
    assert_int_equal(decode_form("utk", "set", "x", NULL, &p, &err), AA_EINVAL);
}

static void test_rps_errors(void **state)
{
    (void)state;
    const char *F = "pattern.points.base64";
    static unsigned char b[4097 * 8];
    for (int i = 0; i < 4097 * 2; i++)
        put32f(b + 4 * i, (float)((i * 37 % 4096) + 0.5) / 4096.0f);
    aa_pattern p;
    aa_error err = {0};
    assert_int_equal(decode_bytes("rps", b, 16, "{\"weights\":\"equal\"}", &p, &err), AA_OK);
    assert_int_equal(p.tile_count, 2);
    aa_pattern_free(&p);
    expect_bytes_error("rps", b, 12, NULL, F, "12 bytes is not a whole number of points");
    expect_bytes_error("rps", b, 0, NULL, F, "no points");
    expect_bytes_error("rps", b, sizeof b, NULL, F, "4097 points, more than 4096");
    put32f(b + 4, NAN);
    expect_bytes_error("rps", b, 16, NULL, F, "point 0: y is not a finite number");
    expect_bytes_error("rps", b, 16, "{\"set\":1}", "pattern.points.set", "one set");
}

/* Export p as bin, import it back through the points form: the same E2 (the header trailer). */
static double bin_round_trip(const aa_pattern *p, const char *what)
{
    size_t len;
    aa_error err = {0};
    char *b = proto_export_points(p, PROTO_POINTS_BIN, &len, &err);
    assert_non_null(b);
    aa_pattern q;
    if (decode_bytes("bin", b, len, NULL, &q, &err))
        fail_msg("%s as bin: %s: %s", what, err.field, err.message);
    double d = fabs(e2_of(&q) - e2_of(p));
    if (!(d <= ROUND_TRIP_TOLERANCE))
        fail_msg("%s as bin: E2 %.17g back as %.17g", what, e2_of(p), e2_of(&q));
    assert_string_equal(q.family, p->family);
    /* UTK's reader stops after m N d values: the trailer is after them. */
    size_t n = p->tile > 0 ? p->tile_count : p->kernels[0].count;
    assert_true(len > 20 + 16 * n);
    assert_memory_equal(b + 20 + 16 * n, "# aalab-pattern {", 17);
    assert_true(b[len - 1] == '\n');
    aa_pattern_free(&q);
    free(b);
    return d;
}

/* p's points rounded to float32, its tile, kernel and border, weights from the filter. */
static int float32_pattern(const aa_pattern *p, aa_pattern *out)
{
    proto_pointset ps;
    aa_error err = {0};
    assert_int_equal(proto_pointset_of_pattern(p, &ps, &err), AA_OK);
    json_decref(ps.header);
    ps.header = NULL;
    /* Through a volatile float: GCC 12.2 at -O2/-O3 (SLP vectoriser) drops (double)(float)x in
     * such a loop's tail, leaving the last points unrounded (-fno-tree-slp-vectorize fixes it). */
    for (size_t i = 0; i < ps.count; i++) {
        volatile float fx = (float)ps.points[i].x, fy = (float)ps.points[i].y;
        ps.points[i].x = fx;
        ps.points[i].y = fy;
    }
    proto_points_options o = proto_points_options_default();
    o.tile = p->tile;
    o.kernel = p->kernel_size;
    o.border = p->border;
    o.weights = PROTO_WEIGHTS_FILTER;
    int rc = proto_pattern_from_pointset(&ps, &o, out, "o", "p", &err);
    proto_pointset_free(&ps);
    return rc;
}

/* rps: float32 and no header, so the reader states tile, kernel, border and weights. */
static double rps_round_trip(const aa_pattern *p32, const char *what)
{
    size_t len;
    aa_error err = {0};
    char *b = proto_export_points(p32, PROTO_POINTS_RPS, &len, &err);
    assert_non_null(b);
    assert_int_equal(len, 8 * p32->tile_count);
    char extra[128];
    snprintf(extra, sizeof extra,
             "{\"tile\":%d,\"kernel\":%d,\"border\":%s,\"weights\":\"filter\"}", p32->tile,
             p32->kernel_size, p32->border ? "true" : "false");
    aa_pattern q;
    if (decode_bytes("rps", b, len, extra, &q, &err))
        fail_msg("%s as rps: %s: %s", what, err.field, err.message);
    double d = fabs(e2_of(&q) - e2_of(p32));
    if (!(d <= ROUND_TRIP_TOLERANCE))
        fail_msg("%s as rps: E2 %.17g back as %.17g", what, e2_of(p32), e2_of(&q));
    aa_pattern_free(&q);
    free(b);
    return d;
}

static void test_round_trips(void **state)
{
    (void)state;
    double worst_bin = 0, worst_rps = 0, worst_float = 0;
    size_t rps_count = 0;
    for (size_t i = 0; i < aa_preset_count(); i++) {
        aa_pattern p, p32;
        aa_error err = {0};
        assert_int_equal(aa_pattern_from_preset(&p, aa_preset_at(i), &err), AA_OK);
        worst_bin = fmax(worst_bin, bin_round_trip(&p, aa_preset_at(i)->name));
        if (p.tile > 0 && p.kernel_size >= 1 && float32_pattern(&p, &p32) == AA_OK) {
            worst_rps = fmax(worst_rps, rps_round_trip(&p32, aa_preset_at(i)->name));
            rps_count++;
            aa_pattern_free(&p32);
        }
        aa_pattern_free(&p);
    }
    static const char *const families[] = {"P(4,1+,2)", "P(16,16,4)", "P(4,4,2)", "P(1,1,3)",
                                           "P(9,4,3)"};
    aa_filter f;
    aa_filter_default(&f);
    for (size_t i = 0; i < sizeof families / sizeof *families; i++) {
        aa_family fam;
        aa_error err = {0};
        assert_int_equal(aa_family_parse(families[i], &fam, &err), AA_OK);
        for (uint64_t seed = 1; seed <= 3; seed++) {
            aa_rng rng;
            aa_rng_seed(&rng, seed, 0);
            aa_pattern p, p32;
            assert_int_equal(aa_family_seed(&fam, AA_SEED_JITTERED, &f, &rng, &p, &err), AA_OK);
            worst_bin = fmax(worst_bin, bin_round_trip(&p, families[i]));
            if (p.tile > 0 && p.kernel_size >= 1 && float32_pattern(&p, &p32) == AA_OK) {
                worst_rps = fmax(worst_rps, rps_round_trip(&p32, families[i]));
                rps_count++;
                aa_pattern_free(&p32);
            }
            aa_pattern_free(&p);
        }
    }
    assert_true(rps_count >= 10);
    (void)worst_float;
    printf("round trip: bin worst |dE2| = %.3g (presets and seeds); rps worst |dE2| = %.3g over "
           "%zu float32 patterns\n",
           worst_bin, worst_rps, rps_count);
}

/* Several sets in one text file: UTK's convention, and concatenated aalab exports. */
static void test_text_sets(void **state)
{
    (void)state;
    const char *text = "# made by a sampler\n0.1 0.2\n0.3 0.4\n#\n\n0.5 0.5\n0.25 0.75\n"
                       "# set 2\n# more\n0.9 0.9\nbad\n#\n";
    proto_pointset ps;
    aa_error err = {0};
    size_t count = 0;
    assert_int_equal(proto_pointset_parse_set(text, strlen(text), PROTO_POINTS_UTK, 1, &ps, &count,
                                              "f", "s", &err),
                     AA_OK);
    assert_int_equal(count, 3);
    assert_int_equal(ps.count, 2);
    assert_true(ps.points[1].x == 0.25 && ps.where[1] == 7);
    proto_pointset_free(&ps);
    /* an error in set 2 names its line in the whole file */
    assert_int_equal(proto_pointset_parse_set(text, strlen(text), PROTO_POINTS_UTK, 2, &ps, NULL,
                                              "f", "s", &err),
                     AA_EINVAL);
    assert_string_equal(err.field, "f");
    assert_non_null(strstr(err.message, "line 11: 'bad' is not a number"));
    assert_int_equal(proto_pointset_parse_set(text, strlen(text), PROTO_POINTS_UTK, 3, &ps, NULL,
                                              "f", "s", &err),
                     AA_ERANGE);
    assert_string_equal(err.field, "s");
    assert_non_null(strstr(err.message, "holds 3 sets"));
    assert_int_equal(
        proto_pointset_count_sets(text, strlen(text), PROTO_POINTS_XYW, &count, "f", &err), AA_OK);
    assert_int_equal(count, 3);
    assert_int_equal(
        proto_pointset_count_sets(text, strlen(text), PROTO_POINTS_CSV, &count, "f", &err), AA_OK);
    assert_int_equal(count, 1);
    assert_int_equal(proto_pointset_parse_set(text, strlen(text), PROTO_POINTS_CSV, 0, &ps, NULL,
                                              "f", "s", &err),
                     AA_EINVAL);
    assert_string_equal(err.field, "s");

    /* Concatenated exports of three presets: set i is preset i, to 1e-12, in utk and xyw. */
    const proto_points_format fmts[] = {PROTO_POINTS_UTK, PROTO_POINTS_XYW};
    double worst = 0;
    for (int f = 0; f < 2; f++) {
        aa_pattern p[3];
        char *cat = NULL;
        size_t total = 0;
        for (int i = 0; i < 3; i++) {
            aa_error e = {0};
            assert_int_equal(aa_pattern_from_preset(&p[i], aa_preset_at((size_t)i * 3), &e), AA_OK);
            size_t len;
            char *t = proto_export_points(&p[i], fmts[f], &len, &e);
            cat = realloc(cat, total + len + 1);
            memcpy(cat + total, t, len + 1);
            total += len;
            free(t);
        }
        for (int i = 0; i < 3; i++) {
            char extra[32];
            snprintf(extra, sizeof extra, "{\"set\":%d}", i);
            aa_pattern q;
            if (decode_form(proto_points_format_name(fmts[f]), "text", cat, extra, &q, &err))
                fail_msg("set %d: %s: %s", i, err.field, err.message);
            double d = fabs(e2_of(&q) - e2_of(&p[i]));
            assert_true(d <= ROUND_TRIP_TOLERANCE);
            worst = fmax(worst, d);
            aa_pattern_free(&q);
        }
        /* Without a set: the second header says why. */
        aa_pattern q;
        assert_int_equal(
            decode_form(proto_points_format_name(fmts[f]), "text", cat, NULL, &q, &err), AA_EINVAL);
        assert_string_equal(err.field, "pattern.points.text");
        assert_non_null(strstr(err.message, "choose one with set"));
        assert_int_equal(
            decode_form(proto_points_format_name(fmts[f]), "text", cat, "{\"set\":-1}", &q, &err),
            AA_EINVAL);
        assert_string_equal(err.field, "pattern.points.set");
        assert_int_equal(decode_form(proto_points_format_name(fmts[f]), "text", cat,
                                     "{\"set\":\"all\"}", &q, &err),
                         AA_EINVAL);
        assert_string_equal(err.field, "pattern.points.set");
        assert_non_null(strstr(err.message, "/v1/analyze"));
        for (int i = 0; i < 3; i++)
            aa_pattern_free(&p[i]);
        free(cat);
    }
    printf("sets: 3 concatenated exports x utk, xyw, worst |dE2| = %.3g\n", worst);
}

static json_t *metal_of(const char *pattern_json)
{
    aa_pattern p;
    aa_error err = {0};
    json_t *j = parse(pattern_json);
    if (proto_decode_pattern(j, 0, &p, "", &err))
        fail_msg("%s: %s", err.field, err.message);
    json_decref(j);
    json_t *m = proto_export_metal(&p);
    aa_pattern_free(&p);
    return m;
}

static void test_metal_export(void **state)
{
    (void)state;
    proto_export_writer k;
    proto_points_format f = PROTO_POINTS_UTK;
    assert_true(proto_export_format_parse("metal", &k, &f) && k == PROTO_EXPORT_METAL);
    assert_true(proto_export_format_parse("bin", &k, &f) && k == PROTO_EXPORT_POINTS &&
                f == PROTO_POINTS_BIN);
    assert_true(proto_export_format_parse("rps", &k, &f) && f == PROTO_POINTS_RPS);
    /* 4 samples of one pixel on the 1/16 grid: kernel offsets from the centre + 0.5. */
    json_t *m = metal_of("{\"kernels\":[[[-0.375,-0.125,0.25],[0.125,-0.375,0.25],"
                         "[0.375,0.125,0.25],[-0.125,0.4375,0.25]]]}");
    assert_true(json_is_true(json_object_get(m, "representable")));
    assert_string_equal(json_string_value(json_object_get(m, "api")), "metal");
    assert_int_equal(json_integer_value(json_object_get(m, "sampleCount")), 4);
    json_t *pos = json_object_get(m, "samplePositions");
    assert_int_equal(json_array_size(pos), 4);
    double sx = 0, sy = 0;
    for (size_t i = 0; i < 4; i++) {
        double x = json_real_value(json_object_get(json_array_get(pos, i), "x"));
        double y = json_real_value(json_object_get(json_array_get(pos, i), "y"));
        assert_true(x >= 0 && x <= 15.0 / 16 && x * 16 == floor(x * 16));
        assert_true(y >= 0 && y <= 15.0 / 16 && y * 16 == floor(y * 16));
        sx += x;
        sy += y;
    }
    assert_true(sx == 0.125 + 0.625 + 0.875 + 0.375 && sy == 0.375 + 0.125 + 0.625 + 0.9375);
    json_decref(m);
    /* off the grid; three samples; a 2x2 tile */
    m = metal_of("{\"kernels\":[[[-0.3,-0.1,0.5],[0.1,0.3,0.5]]]}");
    assert_true(json_is_false(json_object_get(m, "representable")));
    assert_non_null(strstr(json_string_value(json_object_get(m, "reason")), "1/16"));
    json_decref(m);
    m = metal_of("{\"kernels\":[[[-0.25,-0.25,0.3],[0.25,0.25,0.3],[0,0,0.4]]]}");
    assert_true(json_is_false(json_object_get(m, "representable")));
    json_decref(m);
    /* The D3D/Vulkan standard positions are on the same 1/16 grid; 16 samples are not Metal's. */
    m = metal_of("{\"preset\":\"d3d-8x\"}");
    assert_true(json_is_true(json_object_get(m, "representable")));
    assert_int_equal(json_integer_value(json_object_get(m, "sampleCount")), 8);
    json_decref(m);
    m = metal_of("{\"preset\":\"d3d-16x\"}");
    assert_true(json_is_false(json_object_get(m, "representable")));
    json_decref(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_base64),       cmocka_unit_test(test_bin_read),
        cmocka_unit_test(test_bin_errors),   cmocka_unit_test(test_rps_errors),
        cmocka_unit_test(test_round_trips),  cmocka_unit_test(test_text_sets),
        cmocka_unit_test(test_metal_export),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
