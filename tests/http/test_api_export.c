/* handlers_export.c via api_handle: GET /v1/patterns/{job}/export and POST /v1/patterns/export in
 * every format, answered with the codec's writer (the bytes the client writes), and their errors.
 */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "api.h"
#include "api_fixture.h"
#include "codec.h"
#include "pointset.h"

typedef api_fixture fixture;

static void configure(aalab_config *cfg)
{
    cfg->workers = 1;
    cfg->test_kinds = true;
}

static int setup(void **state)
{
    *state = api_fixture_open("api-export", configure);
    return 0;
}

static int teardown(void **state)
{
    return api_fixture_close(*state);
}

/* The preset's text as the codec writes it. */
static char *codec_text(const char *preset, proto_points_format fmt, size_t *len)
{
    aa_pattern p;
    aa_error err = {0};
    assert_int_equal(aa_pattern_from_preset(&p, aa_preset_find(preset), &err), AA_OK);
    char *text = proto_export_points(&p, fmt, len, &err);
    assert_non_null(text);
    aa_pattern_free(&p);
    return text;
}

static void expect_error(fixture *f, const char *method, const char *path, const char *body,
                         int status, const char *field)
{
    int st;
    json_t *j = api_call(f, method, path, body, 1000, &st);
    assert_int_equal(st, status);
    json_t *e = json_object_get(j, "error");
    assert_non_null(e);
    if (field)
        assert_string_equal(json_string_value(json_object_get(e, "field")), field);
    json_decref(j);
}

static void test_post_formats(void **state)
{
    fixture *f = *state;
    static const struct {
        const char *name;
        proto_points_format fmt;
        const char *type;
    } text_formats[] = {{"utk", PROTO_POINTS_UTK, "text/plain"},
                        {"xyw", PROTO_POINTS_XYW, "text/plain"},
                        {"csv", PROTO_POINTS_CSV, "text/plain"},
                        {"points-json", PROTO_POINTS_JSON, "application/json"}};
    for (size_t i = 0; i < 4; i++) {
        char body[128];
        snprintf(body, sizeof body, "{\"pattern\":{\"preset\":\"flipquad\"},\"format\":\"%s\"}",
                 text_formats[i].name);
        api_response r;
        api_request_raw(f, "POST", "/v1/patterns/export", body, 1000, &r);
        assert_int_equal(r.status, 200);
        assert_true(!strncmp(r.content_type, text_formats[i].type, strlen(text_formats[i].type)));
        size_t len;
        char *want = codec_text("flipquad", text_formats[i].fmt, &len);
        assert_int_equal(r.body_len, len);
        assert_memory_equal(r.body, want, len);
        free(want);
        api_response_free(&r);
    }
    int st;
    json_t *j = api_call(f, "POST", "/v1/patterns/export",
                         "{\"pattern\":{\"preset\":\"rgss\"},\"format\":\"json\"}", 1000, &st);
    assert_int_equal(st, 200);
    assert_null(json_object_get(j, "job"));
    assert_string_equal(json_string_value(json_object_get(json_object_get(j, "pattern"), "family")),
                        "P(1,1,4)");
    json_decref(j);
    j = api_call(f, "POST", "/v1/patterns/export",
                 "{\"pattern\":{\"preset\":\"rgss\"},\"format\":\"d3d12\"}", 1000, &st);
    assert_int_equal(st, 200);
    assert_true(json_is_true(json_object_get(j, "representable")));
    assert_int_equal(json_integer_value(json_object_get(j, "NumSamplesPerPixel")), 4);
    json_decref(j);
    /* A points pattern with filter weights takes the request's filter. */
    const char *pts = "{\"points\":{\"format\":\"utk\",\"text\":\"0.2 0.3\\n0.7 0.6\\n\","
                      "\"weights\":\"filter\"}}";
    char body[256];
    snprintf(body, sizeof body, "{\"pattern\":%s,\"format\":\"json\"}", pts);
    json_t *a = api_call(f, "POST", "/v1/patterns/export", body, 1000, &st);
    assert_int_equal(st, 200);
    snprintf(body, sizeof body,
             "{\"pattern\":%s,\"format\":\"json\",\"filter\":{\"name\":\"box\"}}", pts);
    json_t *b = api_call(f, "POST", "/v1/patterns/export", body, 1000, &st);
    assert_int_equal(st, 200);
    const json_t *wa = json_object_get(json_object_get(json_object_get(a, "pattern"), "tile"),
                                       "weights"),
                 *wb = json_object_get(json_object_get(json_object_get(b, "pattern"), "tile"),
                                       "weights");
    assert_false(json_equal(wa, wb));
    json_decref(a);
    json_decref(b);
}

static void test_post_errors(void **state)
{
    fixture *f = *state;
    const char *P = "/v1/patterns/export";
    expect_error(f, "POST", P, "{\"pattern\":{\"preset\":\"rgss\"}}", 400, "format");
    expect_error(f, "POST", P, "{\"pattern\":{\"preset\":\"rgss\"},\"format\":\"png\"}", 400,
                 "format");
    expect_error(f, "POST", P, "{\"format\":\"csv\"}", 400, "pattern");
    expect_error(f, "POST", P, "{\"pattern\":{\"preset\":\"rgss\"},\"format\":\"csv\",\"x\":1}",
                 400, "x");
    expect_error(f, "POST", P, "{\"pattern\":{\"preset\":\"nope\"},\"format\":\"csv\"}", 400,
                 "pattern.preset");
    expect_error(f, "POST", P,
                 "{\"pattern\":{\"points\":{\"format\":\"xyw\",\"text\":\"0.5 0.5\\n0.1\\n\"}},"
                 "\"format\":\"csv\"}",
                 400, "pattern.points.text");
    expect_error(f, "POST", P, "{\"pattern\":{\"job\":424242},\"format\":\"csv\"}", 400,
                 "pattern.job");
    expect_error(f, "GET", P, NULL, 405, "");
    /* An export decodes and writes up to --max-body: the compute pool's work, not an HTTP
     * thread's. */
    assert_int_equal(api_classify("POST", "/v1/patterns/export", 0), API_CLASS_EVALUATE);
    assert_int_equal(api_classify("GET", "/v1/patterns/3/export", 0), API_CLASS_OTHER);
    /* The route table's compute column, for every class. */
    assert_int_equal(api_classify("POST", "/v1/evaluate", 0), API_CLASS_EVALUATE);
    assert_int_equal(api_classify("POST", "/v1/analyze", 0), API_CLASS_EVALUATE);
    assert_int_equal(api_classify("POST", "/v1/predict", 0), API_CLASS_PREDICT);
    assert_int_equal(api_classify("POST", "/v1/render", 0), API_CLASS_RENDER);
    assert_int_equal(api_classify("POST", "/v1/jobs", 0), API_CLASS_OTHER);
    assert_int_equal(api_classify("POST", "/v1/jobs", API_SPEC_INLINE_BYTES), API_CLASS_OTHER);
    assert_int_equal(api_classify("POST", "/v1/jobs", API_SPEC_INLINE_BYTES + 1),
                     API_CLASS_PREDICT);
    assert_int_equal(api_classify("GET", "/v1/jobs", API_SPEC_INLINE_BYTES + 1), API_CLASS_OTHER);
    assert_int_equal(api_classify("GET", "/v1/evaluate", 0), API_CLASS_OTHER);
    assert_int_equal(api_classify("POST", "/v1/evaluate/x", 0), API_CLASS_OTHER);
    assert_int_equal(api_classify(NULL, "/v1/evaluate", 0), API_CLASS_OTHER);
}

static json_t *wait_done(fixture *f, long long id)
{
    char path[64];
    snprintf(path, sizeof path, "/v1/jobs/%lld", id);
    for (int i = 0; i < 500; i++) {
        int st;
        json_t *j = api_call(f, "GET", path, NULL, 1000, &st);
        assert_int_equal(st, 200);
        if (!strcmp(json_string_value(json_object_get(j, "state")), "done"))
            return j;
        json_decref(j);
        struct timespec d = {0, 10 * 1000 * 1000};
        nanosleep(&d, NULL);
    }
    fail_msg("job %lld never finished", id);
    return NULL;
}

/* GET of a job's pattern: the same bytes as POST of the same pattern, for every format. */
static void test_get_matches_post(void **state)
{
    fixture *f = *state;
    long long id = api_submit(
        f, "{\"kind\":\"sleep\",\"seconds\":0,\"pattern\":{\"preset\":\"quincunx\"}}", 1000);
    json_decref(wait_done(f, id));
    static const char *const formats[] = {"utk", "xyw", "csv", "points-json", "vulkan", "d3d12"};
    for (size_t i = 0; i < sizeof formats / sizeof *formats; i++) {
        char path[96], body[128];
        snprintf(path, sizeof path, "/v1/patterns/%lld/export?format=%s", id, formats[i]);
        snprintf(body, sizeof body, "{\"pattern\":{\"job\":%lld},\"format\":\"%s\"}", id,
                 formats[i]);
        api_response g, p;
        api_request_raw(f, "GET", path, NULL, 1000, &g);
        api_request_raw(f, "POST", "/v1/patterns/export", body, 1000, &p);
        assert_int_equal(g.status, 200);
        assert_int_equal(p.status, 200);
        assert_int_equal(g.body_len, p.body_len);
        assert_memory_equal(g.body, p.body, g.body_len);
        api_response_free(&g);
        api_response_free(&p);
    }
    char path[96];
    snprintf(path, sizeof path, "/v1/patterns/%lld/export?format=dat", id);
    expect_error(f, "GET", path, NULL, 400, "format");
    expect_error(f, "GET", "/v1/patterns/424242/export?format=csv", NULL, 404, "id");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_post_formats, setup, teardown),
        cmocka_unit_test_setup_teardown(test_post_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_get_matches_post, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
