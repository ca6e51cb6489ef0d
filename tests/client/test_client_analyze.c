/* aalab analyze: argument parsing, the request body and the view of an answer. */
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

static void parsing_and_request(void **state)
{
    (void)state;
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "analyze", "flipquad", "--metrics", "spacing,spectrum", "--radius",
                           "8", "--pcf-bins", "16"),
                     0);
    assert_int_equal(a.command, CMD_ANALYZE);
    assert_int_equal(a.radius, 8);
    json_t *req;
    assert_int_equal(analyze_request(&a, &req, err, sizeof err), 0);
    json_t *want = json_loads("{\"pattern\":{\"preset\":\"flipquad\"},\"metrics\":[\"spacing\","
                              "\"spectrum\"],\"spectrum\":{\"radius\":8},\"pcf\":{\"bins\":16}}",
                              0, NULL);
    if (!json_equal(req, want)) {
        char *g = json_dumps(req, JSON_SORT_KEYS | JSON_COMPACT);
        fail_msg("got %s", g);
    }
    json_decref(want);
    json_decref(req);
    assert_int_equal(PARSE(&a, "analyze"), -1);
    assert_non_null(strstr(err, "preset NAME"));
    assert_int_equal(PARSE(&a, "analyze", "rgss", "--radius", "0"), -1);
    assert_non_null(strstr(err, "--radius"));
    assert_int_equal(PARSE(&a, "analyze", "rgss", "--radius", "129"), -1);
    assert_int_equal(PARSE(&a, "eval", "rgss", "--radius", "4"), -1);
    assert_int_equal(PARSE(&a, "analyze", "rgss", "--metrics", "a,,b"), 0);
    assert_int_equal(analyze_request(&a, &req, err, sizeof err), -1);
    assert_non_null(strstr(err, "--metrics"));
}

static const char *ANSWER =
    "{\"points\":8,\"tile\":2,\"family\":\"P(4,1+,2)\","
    "\"discrepancy\":{\"centered\":0.25,\"centered_squared\":0.0625,\"star_linf\":0.333333},"
    "\"spacing\":{\"min_distance\":0.3,\"mean_nn_distance\":0.32,\"packing_distance\":0.38,"
    "\"min_distance_normalized\":0.789,\"mean_nn_distance_normalized\":0.842},"
    "\"spectrum\":{\"radius\":2,\"radial\":[8,0,0.5],\"anisotropy_db\":[null,null,1.5],"
    "\"annulus_count\":[1,8,12],\"effective_nyquist\":1,\"effective_nyquist_normalized\":0.35,"
    "\"oscillation\":null}}";

static void view(void **state)
{
    (void)state;
    json_t *resp = json_loads(ANSWER, 0, NULL);
    assert_non_null(resp);
    capture c;
    analyze_print(capture_begin(&c), resp, false);
    const char *text = capture_end(&c);
    assert_non_null(strstr(text, "CD                 0.25 (square 0.0625)"));
    assert_non_null(strstr(text, "Linf-star"));
    assert_non_null(strstr(text, "0.789 of d_hex"));
    assert_non_null(strstr(text, "effective Nyquist  1 (0.350 sqrt(n))"));
    assert_non_null(strstr(text, "annulus  frequencies"));
    assert_null(strstr(text, "WD")); /* not in the answer: not printed */
    capture_free(&c);
    analyze_print(capture_begin(&c), resp, true);
    text = capture_end(&c);
    /* RFC 4180: CRLF line ends; a missing value is an empty field. */
    assert_string_equal(text, "annulus,frequencies,power,anisotropy_db\r\n"
                              "0,1,8.0000,\r\n1,8,0.0000,\r\n2,12,0.5000,1.50\r\n");
    capture_free(&c);
    json_decref(resp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(parsing_and_request),
        cmocka_unit_test(view),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
