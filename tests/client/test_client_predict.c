/* aalab predict: argument parsing, the request body and the view of an answer. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <jansson.h>

#include "args.h"
#include "capture.h"
#include "commands/commands.h"

static int parse(cli_args *a, char *err, size_t cap, ...)
{
    char *argv[32] = {"aalab"};
    int argc = 1;
    va_list ap;
    va_start(ap, cap);
    for (char *s; (s = va_arg(ap, char *)) != NULL && argc < 31;)
        argv[argc++] = s;
    va_end(ap);
    return cli_parse(argc, argv, a, err, cap);
}

#define PARSE(a, ...) parse(a, err, sizeof err, __VA_ARGS__, (char *)NULL)

static void assert_json(const json_t *got, const char *expected)
{
    json_t *want = json_loads(expected, 0, NULL);
    assert_non_null(want);
    if (!json_equal(got, want)) {
        char *g = json_dumps(got, JSON_SORT_KEYS | JSON_COMPACT);
        fail_msg("got %s, want %s", g, expected);
    }
    json_decref(want);
}

static void parsing(void **state)
{
    (void)state;
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "predict", "--pattern", "rgss,quincunx", "--scene", "half-plane",
                           "--angle", "27", "--size", "128x64", "--csv"),
                     0);
    assert_int_equal(a.command, CMD_PREDICT);
    assert_true(a.has_angle);
    assert_true(a.angle == 27);
    assert_int_equal(a.width, 128);
    assert_true(a.csv);
    assert_int_equal(PARSE(&a, "predict"), -1);
    assert_non_null(strstr(err, "--pattern"));
    assert_int_equal(PARSE(&a, "predict", "--pattern", "rgss", "--angle", "x"), -1);
    assert_int_equal(PARSE(&a, "render", "--pattern", "rgss", "--angle", "3", "--json"), -1);
    assert_int_equal(PARSE(&a, "predict", "--pattern", "rgss", "-o", "x.png"), -1);
    assert_null(a.model);
    assert_int_equal(PARSE(&a, "predict", "--pattern", "rgss", "--model", "exact"), 0);
    assert_string_equal(a.model, "exact");
    assert_int_equal(PARSE(&a, "predict", "--pattern", "rgss", "--model", "segments"), -1);
    assert_non_null(strstr(err, "--model"));
    assert_int_equal(PARSE(&a, "render", "--pattern", "rgss", "--model", "exact", "--json"), -1);
}

static void request_bodies(void **state)
{
    (void)state;
    json_t *req;
    char err[256];
    cli_args a = {.command = CMD_PREDICT, .pattern = "rgss,job:17", .width = 64, .height = 32};
    assert_int_equal(predict_request(&a, &req, err, sizeof err), 0);
    assert_json(req, "{\"patterns\":[{\"preset\":\"rgss\"},{\"job\":\"17\"}],"
                     "\"scene\":\"siemens-star\",\"size\":[64,32]}");
    json_decref(req);
    cli_args b = {.command = CMD_PREDICT,
                  .pattern = "rgss",
                  .scene = "half-plane",
                  .angle = 27.5,
                  .has_angle = true};
    assert_int_equal(predict_request(&b, &req, err, sizeof err), 0);
    assert_json(req, "{\"patterns\":[{\"preset\":\"rgss\"}],"
                     "\"scene\":{\"name\":\"half-plane\",\"angle\":27.5}}");
    json_decref(req);
    cli_args m = {.command = CMD_PREDICT, .pattern = "rgss", .model = "reference-profile"};
    assert_int_equal(predict_request(&m, &req, err, sizeof err), 0);
    assert_json(req, "{\"patterns\":[{\"preset\":\"rgss\"}],\"scene\":\"siemens-star\","
                     "\"model\":\"reference-profile\"}");
    json_decref(req);
    cli_args c = {.command = CMD_PREDICT, .pattern = ","};
    assert_int_equal(predict_request(&c, &req, err, sizeof err), -1);
    cli_args d = {.command = CMD_PREDICT, .pattern = "rgss,job:../x"};
    assert_int_equal(predict_request(&d, &req, err, sizeof err), -1);
}

/* An answer in the shape of predict_response.json (values as the daemon wrote them for the
 * star; shortened to two angles). */
static const char ANSWER[] =
    "{\"scene\":{\"name\":\"siemens-star\",\"width\":256,\"height\":256},"
    "\"reference\":{\"filter\":\"mitchell\"},\"model\":\"exact\","
    "\"edges\":{\"total_length\":4110.2,\"locked_length\":439.0,\"subpixel_area_share\":0.0012},"
    "\"predictions\":[{\"pattern\":{\"name\":\"rgss\",\"family\":\"P(1,1,4)\","
    "\"samples_per_pixel\":4,\"kernels\":1},\"predicted_rmse\":4.25,\"locked_share\":0.125,"
    "\"angles\":[{\"angle\":45,\"length\":50,\"e1_rms\":0.2,\"share\":0.031},"
    "{\"angle\":0,\"length\":219.5,\"e1_rms\":0.1,\"share\":0.02}]},"
    "{\"pattern\":{\"name\":\"\",\"family\":\"P(1,1,1)\",\"samples_per_pixel\":1,\"kernels\":1},"
    "\"predicted_rmse\":9.5,\"locked_share\":0.25,\"angles\":[]}]}";

static void view(void **state)
{
    (void)state;
    json_t *r = json_loads(ANSWER, 0, NULL);
    assert_non_null(r);
    capture c;
    predict_print(capture_begin(&c), r, false);
    const char *text = capture_end(&c);
    assert_non_null(strstr(text, "predicted RMSE"));
    assert_non_null(strstr(text, "rgss"));
    assert_non_null(strstr(text, "4.250"));
    assert_non_null(strstr(text, "45° 3%"));
    assert_non_null(strstr(text, "#2"));
    assert_non_null(strstr(text, "9.500"));
    assert_non_null(strstr(text, "edge length 4110.2 px (439.0 px pixel-locked)"));
    assert_non_null(strstr(text, "0.1% of the image is below the pixel scale"));
    assert_non_null(strstr(text, "\nmodel exact, reference filter mitchell\n"));
    capture_free(&c);
    predict_print(capture_begin(&c), r, true);
    text = capture_end(&c);
    assert_non_null(strstr(text, "pattern,family,spp,predicted RMSE,locked share,costliest angle"));
    assert_non_null(strstr(text, "rgss,\"P(1,1,4)\",4.000,4.250,0.125,45° 3%"));
    assert_null(strstr(text, "edge length"));
    assert_null(strstr(text, "model exact"));
    capture_free(&c);
    /* issue 34: the row of `--pattern rgss,job:8` reads "job:8", not "#2" */
    predict_name_rows(r, "rgss,job:8");
    predict_print(capture_begin(&c), r, false);
    text = capture_end(&c);
    assert_non_null(strstr(text, "\njob:8 "));
    assert_null(strstr(text, "#2"));
    assert_non_null(strstr(text, "\nrgss "));
    capture_free(&c);
    json_decref(r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(parsing),
        cmocka_unit_test(request_bodies),
        cmocka_unit_test(view),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
