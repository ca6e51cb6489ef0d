/* aalab-worker, the binary, as a Slurm array task runs it: each kind's shards written as
 * TASK.json files and run by the worker give outputs whose merge equals the one-shard run (the
 * local executor's computation), bit for bit; the output and trace files have their formats; a
 * bad task file exits 65 naming the field, an unwritable output directory 73, SIGTERM 75 with
 * no output file, no argument 64. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "job_kind.h"
#include "job_split.h"
#include "split_harness.h"

extern char **environ;

static char dir[64];

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/aalab-worker-test-XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

/* Starts the worker on task (NULL: no argument) with stderr to err_path; returns its pid. */
static pid_t start_worker(const char *task, const char *err_path)
{
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 2, err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    char *argv[] = {(char *)AALAB_WORKER_PATH, (char *)task, NULL};
    pid_t pid;
    assert_int_equal(posix_spawn(&pid, AALAB_WORKER_PATH, &fa, NULL, argv, environ), 0);
    posix_spawn_file_actions_destroy(&fa);
    return pid;
}

static int wait_exit(pid_t pid)
{
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    return WEXITSTATUS(status);
}

static int run_worker(const char *task, const char *err_path)
{
    return wait_exit(start_worker(task, err_path));
}

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return NULL;
    static char buf[4096];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = 0;
    fclose(f);
    return buf;
}

/* The kind's params from spec text; the test fails if the spec does not decode. */
static void *decode(const job_kind *k, const char *text)
{
    void *params = split_harness_decode(k, text);
    assert_non_null(params);
    return params;
}

/* Writes shard i's task of a stage; fills the output path. */
static void write_task(const char *kind, const char *spec, int stage, size_t i, const json_t *shard,
                       const json_t *prior, char *task, char *output, size_t size)
{
    char trace[256];
    assert_true(snprintf(task, size, "%s/task-%d-%zu.json", dir, stage, i) < (int)size);
    assert_true(snprintf(output, size, "%s/output-%d-%zu.json", dir, stage, i) < (int)size);
    assert_true(snprintf(trace, sizeof trace, "%s/trace-%d-%zu.json", dir, stage, i) <
                (int)sizeof trace);
    json_error_t je;
    json_t *t =
        json_pack("{s:s,s:i,s:s,s:o,s:i,s:I,s:O,s:O,s:s,s:s}", "format", "aalab-task/1", "job_id",
                  42, "kind", kind, "spec", json_loads(spec, JSON_REJECT_DUPLICATES, &je), "stage",
                  stage, "shard_index", (json_int_t)i, "shard", shard, "prior",
                  prior ? prior : json_null(), "output", output, "trace", trace);
    assert_non_null(t);
    assert_int_equal(json_dump_file(t, task, JSON_REAL_PRECISION(17)), 0);
    json_decref(t);
    (void)je;
}

/* The shard output of an output file, its envelope checked. */
static json_t *read_output(const char *path, int stage, size_t i)
{
    json_error_t je;
    json_t *f = json_load_file(path, JSON_REJECT_DUPLICATES, &je);
    assert_non_null(f);
    assert_string_equal(json_string_value(json_object_get(f, "format")), "aalab-shard-output/1");
    assert_int_equal(json_integer_value(json_object_get(f, "job_id")), 42);
    assert_int_equal(json_integer_value(json_object_get(f, "stage")), stage);
    assert_int_equal(json_integer_value(json_object_get(f, "shard_index")), (json_int_t)i);
    assert_true(json_is_string(json_object_get(f, "host")));
    assert_true(json_number_value(json_object_get(f, "finished_unix")) >=
                json_number_value(json_object_get(f, "started_unix")));
    json_t *out = json_incref(json_object_get(f, "output"));
    json_decref(f);
    return out;
}

/* Runs every stage of the job as worker processes, 2 shards where the kind can. */
static json_t *run_by_workers(const job_kind *k, void *params, const char *spec)
{
    json_t *prior = NULL;
    aa_error err = {0};
    size_t most = 0;
    char errp[300];
    snprintf(errp, sizeof errp, "%s/stderr.txt", dir);
    for (int stage = 0; stage < k->split->stages; stage++) {
        json_t *shards = NULL;
        assert_int_equal(k->split->plan(params, stage, prior, 2, &shards, &err), AA_OK);
        size_t n = json_array_size(shards);
        most = n > most ? n : most;
        json_t *outputs[8];
        assert_true(n <= 8);
        for (size_t i = 0; i < n; i++) {
            char task[256], output[256];
            write_task(k->name, spec, stage, i, json_array_get(shards, i), prior, task, output,
                       sizeof task);
            assert_int_equal(run_worker(task, errp), 0);
            outputs[i] = read_output(output, stage, i);
        }
        json_t *merged = NULL;
        assert_int_equal(k->split->merge(params, stage, outputs, n, prior, &merged, &err), AA_OK);
        for (size_t i = 0; i < n; i++)
            json_decref(outputs[i]);
        json_decref(shards);
        json_decref(prior);
        prior = merged;
    }
    void *result = NULL;
    assert_int_equal(k->split->finish(params, prior, "slurm", most, &result, &err), AA_OK);
    json_t *enc = k->encode_result(result);
    k->free_result(result);
    json_decref(prior);
    return enc;
}

static void same_key(const json_t *a, const json_t *b, const char *key)
{
    char *ta = split_harness_text(json_object_get(a, key));
    char *tb = split_harness_text(json_object_get(b, key));
    assert_string_equal(ta, tb);
    free(ta);
    free(tb);
}

static void check_kind_key(const char *kind, const char *spec, const char *extra);

static void check_kind(const char *kind, const char *spec)
{
    check_kind_key(kind, spec, NULL);
}

/* The same, and the result's member extra (when given) alike too. */
static void check_kind_key(const char *kind, const char *spec, const char *extra)
{
    const job_kind *k = job_kind_find(kind);
    assert_non_null(k);
    void *params = decode(k, spec);
    json_t *local = split_harness_run(k, params, 1, 1);
    json_t *workers = run_by_workers(k, params, spec);
    assert_non_null(local);
    same_key(local, workers, "best");
    same_key(local, workers, "e2");
    if (extra) {
        assert_non_null(json_object_get(local, extra));
        same_key(local, workers, extra);
    }
    assert_true(json_is_object(json_object_get(workers, "best")));
    json_decref(local);
    json_decref(workers);
    k->free_params(params);
}

static void optimize_shards_merge_to_the_local_run(void **state)
{
    (void)state;
    check_kind("optimize", "{\"family\":\"P(4,1+,1.5)\",\"seeds\":5,\"max_iterations\":60}");
}

static void family_sweep_shards_merge_to_the_local_run(void **state)
{
    (void)state;
    check_kind("family-sweep", "{\"cost\":1.25,\"seeds_per_config\":2,\"max_iterations\":40}");
}

static void random_stats_shards_merge_to_the_local_run(void **state)
{
    (void)state;
    check_kind("random-stats", "{\"family\":\"P(1,4,2)\",\"count\":40,\"max_iterations\":60}");
}

/* Issue 31: the point-set figures are computed by each worker, ranked after the merge. */
static void random_stats_metrics_merge_to_the_local_run(void **state)
{
    (void)state;
    check_kind_key("random-stats",
                   "{\"family\":\"P(1,1,4)\",\"count\":40,\"max_iterations\":30,"
                   "\"metrics\":[\"centered\",\"star_linf\",\"min_distance\"]}",
                   "point_metrics");
}

static void table3_metrics_merge_to_the_local_run(void **state)
{
    (void)state;
    check_kind_key("table3",
                   "{\"family\":\"P(4,4,2)\",\"seeds\":2,\"count\":8,\"max_iterations\":30,"
                   "\"metrics\":[\"wrap_around\"]}",
                   "rows");
}

static void table3_shards_merge_to_the_local_run(void **state)
{
    (void)state;
    check_kind("table3", "{\"family\":\"P(4,4,2)\",\"seeds\":2,\"count\":8,\"max_iterations\":30}");
}

static void bad_task_is_65_naming_the_field(void **state)
{
    (void)state;
    static const char *const cases[][2] = {
        {"{\"format\":\"aalab-task/1\",\"job_id\":1,\"kind\":\"optimize\",\"spec\":{\"family\":"
         "\"P(1,1,2)\",\"seeds\":0},\"stage\":0,\"shard_index\":0,\"shard\":{\"first\":0,"
         "\"count\":1},\"prior\":null,\"output\":\"/tmp/o.json\",\"trace\":\"/tmp/t.json\"}",
         "\"spec.seeds\""},
        {"{\"format\":\"aalab-task/1\",\"job_id\":1,\"kind\":\"optimize\",\"spec\":{\"family\":"
         "\"P(1,1,2)\"},\"stage\":\"0\",\"shard_index\":0,\"shard\":{\"first\":0,"
         "\"count\":1},\"prior\":null,\"output\":\"/tmp/o.json\",\"trace\":\"/tmp/t.json\"}",
         "\"stage\""},
        {"{\"format\":\"aalab-task/1\",\"job_id\":1,\"kind\":\"compare\",\"spec\":{},\"stage\":0,"
         "\"shard_index\":0,\"shard\":{},\"prior\":null,\"output\":\"/tmp/o.json\",\"trace\":"
         "\"/tmp/t.json\"}",
         "\"kind\""},
        {"{\"format\":\"aalab-task/1\",\"job_id\":1}", "\"kind\""},
        {"{\"format\":\"aalab-task/1\",\"format\":\"aalab-task/1\"}", "duplicate"},
    };
    char task[300], errp[300];
    snprintf(task, sizeof task, "%s/bad.json", dir);
    snprintf(errp, sizeof errp, "%s/bad.err", dir);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        FILE *f = fopen(task, "w");
        assert_non_null(f);
        fputs(cases[i][0], f);
        fclose(f);
        assert_int_equal(run_worker(task, errp), 65);
        const char *msg = read_text(errp);
        assert_non_null(msg);
        if (!strstr(msg, cases[i][1]))
            fail_msg("case %zu: %s does not name %s", i, msg, cases[i][1]);
    }
    snprintf(task, sizeof task, "%s/missing.json", dir);
    assert_int_equal(run_worker(task, errp), 65);
    assert_int_equal(run_worker(NULL, errp), 64);
}

static void unwritable_output_is_73(void **state)
{
    (void)state;
    char task[256], output[256], errp[300];
    json_t *shard = json_pack("{s:i,s:i}", "first", 0, "count", 1);
    write_task("optimize", "{\"family\":\"P(1,1,2)\",\"seeds\":1,\"max_iterations\":10}", 0, 0,
               shard, NULL, task, output, sizeof task);
    json_decref(shard);
    /* Point output and trace into a directory that does not exist (root ignores modes). */
    json_error_t je;
    json_t *t = json_load_file(task, 0, &je);
    json_object_set_new(t, "output", json_string("/nonexistent-aalab-dir/output-0.json"));
    json_object_set_new(t, "trace", json_string("/nonexistent-aalab-dir/trace-0.json"));
    json_dump_file(t, task, 0);
    json_decref(t);
    snprintf(errp, sizeof errp, "%s/unwritable.err", dir);
    assert_int_equal(run_worker(task, errp), 73);
}

static void sigterm_is_75_without_output(void **state)
{
    (void)state;
    char task[256], output[256], trace[300], errp[300];
    json_t *shard = json_pack("{s:i,s:i}", "first", 0, "count", 64);
    write_task("optimize", "{\"family\":\"P(1,4,4)\",\"seeds\":64,\"max_iterations\":10000000}", 0,
               7, shard, NULL, task, output, sizeof task);
    json_decref(shard);
    snprintf(trace, sizeof trace, "%s/trace-0-7.json", dir);
    snprintf(errp, sizeof errp, "%s/sigterm.err", dir);
    pid_t pid = start_worker(task, errp);
    /* The trace file is written before the work starts. */
    struct stat st;
    for (int i = 0; i < 200 && stat(trace, &st); i++)
        nanosleep(&(struct timespec){0, 20 * 1000 * 1000}, NULL);
    assert_int_equal(stat(trace, &st), 0);
    nanosleep(&(struct timespec){0, 300 * 1000 * 1000}, NULL);
    assert_int_equal(kill(pid, SIGTERM), 0);
    assert_int_equal(wait_exit(pid), 75);
    assert_int_not_equal(stat(output, &st), 0);
    json_error_t je;
    json_t *t = json_load_file(trace, JSON_REJECT_DUPLICATES, &je);
    assert_non_null(t);
    assert_string_equal(json_string_value(json_object_get(t, "format")), "aalab-shard-trace/1");
    assert_true(json_is_array(json_object_get(t, "points")));
    json_decref(t);
}

static void help_documents_the_exit_codes(void **state)
{
    (void)state;
    char out[300];
    snprintf(out, sizeof out, "%s/help.txt", dir);
    char cmd[700];
    snprintf(cmd, sizeof cmd, "'%s' --help > '%s'", AALAB_WORKER_PATH, out);
    assert_int_equal(system(cmd), 0);
    const char *text = read_text(out);
    assert_non_null(text);
    for (size_t i = 0; i < 6; i++) {
        static const char *const codes[] = {"  0 ", "  64 ", "  65 ", "  70 ", "  73 ", "  75 "};
        assert_non_null(strstr(text, codes[i]));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(optimize_shards_merge_to_the_local_run),
        cmocka_unit_test(family_sweep_shards_merge_to_the_local_run),
        cmocka_unit_test(random_stats_shards_merge_to_the_local_run),
        cmocka_unit_test(random_stats_metrics_merge_to_the_local_run),
        cmocka_unit_test(table3_metrics_merge_to_the_local_run),
        cmocka_unit_test(table3_shards_merge_to_the_local_run),
        cmocka_unit_test(bad_task_is_65_naming_the_field),
        cmocka_unit_test(unwritable_output_is_73),
        cmocka_unit_test(sigterm_is_75_without_output),
        cmocka_unit_test(help_documents_the_exit_codes),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
