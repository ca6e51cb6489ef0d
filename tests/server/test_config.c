/* aalabd flags: embedded defaults, every flag, bad values. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "config.h"

static int parse(aalab_config *c, int argc, char **argv)
{
    FILE *null = fopen("/dev/null", "w");
    int rc = config_parse_args(c, argc, argv, null, null);
    fclose(null);
    return rc;
}

static void test_defaults(void **state)
{
    (void)state;
    aalab_config c;
    config_defaults(&c);
    assert_true(strlen(c.socket_path) > 0 && strstr(c.socket_path, "aalabd.sock"));
    assert_true(strlen(c.state_dir) > 0);
    assert_true(c.workers >= 1);
    assert_int_equal(c.tcp_port, 0);
    assert_true(c.max_body >= 1024 && c.queue_size > 0 && c.user_quota > 0);
    assert_int_equal(c.render_max_pixels, 512 * 512);
    assert_true(c.render_seconds == 20.0);
    char *argv[] = {"aalabd"};
    assert_int_equal(parse(&c, 1, argv), 0);
    /* Sharing defaults: half the workers (at least 1), 60 s slices, 256 MiB, 90 days. */
    assert_int_equal(c.user_workers, c.workers / 2 > 1 ? c.workers / 2 : 1);
    assert_true(c.job_slice == 60.0 && c.keep_days == 90.0);
    assert_true(c.user_store_bytes == 256u << 20 && c.max_spec_bytes == 2u << 20);
    assert_int_equal(c.user_evaluates, 2);
    assert_int_equal(c.user_renders, 1);
    assert_int_equal(c.user_connections, 32);
    assert_int_equal(c.token_connections, 32);
    assert_false(c.test_kinds);
}

static void test_sharing_flags(void **state)
{
    (void)state;
    aalab_config c;
    config_defaults(&c);
    char *argv[] = {"aalabd",
                    "--workers",
                    "8",
                    "--job-slice=2.5",
                    "--enable-test-kinds",
                    "--max-job-seconds",
                    "120",
                    "--user-store-bytes",
                    "65536",
                    "--keep-days=0.5",
                    "--user-renders",
                    "3"};
    assert_int_equal(parse(&c, 12, argv), 0);
    assert_int_equal(c.user_workers, 4); /* auto: half of 8 */
    assert_true(c.job_slice == 2.5 && c.max_job_seconds == 120.0 && c.keep_days == 0.5);
    assert_true(c.test_kinds);
    assert_true(c.user_store_bytes == 65536);
    assert_int_equal(c.user_renders, 3);
    char *bad[] = {"aalabd", "--job-slice", "0"};
    assert_int_equal(parse(&c, 3, bad), -1);
    char *bad2[] = {"aalabd", "--user-store-bytes", "12"};
    assert_int_equal(parse(&c, 3, bad2), -1);
}

static void test_flags(void **state)
{
    (void)state;
    aalab_config c;
    config_defaults(&c);
    char *argv[] = {"aalabd",
                    "--socket",
                    "/tmp/x.sock",
                    "--tcp",
                    "127.0.0.1:99",
                    "--state-dir",
                    "/tmp/st",
                    "--workers=3",
                    "--web-dir",
                    "/tmp/web",
                    "--queue-size",
                    "7",
                    "--user-quota",
                    "2",
                    "--socket-group",
                    "aalab",
                    "--max-body",
                    "4096",
                    "--render-max-pixels=4096",
                    "--render-seconds",
                    "0.5"};
    assert_int_equal(parse(&c, (int)(sizeof argv / sizeof argv[0]), argv), 0);
    assert_string_equal(c.socket_path, "/tmp/x.sock");
    assert_string_equal(c.tcp_host, "127.0.0.1");
    assert_int_equal(c.tcp_port, 99);
    assert_string_equal(c.state_dir, "/tmp/st");
    assert_int_equal(c.workers, 3);
    assert_string_equal(c.web_dir, "/tmp/web");
    assert_int_equal(c.queue_size, 7);
    assert_int_equal(c.user_quota, 2);
    assert_string_equal(c.socket_group, "aalab");
    assert_int_equal(c.max_body, 4096);
    assert_int_equal(c.render_max_pixels, 4096);
    assert_true(c.render_seconds == 0.5);
}

/* The Slurm executor's flags and their defaults (README, aalabd --help). */
static void test_slurm_flags(void **state)
{
    (void)state;
    aalab_config c;
    config_defaults(&c);
    char *none[] = {"aalabd"};
    assert_int_equal(parse(&c, 1, none), 0);
    assert_string_equal(c.slurm.shared_dir, ""); /* not configured */
    assert_string_equal(c.slurm.partition, "");
    assert_int_equal(c.slurm.max_tasks, 64);
    assert_int_equal(c.slurm.time_limit_minutes, 60);
    assert_string_equal(c.slurm.sbatch_args, "");
    assert_true(c.slurm.poll_seconds == 2.0);
    /* aalab-worker beside this executable. */
    const char *w = c.slurm.worker;
    assert_true(strlen(w) > 13 && w[0] == '/' && !strcmp(w + strlen(w) - 13, "/aalab-worker"));
    char *argv[] = {"aalabd",
                    "--slurm-shared-dir",
                    "/shared/aalab",
                    "--slurm-partition=short",
                    "--slurm-max-tasks",
                    "8",
                    "--slurm-time-limit",
                    "15",
                    "--slurm-sbatch-args",
                    "--account=lab --qos=low",
                    "--slurm-worker",
                    "/opt/aalab/bin/aalab-worker",
                    "--slurm-poll=0.5"};
    assert_int_equal(parse(&c, (int)(sizeof argv / sizeof argv[0]), argv), 0);
    assert_string_equal(c.slurm.shared_dir, "/shared/aalab");
    assert_string_equal(c.slurm.partition, "short");
    assert_int_equal(c.slurm.max_tasks, 8);
    assert_int_equal(c.slurm.time_limit_minutes, 15);
    assert_string_equal(c.slurm.sbatch_args, "--account=lab --qos=low");
    assert_string_equal(c.slurm.worker, "/opt/aalab/bin/aalab-worker");
    assert_true(c.slurm.poll_seconds == 0.5);
    char *bad[][2] = {{"--slurm-shared-dir", "relative/dir"},
                      {"--slurm-max-tasks", "0"},
                      {"--slurm-time-limit", "0"},
                      {"--slurm-poll", "0"},
                      {"--slurm-worker", ""}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        config_defaults(&c);
        char *a[] = {"aalabd", bad[i][0], bad[i][1]};
        if (parse(&c, 3, a) != -1)
            fail_msg("accepted %s %s", bad[i][0], bad[i][1]);
    }
}

/* The limits of the second multi-user attack and the inline evaluate threshold (README, sharing
 * table; docs/http.md), their defaults and their ranges. */
static void test_limit_flags(void **state)
{
    (void)state;
    aalab_config c;
    config_defaults(&c);
    char *none[] = {"aalabd"};
    assert_int_equal(parse(&c, 1, none), 0);
    assert_int_equal(c.inline_work, 2048);
    assert_int_equal(c.user_tokens, 32);
    assert_int_equal(c.user_body_bytes, 32u << 20);
    assert_int_equal(c.answer_timeout, 60);
    char *argv[] = {"aalabd", "--inline-work",    "0", "--user-tokens", "4", "--user-body-bytes",
                    "65536",  "--answer-timeout", "3"};
    config_defaults(&c);
    assert_int_equal(parse(&c, (int)(sizeof argv / sizeof argv[0]), argv), 0);
    assert_int_equal(c.inline_work, 0);
    assert_int_equal(c.user_tokens, 4);
    assert_int_equal(c.user_body_bytes, 65536);
    assert_int_equal(c.answer_timeout, 3);
    const char *bad[][2] = {{"--inline-work", "-1"},
                            {"--user-tokens", "0"},
                            {"--user-body-bytes", "10"},
                            {"--answer-timeout", "0"},
                            {"--answer-timeout", "x"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char *one[] = {"aalabd", (char *)bad[i][0], (char *)bad[i][1]};
        config_defaults(&c);
        assert_int_not_equal(parse(&c, 3, one), 0);
    }
}

static void test_bad_flags(void **state)
{
    (void)state;
    char *cases[][2] = {
        {"--workers", "0"},          {"--workers", "x"},        {"--tcp", "nocolon"},
        {"--tcp", "h:70000"},        {"--bogus", "1"},          {"--max-body", "10"},
        {"--queue-size", "-1"},      {"--tcp", ":80"},          {"--render-max-pixels", "0"},
        {"--render-seconds", "nan"}, {"--render-seconds", "0"}, {"--render-seconds", "1e9"},
        {"--render-seconds", "2s"}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        aalab_config c;
        config_defaults(&c);
        char *argv[] = {"aalabd", cases[i][0], cases[i][1]};
        if (parse(&c, 3, argv) != -1)
            fail_msg("accepted %s %s", cases[i][0], cases[i][1]);
    }
    aalab_config c;
    config_defaults(&c);
    char *argv[] = {"aalabd", "--socket"};
    assert_int_equal(parse(&c, 2, argv), -1);
    char *help[] = {"aalabd", "--help"};
    assert_int_equal(parse(&c, 2, help), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),      cmocka_unit_test(test_flags),
        cmocka_unit_test(test_sharing_flags), cmocka_unit_test(test_slurm_flags),
        cmocka_unit_test(test_bad_flags),     cmocka_unit_test(test_limit_flags),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
