/* The command runner (server/cluster/cluster_command.c): output capture, exit codes, timeout,
 * a command that cannot start. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

#include "cluster_command.h"

static void test_captures_output_and_exit_code(void **state)
{
    (void)state;
    char *argv[] = {"sh", "-c", "echo out; echo err >&2; exit 3", NULL};
    cluster_output o;
    aa_error err = {0};
    assert_int_equal(cluster_command_run(argv, 10, &o, &err), AA_OK);
    assert_int_equal(o.exit_code, 3);
    assert_false(o.timed_out);
    assert_string_equal(o.out, "out\n");
    assert_string_equal(o.err, "err\n");
    cluster_output_free(&o);
    /* No shell: the argument is passed as is. */
    char *echo[] = {"echo", "a;b $HOME", NULL};
    assert_int_equal(cluster_command_run(echo, 10, &o, &err), AA_OK);
    assert_string_equal(o.out, "a;b $HOME\n");
    assert_string_equal(o.err, "");
    cluster_output_free(&o);
}

static void test_timeout_kills_the_command_and_its_children(void **state)
{
    (void)state;
    /* The child keeps the pipe open: the timeout must not wait for it. */
    char *argv[] = {"sh", "-c", "sleep 30 & sleep 30", NULL};
    cluster_output o;
    aa_error err = {0};
    double t0 = aa_monotonic_seconds();
    assert_int_equal(cluster_command_run(argv, 0.3, &o, &err), AA_OK);
    assert_true(aa_monotonic_seconds() - t0 < 5);
    assert_true(o.timed_out);
    assert_int_equal(o.exit_code, 128 + 9);
    cluster_output_free(&o);
}

static void test_missing_command(void **state)
{
    (void)state;
    char *argv[] = {"aalab-no-such-command", NULL};
    cluster_output o;
    aa_error err = {0};
    assert_int_equal(cluster_command_run(argv, 5, &o, &err), AA_EINVAL);
    assert_non_null(strstr(err.message, "aalab-no-such-command"));
    assert_null(o.out);
    char line[16];
    cluster_first_line("  first line  \nsecond", line, sizeof line);
    assert_string_equal(line, "first line");
    cluster_first_line("a very long first line", line, 7);
    assert_string_equal(line, "a very");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_captures_output_and_exit_code),
        cmocka_unit_test(test_timeout_kills_the_command_and_its_children),
        cmocka_unit_test(test_missing_command),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
