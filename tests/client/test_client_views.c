/* Human-readable views of daemon answers, error lines, exit codes, socket path resolution. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cmocka.h>
#include <jansson.h>

#include "capture.h"
#include "cli.h"
#include "commands/commands.h"
#include "exit_codes.h"
#include "socket_path.h"

static json_t *doc(const char *text)
{
    json_error_t e;
    json_t *j = json_loads(text, 0, &e);
    if (!j)
        fail_msg("bad fixture: %s", e.text);
    return j;
}

static void contains(const char *text, const char *needle)
{
    if (!strstr(text, needle))
        fail_msg("output lacks '%s':\n%s", needle, text);
}

static void evaluation_summary_and_detail(void **state)
{
    json_t *r = doc("{\"e2\":0.36412345,\"argmax\":{\"kernel\":2,\"angle_deg\":35},"
                    "\"family\":\"P(4,1+,2)\",\"cost_spp\":2,"
                    "\"detail\":[{\"kernel\":0,\"angles\":[{\"angle_deg\":0,\"weight\":1,"
                    "\"e1\":0.25,\"weighted\":0.25},{\"angle_deg\":5,\"weight\":0.9,"
                    "\"e1\":0.3,\"weighted\":0.27}]}]}");
    capture c;
    eval_print(capture_begin(&c), r, false, false);
    const char *text = capture_end(&c);
    contains(text, "family            P(4,1+,2)\n");
    contains(text, "E2                0.364123\n");
    contains(text, "argmax kernel     2\n");
    contains(text, "argmax angle_deg  35.0\n");
    contains(text, "cost_spp          2.0000\n");
    assert_null(strstr(text, "weighted"));
    assert_null(strstr(text, "acuity")); /* a daemon from before evaluations named the table */
    capture_free(&c);

    /* The table the E2 uses, as the job views print it. */
    json_object_set_new(r, "acuity", doc("{\"name\":\"naiman\",\"version\":2}"));
    eval_print(capture_begin(&c), r, false, false);
    contains(capture_end(&c), "argmax angle_deg  35.0\nacuity            naiman version 2\n");
    capture_free(&c);
    eval_print(capture_begin(&c), r, false, true);
    contains(capture_end(&c), "acuity,naiman version 2");
    capture_free(&c);
    json_object_set_new(r, "acuity", doc("{\"name\":\"custom\"}"));
    eval_print(capture_begin(&c), r, false, false);
    contains(capture_end(&c), "acuity            custom\n");
    capture_free(&c);

    eval_print(capture_begin(&c), r, true, false);
    text = capture_end(&c);
    contains(text, "\nkernel 0\n");
    contains(text, "angle_deg  weight        e1  weighted\n");
    contains(text, "      0.0  1.0000  0.250000  0.250000\n");
    contains(text, "      5.0  0.9000  0.300000  0.270000\n");
    capture_free(&c);
    json_decref(r);
}

static void presets_table(void **state)
{
    json_t *r = doc("{\"presets\":[{\"name\":\"quincunx\",\"family\":\"P(1,1,2)\","
                    "\"cost_spp\":2,\"published_e2\":0.518,\"source\":\"NVIDIA\"},"
                    "{\"name\":\"flipquad\",\"family\":\"P(4,1+,2)\",\"cost_spp\":2.0,"
                    "\"published_e2\":null,\"source\":\"Akenine-Moller\"},"
                    "{\"name\":\"fliptri\",\"published_e2\":{\"laine-aila-table-2\":0.636}}]}");
    capture c;
    presets_print(capture_begin(&c), r, false);
    const char *text = capture_end(&c);
    contains(text, "name      family     cost_spp  published_e2  source\n");
    contains(text, "quincunx  P(1,1,2)       2.00         0.518  NVIDIA\n");
    contains(text, "flipquad  P(4,1+,2)      2.00             -  Akenine-Moller\n");
    contains(text, "fliptri   -                 -         0.636  -\n");
    capture_free(&c);
    json_decref(r);
    /* a bare array works too */
    r = doc("[{\"name\":\"rgss\"}]");
    presets_print(capture_begin(&c), r, false);
    contains(capture_end(&c), "rgss");
    capture_free(&c);
    json_decref(r);
}

static void jobs_table(void **state)
{
    json_t *r = doc("{\"jobs\":[{\"id\":3,\"kind\":\"optimize\",\"state\":\"running\","
                    "\"progress\":0.425,\"owner_uid\":1000,\"family\":\"P(4,1+,2)\","
                    "\"label\":\"night run\",\"best_e2\":0.3712},"
                    "{\"id\":4,\"kind\":\"compare\",\"state\":\"queued\",\"progress\":0,"
                    "\"owner_uid\":0,\"created\":1763861207.5,\"family\":null,\"label\":null,"
                    "\"best_e2\":null}]}");
    capture c;
    jobs_print(capture_begin(&c), r, false);
    const char *text = capture_end(&c);
    contains(text,
             "id  kind      state    progress  family     label       best_e2  owner  created\n");
    contains(text, " 3  optimize  running       42%  P(4,1+,2)  night run  0.371200   1000  -\n");
    contains(text, " 4  compare   queued         0%  -          -                 -      0  "
                   "2025-11-23 01:26:47\n");
    capture_free(&c);
    jobs_print(capture_begin(&c), r, true);
    text = capture_end(&c);
    assert_string_equal(text, "id,kind,state,progress,family,label,best_e2,owner,created\r\n"
                              "3,optimize,running,0.425,\"P(4,1+,2)\",night run,0.3712,1000,\r\n"
                              "4,compare,queued,0,,,,0,2025-11-23 01:26:47\r\n");
    capture_free(&c);
    json_decref(r);
}

static void one_job(void **state)
{
    json_t *j = doc("{\"id\":9,\"kind\":\"some-future-kind\",\"state\":\"done\",\"progress\":0.625,"
                    "\"finished\":1763861207,\"result\":{\"e2\":0.33,\"family\":\"P(4,1+,2)\"},"
                    "\"trace\":[{\"seconds\":0.1,\"best_e2\":0.5},{\"seconds\":1.25,"
                    "\"best_e2\":0.33}]}");
    capture c;
    job_print(capture_begin(&c), j, false);
    const char *text = capture_end(&c);
    contains(text, "id        9\n");
    contains(text, "finished  2025-11-23 01:26:47\n");
    contains(text, "progress  62%\n");
    /* a kind without a view of its own: every scalar of its result */
    contains(text, "\ne2      0.33\nfamily  P(4,1+,2)\n");
    contains(text, "trace  2 points, last at 1.25 s with E2 0.330000");
    capture_free(&c);
    job_print(capture_begin(&c), j, true);
    assert_string_equal(capture_end(&c), "key,value\r\ne2,0.33\r\nfamily,\"P(4,1+,2)\"\r\n");
    capture_free(&c);
    json_decref(j);
}

static void progress_bar(void **state)
{
    char line[160];
    json_t *j = doc("{\"state\":\"running\",\"best_e2\":0.41}");
    progress_line(line, sizeof line, 0.5, j, 10);
    assert_string_equal(line, "[#####.....]  50%  running  best E2 0.410000");
    progress_line(line, sizeof line, 7, j, 4); /* clamped */
    assert_string_equal(line, "[####] 100%  running  best E2 0.410000");
    json_decref(j);
    j = doc("{\"state\":\"queued\"}");
    progress_line(line, sizeof line, -1, j, 4);
    assert_string_equal(line, "[....]   0%  queued");
    json_decref(j);
    j = doc("{\"state\":\"running\",\"paused\":true,\"paused_seconds\":3.5}");
    progress_line(line, sizeof line, 0.25, j, 4);
    assert_string_equal(line, "[#...]  25%  running (paused: another user's turn)");
    json_decref(j);
}

static void render_summary(void **state)
{
    json_t *r = doc("{\"scene\":{\"name\":\"siemens-star\",\"width\":128,\"height\":64},"
                    "\"pattern\":{\"family\":\"P(1,1+,2)\"},\"e2\":0.518044,"
                    "\"stats\":{\"rmse\":15.88041,\"max_dev\":128.272},"
                    "\"times\":{\"pattern_seconds\":0.002,\"reference_seconds\":0.3126},"
                    "\"pixels\":{\"total\":8192,\"supersampled\":4410},"
                    "\"tiles\":{\"pattern\":{\"url\":\"/v1/tiles/a.png\"}}}");
    capture c;
    render_print(capture_begin(&c), r);
    const char *text = capture_end(&c);
    contains(text, "scene                siemens-star\n");
    contains(text, "size                 128 x 64\n");
    contains(text, "pattern              P(1,1+,2)\n");
    contains(text, "E2                   0.518044\n");
    contains(text, "RMSE (0..255)        15.880\n");
    contains(text, "max deviation        128.272\n");
    contains(text, "reference time       0.3126\n");
    contains(text, "supersampled pixels  4410 of 8192\n");
    capture_free(&c);
    json_decref(r);
}

static void catalog_views(void **state)
{
    json_t *r = doc("{\"filters\":[{\"name\":\"mitchell\",\"radius\":2.0,\"B\":0.3333333,"
                    "\"C\":0.3333333,\"default\":true},{\"name\":\"box\",\"radius\":0.5}]}");
    capture c;
    filters_print(capture_begin(&c), r, false);
    const char *text = capture_end(&c);
    contains(text, "mitchell    2.00  0.3333  0.3333  yes\n");
    contains(text, "box         0.50       -       -\n"); /* no trailing blanks */
    capture_free(&c);
    json_decref(r);

    r = doc("{\"tables\":[{\"name\":\"naiman\",\"version\":2,\"default\":true,"
            "\"description\":\"Version 2.\",\"knots\":[[0,3.93],[45,2.5]]},"
            "{\"name\":\"naiman-envelope\",\"version\":1,\"description\":\"Version 1.\","
            "\"knots\":[[0,3.93]]}]}");
    acuity_print(capture_begin(&c), r, false);
    text = capture_end(&c);
    contains(text, "naiman                 2  yes      0:3.93 45:2.5\n");
    contains(text, "naiman-envelope        1           0:3.93\n");
    contains(text, "\nnaiman: Version 2.\nnaiman-envelope: Version 1.\n");
    capture_free(&c);
    json_decref(r);

    r = doc("{\"count\":2,\"configurations\":[{\"corners\":1},{\"edges\":2}]}");
    enumerate_print(capture_begin(&c), r, false);
    assert_string_equal(capture_end(&c), "count  2\n"
                                         "   1  {\"corners\":1}\n"
                                         "   2  {\"edges\":2}\n");
    capture_free(&c);
    json_decref(r);
}

static void health_listing(void **state)
{
    json_t *r = doc("{\"version\":\"0.1.0\",\"uptime_s\":12.5,\"workers\":2,"
                    "\"jobs\":{\"queued\":1,\"done\":4},\"job_kinds\":[\"sleep\",\"optimize\"],"
                    "\"big\":[[1],[2]],\"tcp\":false,\"tcp_listener\":true}");
    capture c;
    health_print(capture_begin(&c), r, false);
    const char *text = capture_end(&c);
    /* Asked on the socket of a daemon serving the dashboard: not "tcp false" (issue 34). */
    assert_null(strstr(text, "\ntcp "));
    contains(text, "request_over_tcp  false\n");
    contains(text, "tcp_listener      true\n");
    contains(text, "version           0.1.0\n");
    contains(text, "uptime_s          12.5\n");
    contains(text, "jobs.queued       1\n");
    contains(text, "jobs.done         4\n");
    contains(text, "job_kinds         sleep, optimize\n");
    contains(text, "big               [2 items]\n");
    capture_free(&c);
    json_decref(r);
}

static void token_views(void **state)
{
    json_t *r = doc("{\"id\":7,\"token\":\"aalab_7_abc\",\"uid\":1000,\"label\":\"x\","
                    "\"created\":1700000000}");
    capture c;
    token_issued_print(capture_begin(&c), r, "http://127.0.0.1:8765/");
    const char *text = capture_end(&c);
    contains(text, "token aalab_7_abc (id 7;");
    contains(text, "aalab token revoke 7");
    contains(text, "dashboard: http://127.0.0.1:8765/#token=aalab_7_abc\n");
    capture_free(&c);
    token_issued_print(capture_begin(&c), r, NULL);
    text = capture_end(&c);
    assert_null(strstr(text, "dashboard"));
    capture_free(&c);
    json_decref(r);
    r = doc("{\"tokens\":[{\"id\":3,\"uid\":1001,\"label\":\"laptop\","
            "\"created\":1700000000}]}");
    tokens_print(capture_begin(&c), r, false);
    text = capture_end(&c);
    contains(text, "laptop");
    contains(text, "1001");
    capture_free(&c);
    json_decref(r);
}

static void error_lines(void **state)
{
    capture c;
    cli_print_error(capture_begin(&c), 400,
                    "{\"error\":{\"code\":\"invalid_field\",\"message\":\"weights must sum to "
                    "1\",\"field\":\"pattern.kernels[0]\"}}");
    assert_string_equal(capture_end(&c), "aalab: server answered 400 invalid_field: weights must "
                                         "sum to 1 (field pattern.kernels[0])\n");
    capture_free(&c);
    cli_print_error(capture_begin(&c), 502, "Bad Gateway");
    assert_string_equal(capture_end(&c), "aalab: server answered 502: Bad Gateway\n");
    capture_free(&c);
}

static void exit_codes(void **state)
{
    assert_int_equal(exit_code_for_status(200), EXIT_OK);
    assert_int_equal(exit_code_for_status(202), EXIT_OK);
    assert_int_equal(exit_code_for_status(404), EXIT_CLIENT_4XX);
    assert_int_equal(exit_code_for_status(429), EXIT_CLIENT_4XX);
    assert_int_equal(exit_code_for_status(500), EXIT_SERVER_5XX);
    assert_int_equal(exit_code_for_status(503), EXIT_SERVER_5XX);
    assert_int_equal(EXIT_USAGE, 1);
    assert_int_equal(EXIT_NO_CONNECT, 4);
    assert_int_equal(EXIT_JOB_FAILED, 5);
}

static void url_escaping(void **state)
{
    char *s = url_escape_segment("a b/../c~_.-Z9");
    assert_string_equal(s, "a%20b%2F..%2Fc~_.-Z9");
    free(s);
}

static void socket_paths(void **state)
{
    char out[256], dir[128];
    unsetenv("AALAB_SOCKET");
    unsetenv("XDG_RUNTIME_DIR");
    assert_int_equal(socket_path_resolve(NULL, out, sizeof out), 0);
    assert_string_equal(out, "/run/aalab/aalabd.sock");
    assert_int_equal(socket_path_resolve("/x/y.sock", out, sizeof out), 0);
    assert_string_equal(out, "/x/y.sock");
    setenv("AALAB_SOCKET", "/env.sock", 1);
    assert_int_equal(socket_path_resolve(NULL, out, sizeof out), 0);
    assert_string_equal(out, "/env.sock");
    assert_int_equal(socket_path_resolve("/flag.sock", out, sizeof out), 0);
    assert_string_equal(out, "/flag.sock"); /* the flag beats the environment */
    unsetenv("AALAB_SOCKET");

    /* $XDG_RUNTIME_DIR/aalab/aalabd.sock only when a socket is there */
    snprintf(dir, sizeof dir, "%s/aalab-sock-XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
    assert_non_null(mkdtemp(dir));
    setenv("XDG_RUNTIME_DIR", dir, 1);
    assert_int_equal(socket_path_resolve(NULL, out, sizeof out), 0);
    assert_string_equal(out, "/run/aalab/aalabd.sock");
    char sub[200], sock[220];
    snprintf(sub, sizeof sub, "%s/aalab", dir);
    assert_int_equal(mkdir(sub, 0700), 0);
    snprintf(sock, sizeof sock, "%s/aalabd.sock", sub);
    int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    struct sockaddr_un addr = {.sun_family = AF_UNIX};
    assert_true(strlen(sock) < sizeof addr.sun_path);
    memcpy(addr.sun_path, sock, strlen(sock) + 1);
    assert_int_equal(bind(fd, (struct sockaddr *)&addr, sizeof addr), 0);
    assert_int_equal(socket_path_resolve(NULL, out, sizeof out), 0);
    assert_string_equal(out, sock);
    close(fd);
    unlink(sock);
    rmdir(sub);
    rmdir(dir);
    unsetenv("XDG_RUNTIME_DIR");
    char tiny[8];
    assert_int_equal(socket_path_resolve("/a/long/path.sock", tiny, sizeof tiny), -1);
}

static void no_daemon_message(void **state)
{
    char tried[512];
    setenv("AALAB_SOCKET", "/env/a.sock", 1);
    socket_path_tried(NULL, tried, sizeof tried);
    assert_string_equal(tried, "/env/a.sock ($AALAB_SOCKET)");
    socket_path_tried("/flag.sock", tried, sizeof tried);
    assert_string_equal(tried, "/flag.sock (--socket)");
    unsetenv("AALAB_SOCKET");
    setenv("XDG_RUNTIME_DIR", "/run/user/1000", 1);
    socket_path_tried(NULL, tried, sizeof tried);
    assert_string_equal(tried, "/run/user/1000/aalab/aalabd.sock, /run/aalab/aalabd.sock");
    unsetenv("XDG_RUNTIME_DIR");
    socket_path_tried(NULL, tried, sizeof tried);
    char want[128];
    snprintf(want, sizeof want, "/tmp/aalab-%u/aalabd.sock, /run/aalab/aalabd.sock",
             (unsigned)geteuid());
    assert_string_equal(tried, want);

    capture c;
    cli_print_no_daemon(capture_begin(&c), "/nonexistent/aalabd.sock", "/a.sock, /b.sock");
    const char *text = capture_end(&c);
    contains(text, "aalab: cannot reach the daemon at /nonexistent/aalabd.sock: no such socket\n");
    contains(text, "socket paths tried: /a.sock, /b.sock\n");
    contains(text, "'aalabd'");
    contains(text, "systemctl start aalabd.socket");
    contains(text, "--socket PATH or $AALAB_SOCKET");
    capture_free(&c);
    cli_print_no_daemon(capture_begin(&c), "/", "/");
    contains(capture_end(&c), ": that file is not a socket\n");
    capture_free(&c);
}

static void jobs_query_string(void **state)
{
    cli_args a = {0};
    char q[128];
    assert_int_equal(jobs_query(&a, q, sizeof q), 0);
    assert_string_equal(q, "");
    a.kind = "family-sweep";
    assert_int_equal(jobs_query(&a, q, sizeof q), 0);
    assert_string_equal(q, "?kind=family-sweep");
    a.state = "done";
    a.kind = "a b&c";
    a.limit = 5;
    a.has_limit = true;
    assert_int_equal(jobs_query(&a, q, sizeof q), 0);
    assert_string_equal(q, "?state=done&kind=a%20b%26c&limit=5");
    char tiny[8];
    assert_int_equal(jobs_query(&a, tiny, sizeof tiny), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(evaluation_summary_and_detail),
        cmocka_unit_test(presets_table),
        cmocka_unit_test(jobs_table),
        cmocka_unit_test(one_job),
        cmocka_unit_test(progress_bar),
        cmocka_unit_test(render_summary),
        cmocka_unit_test(catalog_views),
        cmocka_unit_test(health_listing),
        cmocka_unit_test(token_views),
        cmocka_unit_test(error_lines),
        cmocka_unit_test(exit_codes),
        cmocka_unit_test(url_escaping),
        cmocka_unit_test(socket_paths),
        cmocka_unit_test(no_daemon_message),
        cmocka_unit_test(jobs_query_string),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
