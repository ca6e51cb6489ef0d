/* cli_parse: commands, options in any position, per-command option checks, number parsing. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "args.h"

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

static void eval_with_options(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "eval", "quincunx", "--filter", "mitchell:B=0.3,C=0.35",
                           "--acuity=uniform", "--detail", "--json"),
                     0);
    assert_int_equal(a.command, CMD_EVAL);
    assert_string_equal(a.target, "quincunx");
    assert_string_equal(a.filter, "mitchell:B=0.3,C=0.35");
    assert_string_equal(a.acuity, "uniform");
    assert_true(a.detail);
    assert_true(a.json);
    assert_null(a.socket_path);
    assert_true(a.timeout_s == 30);
}

static void global_options_before_command(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(
        PARSE(&a, "--socket", "/tmp/x.sock", "--timeout", "2.5", "-s/tmp/y.sock", "health"), 0);
    assert_int_equal(a.command, CMD_HEALTH);
    assert_string_equal(a.socket_path, "/tmp/y.sock"); /* the last one wins */
    assert_true(a.timeout_s == 2.5);
}

static void optimize_family_and_numbers(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "optimize", "--family", "P(4,1+,2)", "--seeds", "64",
                           "--max-seconds", "1.5", "--rng-seed", "7", "--mode", "both", "--method",
                           "smooth", "-w"),
                     0);
    assert_int_equal(a.command, CMD_OPTIMIZE);
    assert_string_equal(a.family, "P(4,1+,2)");
    assert_true(a.has_seeds && a.seeds == 64);
    assert_true(a.has_max_seconds && a.max_seconds == 1.5);
    assert_true(a.has_rng_seed && a.rng_seed == 7);
    assert_string_equal(a.mode, "both");
    assert_string_equal(a.method, "smooth");
    assert_true(a.wait);
}

static void optimize_needs_exactly_one_source(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "optimize"), -1);
    assert_non_null(strstr(err, "exactly one of --family or --pattern"));
    assert_int_equal(PARSE(&a, "optimize", "--family", "P(4,1+,2)", "--pattern", "x.json"), -1);
    assert_non_null(strstr(err, "exactly one"));
}

static void bad_numbers_are_usage_errors(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "optimize", "--family", "F", "--seeds", "0"), -1);
    assert_non_null(strstr(err, "--seeds"));
    assert_int_equal(PARSE(&a, "optimize", "--family", "F", "--seeds", "12x"), -1);
    assert_int_equal(PARSE(&a, "optimize", "--family", "F", "--max-seconds", "nan"), -1);
    assert_int_equal(PARSE(&a, "optimize", "--family", "F", "--max-seconds", "-1"), -1);
    assert_int_equal(PARSE(&a, "optimize", "--family", "F", "--rng-seed", "-3"), -1);
    assert_int_equal(PARSE(&a, "optimize", "--family", "F", "--mode", "all"), -1);
    assert_non_null(strstr(err, "--mode"));
    assert_int_equal(PARSE(&a, "optimize", "--family", "F", "--method", "newton"), -1);
    assert_non_null(strstr(err, "--method"));
    assert_int_equal(PARSE(&a, "optimize", "--family", "F", "--executor", "cloud"), -1);
    assert_non_null(strstr(err, "--executor"));
    assert_int_equal(PARSE(&a, "optimize", "--family", "F", "--executor", "slurm"), 0);
    assert_string_equal(a.executor, "slurm");
    assert_int_equal(PARSE(&a, "health", "--timeout", "0"), -1);
}

static void option_of_another_command_is_rejected(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "jobs", "--detail"), -1);
    assert_non_null(strstr(err, "'--detail' does not apply to 'jobs'"));
    /* also when the option comes before the command */
    assert_int_equal(PARSE(&a, "--seeds", "3", "eval", "rgss"), -1);
    assert_non_null(strstr(err, "does not apply to 'eval'"));
}

static void unknown_things(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "frobnicate"), -1);
    assert_non_null(strstr(err, "unknown command 'frobnicate'"));
    assert_int_equal(PARSE(&a, "health", "--colour"), -1);
    assert_non_null(strstr(err, "unknown option '--colour'"));
    assert_int_equal(PARSE(&a, "health", "-x"), -1);
    assert_int_equal(PARSE(&a, "--json"), -1); /* no command */
    assert_non_null(strstr(err, "no command"));
    assert_int_equal(PARSE(&a, "eval", "--filter"), -1);
    assert_non_null(strstr(err, "needs a value"));
    assert_int_equal(PARSE(&a, "health", "--json=yes"), -1);
    assert_non_null(strstr(err, "takes no value"));
}

static void job_ids(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "job", "42"), 0);
    assert_int_equal(a.command, CMD_JOB);
    assert_string_equal(a.target, "42");
    assert_int_equal(PARSE(&a, "cancel", "7"), 0);
    assert_int_equal(a.command, CMD_CANCEL);
    assert_int_equal(PARSE(&a, "job"), -1);
    assert_int_equal(PARSE(&a, "job", "j-7f3a_B"), 0); /* ids are opaque strings */
    assert_int_equal(PARSE(&a, "job", "../3"), -1);
    assert_non_null(strstr(err, "wants a job ID"));
    assert_int_equal(PARSE(&a, "cancel", "a/b"), -1);
    assert_int_equal(PARSE(&a, "cancel", "3?x=1"), -1);
    assert_int_equal(PARSE(&a, "job", ""), -1);
    assert_int_equal(
        PARSE(&a, "job", "x123456789x123456789x123456789x123456789x123456789x123456789x1234"), -1);
    assert_int_equal(PARSE(&a, "job", "1", "2"), -1);
    assert_non_null(strstr(err, "unexpected argument '2'"));
    assert_int_equal(PARSE(&a, "jobs", "3"), -1);
}

static void export_formats(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "export", "5"), 0);
    assert_string_equal(a.format, "json"); /* default */
    assert_int_equal(PARSE(&a, "export", "5", "--format", "d3d12", "-o", "out.txt"), 0);
    assert_string_equal(a.format, "d3d12");
    assert_string_equal(a.output, "out.txt");
    assert_int_equal(PARSE(&a, "export", "5", "-fvulkan"), 0);
    assert_string_equal(a.format, "vulkan");
    assert_int_equal(PARSE(&a, "export", "5", "--format", "png"), -1);
}

/* Point sets: export's new formats, convert, and how to read a point-set pattern argument. */
static void point_set_options(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "export", "5", "--format", "csv"), 0);
    assert_string_equal(a.format, "csv");
    assert_int_equal(PARSE(&a, "export", "5", "--format", "points-json"), 0);
    assert_int_equal(PARSE(&a, "convert", "flipquad", "--format", "xyw", "-o", "fq.txt"), 0);
    assert_int_equal(a.command, CMD_CONVERT);
    assert_string_equal(a.target, "flipquad");
    assert_string_equal(a.format, "xyw");
    assert_string_equal(a.output, "fq.txt");
    assert_int_equal(PARSE(&a, "convert"), -1);
    assert_non_null(strstr(err, "'convert' needs a preset NAME"));
    assert_int_equal(PARSE(&a, "eval", "p.dat", "--tile", "4", "--kernel", "2", "--weights",
                           "filter", "--points-format", "xyw"),
                     0);
    assert_int_equal(a.tile, 4);
    assert_int_equal(a.kernel, 2);
    assert_string_equal(a.weights, "filter");
    assert_string_equal(a.points_format, "xyw");
    assert_int_equal(PARSE(&a, "render", "--pattern", "p.csv", "--tile", "2", "-o", "t.png"), 0);
    assert_int_equal(PARSE(&a, "optimize", "--pattern", "p.csv", "--weights", "equal"), 0);
    assert_int_equal(PARSE(&a, "eval", "p.dat", "--tile", "17"), -1);
    assert_string_equal(err, "--tile wants the tile size in pixels, 1..16, got '17'");
    assert_int_equal(PARSE(&a, "eval", "p.dat", "--kernel", "0"), -1);
    assert_int_equal(PARSE(&a, "eval", "p.dat", "--weights", "some"), -1);
    assert_string_equal(err, "--weights wants file, filter or equal, got 'some'");
    assert_int_equal(PARSE(&a, "eval", "p.dat", "--points-format", "dat"), -1);
    assert_int_equal(PARSE(&a, "export", "5", "--tile", "2"), -1);
    assert_non_null(strstr(err, "does not apply to 'export'"));
    assert_int_equal(PARSE(&a, "eval", "rgss", "--format", "csv"), -1);
    assert_int_equal(PARSE(&a, "optimize", "--family", "P(4,1+,2)", "--tile", "2"), -1);
    assert_non_null(strstr(err, "not a --family"));
    /* the sampling tools' formats and sets */
    assert_int_equal(PARSE(&a, "export", "5", "--format", "metal"), 0);
    assert_int_equal(PARSE(&a, "convert", "rgss", "--format", "bin"), 0);
    assert_int_equal(PARSE(&a, "convert", "rgss", "--format", "rps"), 0);
    assert_int_equal(PARSE(&a, "eval", "p", "--points-format", "rps", "--set", "0"), 0);
    assert_string_equal(a.points_format, "rps");
    assert_string_equal(a.set, "0");
    assert_int_equal(PARSE(&a, "analyze", "p.dat", "--set", "all"), 0);
    assert_string_equal(a.set, "all");
    assert_int_equal(PARSE(&a, "eval", "p.dat", "--set", "all"), -1);
    assert_non_null(strstr(err, "--set all is for 'aalab analyze'"));
    assert_int_equal(PARSE(&a, "eval", "p.dat", "--set", "-1"), -1);
    assert_non_null(strstr(err, "--set wants a set number"));
}

static void render_size_and_output(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "render", "--pattern", "quincunx", "--scene", "siemens-star",
                           "--size", "256x128", "-o", "tile.png"),
                     0);
    assert_int_equal(a.width, 256);
    assert_int_equal(a.height, 128);
    assert_string_equal(a.output, "tile.png");
    assert_string_equal(a.image, "pattern");
    assert_int_equal(PARSE(&a, "render", "--pattern", "q"), -1); /* neither -o nor --json */
    assert_int_equal(PARSE(&a, "render", "--pattern", "q", "--json"), 0);
    assert_int_equal(PARSE(&a, "render", "--pattern", "q", "-o", "t", "--size", "0x5"), -1);
    assert_int_equal(PARSE(&a, "render", "--pattern", "q", "-o", "t", "--size", "256"), -1);
    assert_int_equal(PARSE(&a, "render", "--pattern", "q", "-o", "t", "--size", "x256"), -1);
    assert_int_equal(PARSE(&a, "render", "--pattern", "q", "-o", "t", "--size", "9x99999"), -1);
    assert_int_equal(PARSE(&a, "render", "--pattern", "q", "-o", "t", "--image", "diff"), -1);
}

static void help_forms(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "--help"), 0);
    assert_int_equal(a.command, CMD_HELP);
    assert_null(a.target);
    assert_int_equal(PARSE(&a, "optimize", "-h"), 0); /* help wins over missing options */
    assert_int_equal(a.command, CMD_HELP);
    assert_string_equal(a.target, "optimize");
    assert_int_equal(PARSE(&a, "help", "render"), 0);
    assert_string_equal(a.target, "render");
    assert_int_equal(PARSE(&a, "help", "nope"), -1);
    assert_int_equal(PARSE(&a, "--version"), 0);
    assert_int_equal(a.command, CMD_VERSION);
    assert_int_equal(PARSE(&a, "version"), 0);
    assert_int_equal(a.command, CMD_VERSION);
}

static void double_dash_ends_options(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "eval", "--", "-odd-name.json"), 0);
    assert_string_equal(a.target, "-odd-name.json");
}

static void submit_forms(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "submit", "spec.json", "--wait", "--poll", "0.5"), 0);
    assert_int_equal(a.command, CMD_SUBMIT);
    assert_string_equal(a.target, "spec.json");
    assert_true(a.wait && a.poll_s == 0.5);
    assert_int_equal(PARSE(&a, "submit", "-"), 0);
    assert_int_equal(PARSE(&a, "submit"), -1);
    assert_non_null(strstr(err, "job spec"));
    assert_int_equal(PARSE(&a, "submit", "s.json", "--seeds", "3"), -1);
}

static void enumerate_forms(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "enumerate", "--family", "P(4,1+,n)", "--cost", "1.25"), 0);
    assert_int_equal(a.command, CMD_ENUMERATE);
    assert_string_equal(a.family, "P(4,1+,n)");
    assert_true(a.has_cost && a.cost == 1.25);
    assert_int_equal(PARSE(&a, "enumerate", "--family", "P(4,1+,1.5)"), 0);
    assert_false(a.has_cost);
    assert_int_equal(PARSE(&a, "enumerate", "--cost", "1"), -1);
    assert_int_equal(PARSE(&a, "enumerate", "--family", "F", "--cost", "0"), -1);
    assert_int_equal(PARSE(&a, "optimize", "--family", "F", "--cost", "1"), -1);
    assert_int_equal(PARSE(&a, "filters"), 0);
    assert_int_equal(a.command, CMD_FILTERS);
    assert_int_equal(PARSE(&a, "acuity", "naiman"), -1);
}

static void number_helpers(void **state)
{
    long l;
    double d;
    int w, h;
    assert_int_equal(parse_long("12", 0, 100, &l), 0);
    assert_int_equal(l, 12);
    assert_int_equal(parse_long("", 0, 100, &l), -1);
    assert_int_equal(parse_long("101", 0, 100, &l), -1);
    assert_int_equal(parse_long("99999999999999999999999", 0, 100, &l), -1);
    assert_int_equal(parse_double("1e3", 0, 1e4, &d), 0);
    assert_true(d == 1000);
    assert_int_equal(parse_double("inf", 0, 1e308, &d), -1);
    assert_int_equal(parse_double("1e999", 0, 1e308, &d), -1);
    assert_int_equal(parse_size("16x9", &w, &h), 0);
    assert_int_equal(w, 16);
    assert_int_equal(h, 9);
    assert_int_equal(parse_size("16x", &w, &h), -1);
    assert_int_equal(parse_size("-4x4", &w, &h), -1);
}

static void token_forms(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "token", "--label", "laptop"), 0);
    assert_int_equal(a.command, CMD_TOKEN);
    assert_null(a.target);
    assert_string_equal(a.label, "laptop");
    assert_int_equal(PARSE(&a, "token", "list", "--json"), 0);
    assert_string_equal(a.target, "list");
    assert_int_equal(PARSE(&a, "token", "revoke", "12"), 0);
    assert_string_equal(a.target2, "12");
    assert_int_equal(PARSE(&a, "token", "revoke"), -1);
    assert_non_null(strstr(err, "token ID"));
    assert_int_equal(PARSE(&a, "token", "revoke", "../x"), -1);
    assert_int_equal(PARSE(&a, "token", "list", "3"), -1);
    assert_int_equal(PARSE(&a, "token", "burn"), -1);
    assert_int_equal(PARSE(&a, "token", "list", "--label", "x"), -1);
    assert_int_equal(PARSE(&a, "jobs", "--label", "x"), -1); /* --label is token's only */
    assert_int_equal(PARSE(&a, "job", "1", "2"), -1);        /* one positional elsewhere */
}

static void quiet_wait_and_trace(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(PARSE(&a, "optimize", "-q", "--family", "P(4,1+,2)"), 0);
    assert_true(a.quiet);
    assert_false(a.wait);
    assert_int_equal(PARSE(&a, "submit", "spec.json", "--quiet", "--wait"), 0);
    assert_true(a.quiet && a.wait);
    assert_int_equal(PARSE(&a, "jobs", "-q"), -1);
    assert_string_equal(err, "option '--quiet' does not apply to 'jobs'");

    assert_int_equal(PARSE(&a, "wait", "17", "--poll", "0.5", "--trace"), 0);
    assert_int_equal(a.command, CMD_WAIT);
    assert_string_equal(a.target, "17");
    assert_true(a.poll_s == 0.5 && a.trace);
    assert_int_equal(PARSE(&a, "wait"), -1);
    assert_string_equal(err, "'wait' needs a job ID");
    assert_int_equal(PARSE(&a, "wait", "../etc"), -1);
    assert_int_equal(PARSE(&a, "job", "3", "--trace", "--csv"), 0);
    assert_true(a.trace && a.csv);
    assert_int_equal(PARSE(&a, "jobs", "--trace"), -1);
    assert_string_equal(err, "option '--trace' does not apply to 'jobs'");
}

static void csv_where_tables_are(void **state)
{
    cli_args a;
    char err[256] = "";
    const char *table_commands[] = {"presets", "jobs",  "filters", "acuity",
                                    "health",  "token", NULL};
    for (const char **c = table_commands; *c; c++) {
        assert_int_equal(PARSE(&a, *c, "--csv"), 0);
        assert_true(a.csv);
    }
    assert_int_equal(PARSE(&a, "--csv", "eval", "rgss", "--detail"), 0);
    assert_int_equal(PARSE(&a, "enumerate", "--family", "P(4,1+,n)", "--cost", "1", "--csv"), 0);
    assert_int_equal(PARSE(&a, "jobs", "--csv", "--json"), -1);
    assert_string_equal(err, "give --csv or --json, not both");
    assert_int_equal(PARSE(&a, "export", "3", "--csv"), -1);
    assert_string_equal(err, "option '--csv' does not apply to 'export'");
    assert_int_equal(PARSE(&a, "optimize", "--family", "P(4,1+,2)", "--csv"), -1);
}

static void jobs_filters(void **state)
{
    cli_args a;
    char err[256] = "";
    assert_int_equal(
        PARSE(&a, "jobs", "--state", "running", "--kind", "family-sweep", "--limit", "20"), 0);
    assert_string_equal(a.state, "running");
    assert_string_equal(a.kind, "family-sweep");
    assert_true(a.has_limit && a.limit == 20);
    assert_int_equal(PARSE(&a, "jobs", "--state", "sleeping"), -1);
    assert_string_equal(err, "--state wants queued, running, done, failed, cancelled or "
                             "interrupted, got 'sleeping'");
    assert_int_equal(PARSE(&a, "jobs", "--limit", "0"), -1);
    assert_string_equal(err, "--limit wants a positive integer, got '0'");
    assert_int_equal(PARSE(&a, "jobs", "--limit", "ten"), -1);
    assert_int_equal(PARSE(&a, "jobs", "--kind", ""), -1);
    assert_int_equal(PARSE(&a, "job", "3", "--state", "done"), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(eval_with_options),
        cmocka_unit_test(global_options_before_command),
        cmocka_unit_test(optimize_family_and_numbers),
        cmocka_unit_test(optimize_needs_exactly_one_source),
        cmocka_unit_test(bad_numbers_are_usage_errors),
        cmocka_unit_test(option_of_another_command_is_rejected),
        cmocka_unit_test(unknown_things),
        cmocka_unit_test(job_ids),
        cmocka_unit_test(export_formats),
        cmocka_unit_test(point_set_options),
        cmocka_unit_test(render_size_and_output),
        cmocka_unit_test(help_forms),
        cmocka_unit_test(double_dash_ends_options),
        cmocka_unit_test(submit_forms),
        cmocka_unit_test(enumerate_forms),
        cmocka_unit_test(number_helpers),
        cmocka_unit_test(token_forms),
        cmocka_unit_test(quiet_wait_and_trace),
        cmocka_unit_test(csv_where_tables_are),
        cmocka_unit_test(jobs_filters),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
