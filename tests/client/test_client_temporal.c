/* aalab eval with a temporal pattern (issue 30, docs/temporal.md): the options, the request
 * bodies they build (exactly), local checks by the daemon's codec, and the per-phase view of a
 * recorded daemon answer (fixtures/eval_temporal.json: halton23-8, angles 0, 45, 90, K = 12). */
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
#include "capture.h"
#include "commands/commands.h"
#include "commands/eval_temporal.h"

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

static void contains(const char *text, const char *needle)
{
    if (!strstr(text, needle))
        fail_msg("output lacks '%s':\n%s", needle, text);
}

/* The arguments after "aalab", up to a NULL. */
static int collect(char **argv, va_list ap)
{
    int argc = 1;
    argv[0] = "aalab";
    for (char *s; argc < 23 && (s = va_arg(ap, char *));)
        argv[argc++] = s;
    return argc;
}

static int parse(cli_args *a, char *err, size_t cap, ...)
{
    char *argv[24];
    va_list ap;
    va_start(ap, cap);
    int argc = collect(argv, ap);
    va_end(ap);
    return cli_parse(argc, argv, a, err, cap);
}

/* The request of a command line, as compact JSON with sorted keys (NULL: a usage error). */
static json_t *request_of(char *err, size_t cap, ...)
{
    char *argv[24];
    va_list ap;
    va_start(ap, cap);
    int argc = collect(argv, ap);
    va_end(ap);
    cli_args a;
    if (cli_parse(argc, argv, &a, err, cap))
        return NULL;
    json_t *req;
    return eval_request(&a, &req, err, cap) ? NULL : req;
}

static void options_parse(void **state)
{
    cli_args a;
    char err[256];
    assert_int_equal(
        parse(&a, err, sizeof err, "eval", "--temporal", "halton23-8", "--alpha", "0.05", NULL), 0);
    assert_string_equal(a.temporal, "halton23-8");
    assert_true(a.has_alpha);
    assert_true(a.alpha == 0.05);
    assert_null(a.target);
    /* --temporal stands for the pattern argument; both is a usage error */
    assert_int_equal(parse(&a, err, sizeof err, "eval", "rgss", "--temporal", "halton23-8", NULL),
                     -1);
    contains(err, "not both");
    assert_int_equal(parse(&a, err, sizeof err, "eval", "--alpha", "0", NULL), -1);
    contains(err, "--alpha wants a number in [1e-6, 1]");
    assert_int_equal(
        parse(&a, err, sizeof err, "eval", "--temporal", "x", "--blend", "gauss", NULL), -1);
    contains(err, "--blend wants box, exponential or an alpha");
    assert_int_equal(
        parse(&a, err, sizeof err, "eval", "--temporal", "x", "--cut-frames", "0", NULL), -1);
    contains(err, "--cut-frames wants an integer in 1..4096");
    /* optimize keeps its --blend: a number in [0, 1] */
    assert_int_equal(parse(&a, err, sizeof err, "optimize", "--pattern", "rgss", "--scene",
                           "siemens-star", "--blend", "box", NULL),
                     -1);
    contains(err, "--blend wants a number in [0, 1], got 'box'");
    assert_int_equal(parse(&a, err, sizeof err, "optimize", "--pattern", "rgss", "--scene",
                           "siemens-star", "--blend", "0.25", NULL),
                     0);
    assert_true(a.has_blend && a.blend == 0.25);
    /* the temporal options belong to eval */
    assert_int_equal(parse(&a, err, sizeof err, "presets", "--alpha", "0.1", NULL), -1);
    contains(err, "does not apply to 'presets'");
}

static void preset_with_flags(void **state)
{
    char err[256];
    json_t *r = request_of(err, sizeof err, "eval", "--temporal", "halton23-8", NULL);
    assert_non_null(r);
    assert_json(r, "{\"pattern\":{\"temporal\":{\"preset\":\"halton23-8\"}}}");
    json_decref(r);
    r = request_of(err, sizeof err, "eval", "--temporal", "urp-like", "--alpha", "0.2",
                   "--cut-frames", "16", "--angles", "0,45", NULL);
    assert_non_null(r);
    assert_json(r, "{\"pattern\":{\"temporal\":{\"preset\":\"urp-like\",\"blend\":{\"kind\":"
                   "\"exponential\",\"alpha\":0.2},\"cut_frames\":16}},\"angles\":[0.0,45.0]}");
    json_decref(r);
    r = request_of(err, sizeof err, "eval", "--temporal", "halton23-16", "--blend", "box", NULL);
    assert_non_null(r);
    assert_json(r, "{\"pattern\":{\"temporal\":{\"preset\":\"halton23-16\",\"blend\":{\"kind\":"
                   "\"box\"}}}}");
    json_decref(r);
    r = request_of(err, sizeof err, "eval", "--temporal", "halton23-8", "--blend", "0.3", NULL);
    assert_non_null(r);
    assert_json(r, "{\"pattern\":{\"temporal\":{\"preset\":\"halton23-8\",\"blend\":{\"kind\":"
                   "\"exponential\",\"alpha\":0.3}}}}");
    json_decref(r);
    /* --blend exponential alone: the schema's default alpha 0.1 */
    r = request_of(err, sizeof err, "eval", "--temporal", "halton23-8", "--blend", "exponential",
                   NULL);
    assert_non_null(r);
    assert_json(r, "{\"pattern\":{\"temporal\":{\"preset\":\"halton23-8\",\"blend\":{\"kind\":"
                   "\"exponential\",\"alpha\":0.1}}}}");
    json_decref(r);
    assert_null(request_of(err, sizeof err, "eval", "--temporal", "halton23-8", "--blend", "box",
                           "--alpha", "0.1", NULL));
    contains(err, "--blend box has none");
    assert_null(request_of(err, sizeof err, "eval", "--temporal", "halton23-8", "--blend", "0.2",
                           "--alpha", "0.3", NULL));
    contains(err, "disagree");
    /* the temporal options on a spatial pattern are a usage error, not silently dropped */
    assert_null(request_of(err, sizeof err, "eval", "rgss", "--alpha", "0.1", NULL));
    contains(err, "apply to a temporal pattern");
}

static void generators_resolve_and_frame_pattern(void **state)
{
    char err[256];
    json_t *r = request_of(err, sizeof err, "eval", "--temporal", "halton:8", NULL);
    assert_non_null(r);
    assert_json(r, "{\"pattern\":{\"temporal\":{\"jitter\":{\"generator\":\"halton\",\"count\":8,"
                   "\"start\":1}}}}");
    json_decref(r);
    r = request_of(err, sizeof err, "eval", "--temporal", "r2:16:0", NULL);
    assert_non_null(r);
    assert_json(r, "{\"pattern\":{\"temporal\":{\"jitter\":{\"generator\":\"r2\",\"count\":16,"
                   "\"start\":0}}}}");
    json_decref(r);
    r = request_of(err, sizeof err, "eval", "--temporal", "fsr2:1.5", NULL);
    assert_non_null(r);
    assert_json(r, "{\"pattern\":{\"temporal\":{\"jitter\":{\"generator\":\"fsr2\","
                   "\"scale\":1.5}}}}");
    json_decref(r);
    r = request_of(err, sizeof err, "eval", "--temporal", "positions:d3d-4x", "--blend", "box",
                   "--resolve", "gaussian:sigma=0.5", "--frame-pattern", "d3d-2x", NULL);
    assert_non_null(r);
    assert_json(r, "{\"pattern\":{\"temporal\":{\"jitter\":{\"generator\":\"preset\",\"preset\":"
                   "\"d3d-4x\"},\"blend\":{\"kind\":\"box\"},\"resolve\":{\"filter\":{\"name\":"
                   "\"gaussian\",\"sigma\":0.5}},\"frame_pattern\":{\"preset\":\"d3d-2x\"}}}}");
    json_decref(r);
    r = request_of(err, sizeof err, "eval", "--temporal", "rgss4", NULL);
    assert_non_null(r);
    assert_json(r, "{\"pattern\":{\"temporal\":{\"jitter\":{\"generator\":\"rgss4\"}}}}");
    json_decref(r);
    assert_null(request_of(err, sizeof err, "eval", "--temporal", "halton:0", NULL));
    contains(err, "halton:N[:START]");
    assert_null(request_of(err, sizeof err, "eval", "--temporal", "fsr2:0.5", NULL));
    contains(err, "fsr2:SCALE");
}

static char *write_temp_json(const char *text)
{
    const char *dir = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    char *path = malloc(strlen(dir) + 40);
    sprintf(path, "%s/aalab-temporal-XXXXXX.json", dir);
    int fd = mkstemps(path, 5);
    assert_true(fd >= 0);
    assert_int_equal(write(fd, text, strlen(text)), (ssize_t)strlen(text));
    close(fd);
    return path;
}

static void files_and_inline_json(void **state)
{
    char err[256];
    /* a pattern file: eval FILE.json with {"temporal": ...} goes the temporal way */
    char *path = write_temp_json("{\"temporal\":{\"jitter\":[[0.25,0.25],[-0.25,-0.25]]}}");
    json_t *r = request_of(err, sizeof err, "eval", path, "--alpha", "0.5", NULL);
    assert_non_null(r);
    assert_json(r, "{\"pattern\":{\"temporal\":{\"jitter\":[[0.25,0.25],[-0.25,-0.25]],"
                   "\"blend\":{\"kind\":\"exponential\",\"alpha\":0.5}}}}");
    json_decref(r);
    unlink(path);
    free(path);
    /* a saved request: its other members stay, options override them */
    path = write_temp_json("{\"pattern\":{\"temporal\":{\"preset\":\"halton23-8\"}},"
                           "\"angles\":[0,90],\"acuity\":{\"name\":\"naiman\"}}");
    r = request_of(err, sizeof err, "eval", "--temporal", path, "--acuity", "uniform", NULL);
    assert_non_null(r);
    assert_json(r, "{\"pattern\":{\"temporal\":{\"preset\":\"halton23-8\"}},\"angles\":[0,90],"
                   "\"acuity\":{\"name\":\"uniform\"}}");
    json_decref(r);
    unlink(path);
    free(path);
    /* inline, the bare temporal object */
    r = request_of(err, sizeof err, "eval", "--temporal",
                   "{\"jitter\":[[0,0]],\"blend\":{\"kind\":\"box\"}}", NULL);
    assert_non_null(r);
    assert_json(r,
                "{\"pattern\":{\"temporal\":{\"jitter\":[[0,0]],\"blend\":{\"kind\":\"box\"}}}}");
    json_decref(r);
    /* local errors, named by the daemon's own codec; nothing is sent */
    assert_null(
        request_of(err, sizeof err, "eval", "--temporal", "{\"jitter\":[[0,0],[0.7,0]]}", NULL));
    assert_string_equal(err, "field pattern.temporal.jitter[1]: an offset must lie in "
                             "[-jitter_range/2, jitter_range/2]^2");
    assert_null(request_of(err, sizeof err, "eval", "--temporal", "{\"jitter\":", NULL));
    contains(err, "--temporal: invalid JSON");
    assert_null(request_of(err, sizeof err, "eval", "--temporal", "no-such-temporal-preset", NULL));
    contains(err, "pattern.temporal.preset");
    assert_null(
        request_of(err, sizeof err, "eval", "--temporal", "{\"temporal\":{},\"x\":1}", NULL));
    contains(err, "no other keys");
}

static json_t *fixture(void)
{
    json_error_t e;
    json_t *j = json_load_file(AALAB_CLIENT_FIXTURES "/eval_temporal.json", 0, &e);
    if (!j)
        fail_msg("fixture: %s", e.text);
    return j;
}

static void view_of_an_answer(void **state)
{
    json_t *r = fixture();
    assert_true(eval_answer_is_temporal(r));
    capture c;
    eval_print(capture_begin(&c), r, false, false);
    const char *text = capture_end(&c);
    contains(text, "preset             halton23-8\n");
    contains(text, "phases             8\n");
    contains(text, "blend              exponential, alpha 0.1\n");
    contains(text, "E2 (worst phase)   0.482130\n");
    contains(text, "argmax             phase 1, angle_deg 0.0\n");
    contains(text, "mean over phases   0.459055\n");
    contains(text, "F2                 0.109987\n");
    contains(text, "frames to 5 %      none within 12\n");
    contains(text, "source: Halton(2,3) from index 1");
    contains(text, "phase      newest_x  newest_y  age_weight        e2  argmax_angle_deg\n");
    /* phase 0: the newest frame is offset 0, (0, -1/6); its worst angle is 90 (W E1 0.4358) */
    contains(text, "0            0.0000   -0.1667      0.1756  0.435843              90.0\n");
    contains(text, "2            0.2500   -0.3889      0.1422  0.464255              45.0\n");
    contains(text, "worst (1)         -         -           -  0.482130               0.0\n");
    contains(text, "mean              -         -           -  0.459055                 -\n");
    contains(text, "not within 5 % of the steady state by k = 12");
    contains(text,
             "  k 1-8        1.3985  1.2217  1.1769  1.1292  0.9419  0.9521  0.8760  0.6930\n");
    contains(text, "  k 9-12       0.7565  0.6777  0.6672  0.6800\n");
    assert_null(strstr(text, "e1_worst"));
    capture_free(&c);

    eval_print(capture_begin(&c), r, true, false);
    text = capture_end(&c);
    contains(text, "angle_deg  weight  e1_worst   e1_mean        f1  weighted_f1\n");
    contains(text, "     90.0  3.9300  0.118096  0.112141  0.027986     0.109987\n");
    capture_free(&c);

    eval_print(capture_begin(&c), r, false, true);
    text = capture_end(&c);
    contains(text, "phase,newest_x,newest_y,age_weight,e2,argmax_angle_deg\r\n");
    contains(text, "1,-0.25,0.16666666666666663,");
    assert_null(strstr(text, "worst"));
    capture_free(&c);

    /* frames to 5 % reached, and a box blend */
    json_object_set_new(r, "frames_to_5pct", json_integer(9));
    json_object_set_new(r, "blend", json_pack("{s:s}", "kind", "box"));
    eval_print(capture_begin(&c), r, false, false);
    text = capture_end(&c);
    contains(text, "frames to 5 %      9\n");
    contains(text, "within 5 % of the steady state from k = 9");
    contains(text, "blend              box\n");
    capture_free(&c);
    json_decref(r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(options_parse),
        cmocka_unit_test(preset_with_flags),
        cmocka_unit_test(generators_resolve_and_frame_pattern),
        cmocka_unit_test(files_and_inline_json),
        cmocka_unit_test(view_of_an_answer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
