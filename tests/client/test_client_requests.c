/* Request bodies built from the command line: the wire format, exactly. */
#define _DEFAULT_SOURCE /* mkstemps */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>
#include <jansson.h>

#include "args.h"
#include "commands/commands.h"
#include "pattern_source.h"

static char *write_temp(const char *text)
{
    const char *dir = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    char *path = malloc(strlen(dir) + 32);
    sprintf(path, "%s/aalab-test-XXXXXX", dir);
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    assert_int_equal(write(fd, text, strlen(text)), (ssize_t)strlen(text));
    close(fd);
    return path;
}

/* A temporary file whose name ends in suffix (point sets are read by extension). */
static char *write_temp_as(const char *text, const char *suffix)
{
    const char *dir = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    char *path = malloc(strlen(dir) + strlen(suffix) + 32);
    sprintf(path, "%s/aalab-test-XXXXXX%s", dir, suffix);
    int fd = mkstemps(path, (int)strlen(suffix));
    assert_true(fd >= 0);
    assert_int_equal(write(fd, text, strlen(text)), (ssize_t)strlen(text));
    close(fd);
    return path;
}

static void assert_json(const json_t *got, const char *expected)
{
    json_t *want = json_loads(expected, 0, NULL);
    assert_non_null(want);
    if (!json_equal(got, want)) {
        char *g = json_dumps(got, JSON_SORT_KEYS);
        print_error("got      %s\nexpected %s\n", g, expected);
        free(g);
        fail();
    }
    json_decref(want);
}

static void eval_preset_name(void **state)
{
    cli_args a = {.command = CMD_EVAL, .target = "quincunx"};
    json_t *req;
    char err[256];
    assert_int_equal(eval_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"pattern\":{\"preset\":\"quincunx\"}}");
    json_decref(req);
}

static void eval_options(void **state)
{
    cli_args a = {.command = CMD_EVAL,
                  .target = "rgss",
                  .filter = "mitchell:B=0.5,C=0.25",
                  .acuity = "uniform",
                  .angles = "0,22.5,45",
                  .detail = true};
    json_t *req;
    char err[256];
    assert_int_equal(eval_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"pattern\":{\"preset\":\"rgss\"},"
                     "\"filter\":{\"name\":\"mitchell\",\"B\":0.5,\"C\":0.25},"
                     "\"acuity\":{\"name\":\"uniform\"},\"angles\":[0.0,22.5,45.0],"
                     "\"detail\":true}");
    json_decref(req);
}

static void eval_json_literals(void **state)
{
    cli_args a = {.command = CMD_EVAL,
                  .target = "rgss",
                  .filter = "{\"name\":\"box\"}",
                  .acuity = "{\"knots\":[[0,1],[45,0.5]]}"};
    json_t *req;
    char err[256];
    assert_int_equal(eval_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"pattern\":{\"preset\":\"rgss\"},\"filter\":{\"name\":\"box\"},"
                     "\"acuity\":{\"knots\":[[0,1],[45,0.5]]}}");
    json_decref(req);
}

static void eval_pattern_file(void **state)
{
    char *path = write_temp("{\"mirrored\":[[0,0,0.5],[0.5,0.5,0.5]]}");
    cli_args a = {.command = CMD_EVAL, .target = path};
    json_t *req;
    char err[256];
    assert_int_equal(eval_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"pattern\":{\"mirrored\":[[0,0,0.5],[0.5,0.5,0.5]]}}");
    json_decref(req);
    unlink(path);
    free(path);
}

static void eval_request_file_with_override(void **state)
{
    char *path = write_temp("{\"pattern\":{\"kernels\":[[[0,0,1]]]},\"detail\":false,"
                            "\"acuity\":{\"name\":\"naiman\"}}");
    cli_args a = {.command = CMD_EVAL, .target = path, .acuity = "uniform", .detail = true};
    json_t *req;
    char err[256];
    assert_int_equal(eval_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"pattern\":{\"kernels\":[[[0,0,1]]]},\"detail\":true,"
                     "\"acuity\":{\"name\":\"uniform\"}}");
    json_decref(req);
    unlink(path);
    free(path);
}

static void eval_exported_file(void **state)
{
    char *path = write_temp("{\"job\":12,\"pattern\":{\"family\":\"P(1,1,1)\",\"form\":"
                            "\"kernels\",\"kernels\":[[[0,0,1]]]}}");
    cli_args a = {.command = CMD_EVAL, .target = path};
    json_t *req;
    char err[256];
    assert_int_equal(eval_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"pattern\":{\"family\":\"P(1,1,1)\",\"form\":\"kernels\","
                     "\"kernels\":[[[0,0,1]]]}}");
    json_decref(req);
    unlink(path);
    free(path);
}

static void bad_files_are_local_errors(void **state)
{
    static const char *const CASES[][2] = {
        {"{\"kernels\":[[[0,0,1]]],\"kernels\":[]}", "duplicate"},
        {"[1,2]", "a point is [x, y]"}, /* an array is a point set */
        {"{\"kernels\":[[[0,0,1]]]", ""},
        {"{\"pattern\":[1]}", "pattern"},
        {"{}", "pattern"},
    };
    for (size_t i = 0; i < sizeof CASES / sizeof CASES[0]; i++) {
        char *path = write_temp(CASES[i][0]);
        cli_args a = {.command = CMD_EVAL, .target = path};
        json_t *req = (json_t *)1;
        char err[400] = "";
        assert_int_equal(eval_request(&a, &req, err, sizeof err), -1);
        assert_null(req);
        assert_non_null(strstr(err, path)); /* the message names the file */
        if (!strstr(err, CASES[i][1]))
            fail_msg("case %zu: '%s' lacks '%s'", i, err, CASES[i][1]);
        unlink(path);
        free(path);
    }
    cli_args a = {.command = CMD_EVAL, .target = "/nonexistent/p.json"};
    json_t *req;
    char err[400];
    assert_int_equal(eval_request(&a, &req, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/p.json"));
}

/* With the shared codec the local check names the same JSON path the daemon would. */
static void codec_names_the_field(void **state)
{
    char *path = write_temp("{\"kernels\":[[[0,0,0.5],[0.25,0.25,\"x\"]]]}");
    cli_args a = {.command = CMD_EVAL, .target = path};
    json_t *req;
    char err[400] = "";
    assert_int_equal(eval_request(&a, &req, err, sizeof err), -1);
    if (!strstr(err, "pattern.kernels[0][1][2]"))
        fail_msg("'%s' lacks the field path", err);
    unlink(path);
    free(path);
    /* an encoded pattern (informational keys included) is accepted */
    path = write_temp("{\"family\":\"P(1,1,1)\",\"cost_spp\":1,\"form\":\"kernels\","
                      "\"kernels\":[[[0,0,1]]]}");
    a.target = path;
    assert_int_equal(eval_request(&a, &req, err, sizeof err), 0);
    json_decref(req);
    unlink(path);
    free(path);
}

static void filter_arguments(void **state)
{
    json_t *f;
    char err[256];
    assert_int_equal(filter_argument("gauss", &f, err, sizeof err), 0);
    assert_json(f, "{\"name\":\"gauss\"}");
    json_decref(f);
    assert_int_equal(filter_argument("mitchell:B", &f, err, sizeof err), -1);
    assert_non_null(strstr(err, "KEY=NUMBER"));
    assert_int_equal(filter_argument("mitchell:B=x", &f, err, sizeof err), -1);
    assert_int_equal(filter_argument(":B=1", &f, err, sizeof err), -1);
    assert_int_equal(filter_argument("{\"name\":1", &f, err, sizeof err), -1);
    assert_non_null(strstr(err, "invalid JSON"));
    assert_int_equal(filter_argument("{\"a\":1,\"a\":2}", &f, err, sizeof err), -1);
}

static void angle_arguments(void **state)
{
    json_t *v;
    char err[256];
    assert_int_equal(angles_argument("10", &v, err, sizeof err), 0);
    assert_json(v, "[10.0]");
    json_decref(v);
    assert_int_equal(angles_argument("10,,20", &v, err, sizeof err), -1);
    assert_int_equal(angles_argument("10,", &v, err, sizeof err), -1);
    assert_int_equal(angles_argument("ten", &v, err, sizeof err), -1);
}

static void optimize_bodies(void **state)
{
    cli_args a = {.command = CMD_OPTIMIZE,
                  .family = "P(4,1+,2)",
                  .seeds = 16,
                  .has_seeds = true,
                  .max_seconds = 2.5,
                  .has_max_seconds = true,
                  .rng_seed = 42,
                  .has_rng_seed = true,
                  .max_iterations = 500,
                  .has_max_iterations = true,
                  .executor = "slurm",
                  .mode = "weights",
                  .method = "minimax"};
    json_t *req;
    char err[256];
    assert_int_equal(optimize_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"kind\":\"optimize\",\"family\":\"P(4,1+,2)\",\"seeds\":16,"
                     "\"max_seconds\":2.5,\"max_iterations\":500,\"executor\":\"slurm\","
                     "\"rng_seed\":42,\"mode\":\"weights\","
                     "\"method\":\"minimax\"}");
    json_decref(req);
    cli_args b = {.command = CMD_OPTIMIZE, .pattern = "flipquad"};
    assert_int_equal(optimize_request(&b, &req, err, sizeof err), 0);
    assert_json(req, "{\"kind\":\"optimize\",\"pattern\":{\"preset\":\"flipquad\"}}");
    json_decref(req);
}

static void render_bodies(void **state)
{
    cli_args a = {.command = CMD_RENDER, .pattern = "quincunx", .width = 256, .height = 128};
    json_t *req;
    char err[256];
    assert_int_equal(render_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"pattern\":{\"preset\":\"quincunx\"},\"scene\":\"siemens-star\","
                     "\"size\":[256,128]}");
    json_decref(req);
    cli_args j = {.command = CMD_RENDER, .pattern = "job:17"};
    assert_int_equal(render_request(&j, &req, err, sizeof err), 0);
    assert_json(req, "{\"pattern\":{\"job\":\"17\"},\"scene\":\"siemens-star\"}");
    json_decref(req);
    j.pattern = "job:../x";
    assert_int_equal(render_request(&j, &req, err, sizeof err), -1);
    cli_args b = {.command = CMD_RENDER, .pattern = "rgss", .scene = "circles"};
    assert_int_equal(render_request(&b, &req, err, sizeof err), 0);
    assert_json(req, "{\"pattern\":{\"preset\":\"rgss\"},\"scene\":\"circles\"}");
    json_decref(req);
}

static void submit_specs(void **state)
{
    char *path = write_temp("{\"kind\":\"sleep\",\"seconds\":1}");
    cli_args a = {.command = CMD_SUBMIT, .target = path};
    json_t *req;
    char err[400] = "";
    assert_int_equal(submit_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"kind\":\"sleep\",\"seconds\":1}");
    json_decref(req);
    unlink(path);
    free(path);
    static const char *const BAD[][2] = {
        {"{\"seconds\":1}", "\"kind\""},
        {"[]", "\"kind\""},
        {"{\"kind\":\"a\",\"kind\":\"b\"}", "duplicate"},
        {"{\"kind\":\"sleep\",\"pattern\":{\"mirrored\":[[0,0]]}}", "pattern.mirrored[0]"},
    };
    for (size_t i = 0; i < sizeof BAD / sizeof BAD[0]; i++) {
        path = write_temp(BAD[i][0]);
        a.target = path;
        assert_int_equal(submit_request(&a, &req, err, sizeof err), -1);
        if (!strstr(err, BAD[i][1]))
            fail_msg("case %zu: '%s' lacks '%s'", i, err, BAD[i][1]);
        unlink(path);
        free(path);
    }
    /* a job reference is left to the daemon */
    path = write_temp("{\"kind\":\"compare\",\"pattern\":{\"job\":\"3\"}}");
    a.target = path;
    assert_int_equal(submit_request(&a, &req, err, sizeof err), 0);
    json_decref(req);
    unlink(path);
    free(path);
}

/* A point-set file becomes the points form, read by extension or --points-format; the codec
 * names a bad line locally, as the daemon would. */
static void point_set_files(void **state)
{
    char err[400] = "";
    json_t *req;
    char *path = write_temp_as("# UTK\n0.25 0.25\n0.75 0.75\n", ".dat");
    cli_args a = {.command = CMD_EVAL, .target = path, .tile = 1, .weights = "equal"};
    assert_int_equal(eval_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"pattern\":{\"points\":{\"format\":\"utk\",\"text\":\"# UTK\\n0.25 "
                     "0.25\\n0.75 0.75\\n\",\"tile\":1,\"weights\":\"equal\"}}}");
    json_decref(req);
    a.weights = NULL; /* weights from the file, which has none */
    assert_int_equal(eval_request(&a, &req, err, sizeof err), -1);
    if (!strstr(err, "--weights: the points have no weights; choose filter or equal"))
        fail_msg("'%s'", err);
    unlink(path);
    free(path);

    path = write_temp_as("x,y,w\n0.25,0.25,0.5\n0.75\n", ".csv");
    a = (cli_args){.command = CMD_EVAL, .target = path};
    assert_int_equal(eval_request(&a, &req, err, sizeof err), -1);
    if (!strstr(err, ": line 3: 1 field, but the header (line 1) names 3"))
        fail_msg("'%s'", err);
    unlink(path);
    free(path);

    /* a JSON array of points goes as data */
    path = write_temp_as("[[0.25,0.25,0.5],[0.75,0.75,0.5]]", ".json");
    a = (cli_args){.command = CMD_EVAL, .target = path};
    assert_int_equal(eval_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"pattern\":{\"points\":{\"format\":\"json\",\"data\":[[0.25,0.25,0.5],"
                     "[0.75,0.75,0.5]]}}}");
    json_decref(req);
    unlink(path);
    free(path);

    /* any name with --points-format */
    path = write_temp_as("0.5 0.5 1\n", ".points");
    a = (cli_args){.command = CMD_RENDER, .pattern = path, .points_format = "xyw"};
    assert_int_equal(render_request(&a, &req, err, sizeof err), 0);
    json_decref(req);
    a.points_format = NULL; /* without it, not a point set: JSON expected */
    assert_int_equal(render_request(&a, &req, err, sizeof err), -1);
    unlink(path);
    free(path);

    /* point-set options on a preset or a pattern file are usage errors */
    a = (cli_args){.command = CMD_EVAL, .target = "rgss", .tile = 2};
    assert_int_equal(eval_request(&a, &req, err, sizeof err), -1);
    assert_non_null(strstr(err, "apply to point-set files"));
    path = write_temp_as("{\"preset\":\"rgss\"}", ".json");
    a = (cli_args){.command = CMD_EVAL, .target = path, .weights = "equal"};
    assert_int_equal(eval_request(&a, &req, err, sizeof err), -1);
    assert_non_null(strstr(err, "apply to point sets"));
    unlink(path);
    free(path);
}

/* convert writes with the codec: an exported file converts back to the same pattern. */
static void convert_round_trip(void **state)
{
    char err[400] = "";
    json_t *pattern = json_pack("{s:s}", "preset", "flipquad");
    char *text;
    size_t len;
    assert_int_equal(convert_text(pattern, "csv", &text, &len, err, sizeof err), 0);
    assert_true(!strncmp(text, "# aalab-pattern {", 17));
    char *path = write_temp_as(text, ".csv");
    free(text);
    cli_args a = {.command = CMD_CONVERT, .target = path};
    json_t *back, *extras;
    assert_int_equal(pattern_argument_load(path, &a, &back, &extras, err, sizeof err), 0);
    char *j1, *j2;
    assert_int_equal(convert_text(pattern, "json", &j1, &len, err, sizeof err), 0);
    assert_int_equal(convert_text(back, "json", &j2, &len, err, sizeof err), 0);
    assert_string_equal(j1, j2);
    free(j1);
    free(j2);
    assert_int_equal(convert_text(pattern, "png", &text, &len, err, sizeof err), -1);
    json_decref(back);
    json_decref(pattern);
    unlink(path);
    free(path);
}

static char *write_bytes_as(const void *b, size_t n, const char *suffix)
{
    const char *dir = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    char *path = malloc(strlen(dir) + strlen(suffix) + 32);
    sprintf(path, "%s/aalab-test-XXXXXX%s", dir, suffix);
    int fd = mkstemps(path, (int)strlen(suffix));
    assert_true(fd >= 0);
    assert_int_equal(write(fd, b, n), (ssize_t)n);
    close(fd);
    return path;
}

/* The sampling tools' files: .rps and .bin go base64, --set picks a set, convert writes bin,
 * rps and metal with the daemon's writer. */
static void tool_formats(void **state)
{
    char err[400] = "";
    json_t *req;
    static const unsigned char rps[16] = {0, 0, 0x80, 0x3e, 0, 0, 0x80, 0x3e,
                                          0, 0, 0x40, 0x3f, 0, 0, 0x40, 0x3f};
    char *path = write_bytes_as(rps, sizeof rps, ".rps");
    cli_args a = {.command = CMD_EVAL, .target = path, .weights = "equal"};
    assert_int_equal(eval_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"pattern\":{\"points\":{\"format\":\"rps\",\"base64\":"
                     "\"AACAPgAAgD4AAEA/AABAPw==\",\"weights\":\"equal\"}}}");
    json_decref(req);
    a.set = "1"; /* an rps file holds one set: the local codec says so */
    assert_int_equal(eval_request(&a, &req, err, sizeof err), -1);
    if (!strstr(err, "--set: is 1 but an rps file holds one set"))
        fail_msg("'%s'", err);
    unlink(path);
    free(path);

    /* bin: rgss written by convert reads back as rgss */
    json_t *rgss = json_pack("{s:s}", "preset", "rgss");
    char *text, *j1, *j2;
    size_t len, len2;
    assert_int_equal(convert_text(rgss, "bin", &text, &len, err, sizeof err), 0);
    assert_memory_equal(text, "UTK!\x05", 5);
    path = write_bytes_as(text, len, ".bin");
    free(text);
    a = (cli_args){.command = CMD_CONVERT, .target = path};
    json_t *back;
    assert_int_equal(pattern_argument_load(path, &a, &back, NULL, err, sizeof err), 0);
    assert_int_equal(convert_text(rgss, "json", &j1, &len, err, sizeof err), 0);
    assert_int_equal(convert_text(back, "json", &j2, &len2, err, sizeof err), 0);
    assert_string_equal(j1, j2);
    free(j1);
    free(j2);
    json_decref(back);
    unlink(path);
    free(path);
    assert_int_equal(convert_text(rgss, "rps", &text, &len, err, sizeof err), 0);
    assert_int_equal(len, 4 * 8);
    free(text);
    json_decref(rgss);
    json_t *d3d = json_pack("{s:s}", "preset", "d3d-4x");
    assert_int_equal(convert_text(d3d, "metal", &text, &len, err, sizeof err), 0);
    assert_non_null(strstr(text, "\"api\":\"metal\",\"family\":\"P(1,1,4)\""));
    assert_non_null(strstr(text, "\"representable\":true"));
    free(text);
    json_decref(d3d);

    /* sets: one by number, or all for analyze (checked locally on set 0) */
    path = write_temp_as("0.1 0.2\n0.6 0.7\n#\n0.3 0.3\n0.8 0.9\n", ".dat");
    a = (cli_args){.command = CMD_EVAL, .target = path, .weights = "equal", .set = "1"};
    assert_int_equal(eval_request(&a, &req, err, sizeof err), 0);
    assert_int_equal(json_integer_value(json_object_get(
                         json_object_get(json_object_get(req, "pattern"), "points"), "set")),
                     1);
    json_decref(req);
    a.set = "2";
    assert_int_equal(eval_request(&a, &req, err, sizeof err), -1);
    if (!strstr(err, "--set: is 2 but the file holds 2 sets"))
        fail_msg("'%s'", err);
    a = (cli_args){.command = CMD_ANALYZE, .target = path, .weights = "equal", .set = "all"};
    assert_int_equal(analyze_request(&a, &req, err, sizeof err), 0);
    assert_string_equal(json_string_value(json_object_get(
                            json_object_get(json_object_get(req, "pattern"), "points"), "set")),
                        "all");
    json_decref(req);
    unlink(path);
    free(path);
}

static void file_or_preset(void **state)
{
    assert_false(pattern_argument_is_file("quincunx"));
    assert_false(pattern_argument_is_file("flipquad"));
    assert_true(pattern_argument_is_file("best.json"));
    assert_true(pattern_argument_is_file("./quincunx"));
    assert_true(pattern_argument_is_file("/tmp"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(eval_preset_name),
        cmocka_unit_test(eval_options),
        cmocka_unit_test(eval_json_literals),
        cmocka_unit_test(eval_pattern_file),
        cmocka_unit_test(eval_request_file_with_override),
        cmocka_unit_test(eval_exported_file),
        cmocka_unit_test(bad_files_are_local_errors),
        cmocka_unit_test(codec_names_the_field),
        cmocka_unit_test(filter_arguments),
        cmocka_unit_test(angle_arguments),
        cmocka_unit_test(optimize_bodies),
        cmocka_unit_test(render_bodies),
        cmocka_unit_test(submit_specs),
        cmocka_unit_test(point_set_files),
        cmocka_unit_test(convert_round_trip),
        cmocka_unit_test(tool_formats),
        cmocka_unit_test(file_or_preset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
