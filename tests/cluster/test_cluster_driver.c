/* The Slurm driver (server/cluster/cluster_driver.c) against fake Slurm commands
 * (fake_slurm/: sbatch runs each element in the background through the fake worker, squeue
 * lists what still runs, scancel kills, scontrol answers show job, sacct has no accounting),
 * with the test kind "sleep" and its split: merge order, retry once, failure with the log tail,
 * cancel, and re-attach from the saved state. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "cluster_driver.h"
#include "job_kind.h"
#include "job_sleep.h"

typedef struct harness {
    char dir[256];    /* FAKE_SLURM_DIR */
    char shared[300]; /* --slurm-shared-dir */
    cluster_config cfg;
    const job_kind *kind;
    void *params;
    json_t *spec;
    /* what the driver reported */
    json_t *saved;
    json_t *first_saved; /* the state as first saved: a stage without its array id yet */
    json_t *best;
    json_t *trace;
    double progress;
    int reports, saves;
    /* when to stop */
    cluster_stop stop_with;
    int stop_after_saves; /* 0: never */
} harness;

static cluster_stop h_check(void *user)
{
    harness *h = user;
    if (h->stop_after_saves && h->saves >= h->stop_after_saves)
        return h->stop_with;
    return CLUSTER_GO;
}

static void h_report(void *user, double progress, const json_t *best, const json_t *trace)
{
    harness *h = user;
    h->progress = progress;
    h->reports++;
    if (best) {
        json_decref(h->best);
        h->best = json_deep_copy(best);
    }
    json_decref(h->trace);
    h->trace = trace ? json_deep_copy(trace) : NULL;
}

static void h_save(void *user, const json_t *state)
{
    harness *h = user;
    json_decref(h->saved);
    h->saved = json_deep_copy(state);
    if (!h->first_saved)
        h->first_saved = json_deep_copy(state);
    h->saves++;
}

static int setup(void **state)
{
    harness *h = calloc(1, sizeof *h);
    snprintf(h->dir, sizeof h->dir, "/tmp/aalab-fake-slurm-XXXXXX");
    assert_non_null(mkdtemp(h->dir));
    snprintf(h->shared, sizeof h->shared, "%s/shared", h->dir);
    setenv("FAKE_SLURM_DIR", h->dir, 1);
    static char path[8192];
    const char *old = getenv("PATH");
    snprintf(path, sizeof path, "%s:%s", FAKE_SLURM_BIN, old ? old : "/usr/bin:/bin");
    setenv("PATH", path, 1);
    snprintf(h->cfg.shared_dir, sizeof h->cfg.shared_dir, "%s", h->shared);
    snprintf(h->cfg.worker, sizeof h->cfg.worker, "%s", FAKE_WORKER);
    h->cfg.max_tasks = 4;
    h->cfg.time_limit_minutes = 5;
    h->cfg.poll_seconds = 0.1;
    snprintf(h->cfg.sbatch_args, sizeof h->cfg.sbatch_args, "--cpus-per-task=1  --exclusive");
    h->kind = job_kind_find("sleep");
    assert_non_null(h->kind);
    assert_non_null(h->kind->split);
    *state = h;
    return 0;
}

static int teardown(void **state)
{
    harness *h = *state;
    /* Anything still running belongs to this test's fake cluster. */
    char cmd[1200];
    snprintf(cmd, sizeof cmd,
             "for p in '%s'/pid/*; do [ -f \"$p\" ] && kill -TERM -- -$(cat \"$p\") 2>/dev/null; "
             "done; rm -rf '%s'",
             h->dir, h->dir);
    if (system(cmd)) {
    }
    json_decref(h->saved);
    json_decref(h->first_saved);
    json_decref(h->best);
    json_decref(h->trace);
    json_decref(h->spec);
    if (h->params)
        h->kind->free_params(h->params);
    free(h);
    return 0;
}

static void use_spec(harness *h, double seconds)
{
    h->spec = json_pack("{s:s,s:f}", "kind", "sleep", "seconds", seconds);
    json_t *kind_spec = json_pack("{s:f}", "seconds", seconds);
    aa_error err = {0};
    assert_int_equal(h->kind->decode(kind_spec, &h->params, &err), AA_OK);
    json_decref(kind_spec);
}

static int run(harness *h, long long id, const json_t *state, void **result, char *failure,
               size_t cap, aa_error *err)
{
    cluster_job job = {
        .id = id, .kind = h->kind, .params = h->params, .spec = h->spec, .state = state};
    cluster_job_io io = {.check = h_check, .report = h_report, .save = h_save, .user = h};
    return cluster_driver_run(&h->cfg, &job, &io, result, failure, cap, err);
}

static int count_lines(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    int n = 0, c;
    while ((c = fgetc(f)) != EOF)
        n += c == '\n';
    fclose(f);
    return n;
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return strdup("");
    char *buf = calloc(1, 65536);
    size_t n = fread(buf, 1, 65535, f);
    buf[n] = 0;
    fclose(f);
    return buf;
}

static void file_in(harness *h, const char *name, char *buf, size_t cap)
{
    snprintf(buf, cap, "%s/%s", h->dir, name);
}

static void touch(harness *h, const char *name)
{
    char p[400];
    file_in(h, name, p, sizeof p);
    FILE *f = fopen(p, "w");
    assert_non_null(f);
    fclose(f);
}

static long long result_steps(harness *h, void *result)
{
    json_t *r = h->kind->encode_result(result);
    long long steps = json_integer_value(json_object_get(r, "steps"));
    json_decref(r);
    h->kind->free_result(result);
    return steps;
}

/* Four shards finish in reverse order; the merge sees them in shard order (the sleep split's
 * merge fails otherwise); progress ends at 1; best is the best shard's; the trace is merged. */
static void test_runs_and_merges_in_order(void **state)
{
    harness *h = *state;
    use_spec(h, 0.4);
    void *result = NULL;
    char failure[1200];
    aa_error err = {0};
    int rc = run(h, 7, NULL, &result, failure, sizeof failure, &err);
    assert_int_equal(rc, AA_OK);
    assert_int_equal(result_steps(h, result), 10 + 20 + 30 + 40);
    assert_float_equal(h->progress, 1.0, 1e-12);
    assert_non_null(h->best);
    /* Shard i's e2 is 1/(i+2): shard 3's is the best. */
    assert_float_equal(json_number_value(json_object_get(h->best, "e2")), 0.2, 1e-12);
    /* Every shard starts at best 1.0 and ends at 1/(i+2); shard 3 (0.2) finishes first. */
    assert_true(json_array_size(h->trace) >= 2);
    json_t *last = json_array_get(h->trace, json_array_size(h->trace) - 1);
    assert_float_equal(json_number_value(json_object_get(last, "best_e2")), 0.2, 1e-12);
    assert_int_equal(json_integer_value(json_object_get(last, "iterations")) <= 100, 1);
    char p[400];
    file_in(h, "sbatch.log", p, sizeof p);
    assert_int_equal(count_lines(p), 1);
    char *log = slurp(p);
    assert_non_null(strstr(log, "--array=0-3"));
    assert_non_null(strstr(log, "--job-name=aalab-7-s0"));
    assert_non_null(strstr(log, "--time=5"));
    assert_non_null(strstr(log, "--cpus-per-task=1 --exclusive"));
    assert_non_null(strstr(log, "/job-7/stage-0/log-%a.out"));
    free(log);
    /* The saved state names the array of every shard. */
    long long ids[8];
    assert_int_equal(cluster_state_arrays(h->saved, ids, 8), 1);
}

/* A shard that dies without output is resubmitted alone, once. */
static void test_retries_a_failed_shard_once(void **state)
{
    harness *h = *state;
    use_spec(h, 0.2);
    touch(h, "fail-once-0-2");
    void *result = NULL;
    char failure[1200];
    aa_error err = {0};
    int rc = run(h, 8, NULL, &result, failure, sizeof failure, &err);
    assert_int_equal(rc, AA_OK);
    assert_int_equal(result_steps(h, result), 100);
    char p[400];
    file_in(h, "sbatch.log", p, sizeof p);
    assert_int_equal(count_lines(p), 2);
    char *log = slurp(p);
    assert_non_null(strstr(log, "--array=2 "));
    free(log);
    assert_int_equal(
        json_integer_value(json_array_get(
            json_object_get(json_array_get(json_object_get(h->saved, "stages"), 0), "retried"), 2)),
        1);
}

/* A shard that fails again fails the job: the message names the shard, Slurm's state and the
 * tail of its log. */
static void test_second_failure_fails_the_job(void **state)
{
    harness *h = *state;
    use_spec(h, 0.2);
    touch(h, "fail-always-0-1");
    void *result = NULL;
    char failure[1200];
    aa_error err = {0};
    int rc = run(h, 9, NULL, &result, failure, sizeof failure, &err);
    assert_int_equal(rc, CLUSTER_ESHARD);
    assert_null(result);
    assert_string_equal(err.field, "executor");
    assert_non_null(strstr(failure, "shard 1 of stage 0 failed twice"));
    assert_non_null(strstr(failure, "state FAILED"));
    assert_non_null(strstr(failure, "exit code 70"));
    assert_non_null(strstr(failure, "fake worker: shard 1 always fails"));
    assert_non_null(strstr(failure, "log-1.out"));
}

/* Cancel scancels every array and returns once squeue lists none. */
static void test_cancel_scancels_every_array(void **state)
{
    harness *h = *state;
    use_spec(h, 60);
    h->stop_with = CLUSTER_CANCEL;
    h->stop_after_saves = 1;
    void *result = NULL;
    char failure[1200];
    aa_error err = {0};
    int rc = run(h, 10, NULL, &result, failure, sizeof failure, &err);
    assert_int_equal(rc, AA_ECANCELED);
    char p[400];
    file_in(h, "scancel.log", p, sizeof p);
    assert_int_equal(count_lines(p), 1);
    char *log = slurp(p);
    long long ids[4];
    assert_int_equal(cluster_state_arrays(h->saved, ids, 4), 1);
    char want[32];
    snprintf(want, sizeof want, "%lld", ids[0]);
    assert_non_null(strstr(log, want));
    free(log);
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "test -z \"$(ls -A '%s/queue')\"", h->dir);
    assert_int_equal(system(cmd), 0);
}

/* Detach (daemon shutdown) leaves the array running; a new run with the saved state
 * re-attaches: nothing is resubmitted, outputs that appeared meanwhile are imported. */
static void test_reattaches_from_saved_state(void **state)
{
    harness *h = *state;
    use_spec(h, 1.0);
    h->stop_with = CLUSTER_DETACH;
    h->stop_after_saves = 1;
    void *result = NULL;
    char failure[1200];
    aa_error err = {0};
    int rc = run(h, 11, NULL, &result, failure, sizeof failure, &err);
    assert_int_equal(rc, CLUSTER_EDETACHED);
    assert_non_null(h->saved);
    json_t *saved = json_deep_copy(h->saved);
    /* Let some shards finish while "the daemon is down". */
    usleep(900 * 1000);
    h->stop_after_saves = 0;
    rc = run(h, 11, saved, &result, failure, sizeof failure, &err);
    json_decref(saved);
    assert_int_equal(rc, AA_OK);
    assert_int_equal(result_steps(h, result), 100);
    char p[400];
    file_in(h, "sbatch.log", p, sizeof p);
    assert_int_equal(count_lines(p), 1);
    file_in(h, "scancel.log", p, sizeof p);
    assert_int_equal(count_lines(p), 0);
}

/* A daemon that stopped between saving a stage and sbatch's answer finds the array by its job
 * name instead of submitting it again. */
static void test_adopts_an_unrecorded_array_by_name(void **state)
{
    harness *h = *state;
    use_spec(h, 1.0);
    h->stop_with = CLUSTER_DETACH;
    h->stop_after_saves = 1;
    void *result = NULL;
    char failure[1200];
    aa_error err = {0};
    int rc = run(h, 13, NULL, &result, failure, sizeof failure, &err);
    assert_int_equal(rc, CLUSTER_EDETACHED);
    json_t *unrecorded = json_deep_copy(h->first_saved);
    long long ids[4];
    assert_int_equal(cluster_state_arrays(unrecorded, ids, 4), 0);
    h->stop_after_saves = 0;
    rc = run(h, 13, unrecorded, &result, failure, sizeof failure, &err);
    json_decref(unrecorded);
    assert_int_equal(rc, AA_OK);
    assert_int_equal(result_steps(h, result), 100);
    char p[400];
    file_in(h, "sbatch.log", p, sizeof p);
    assert_int_equal(count_lines(p), 1);
    assert_int_equal(cluster_state_arrays(h->saved, ids, 4), 1);
}

/* The same when the array was never submitted: only the shards without output go. */
static void test_submits_an_unrecorded_stage(void **state)
{
    harness *h = *state;
    use_spec(h, 0.2);
    void *result = NULL;
    char failure[1200];
    aa_error err = {0};
    assert_int_equal(run(h, 14, NULL, &result, failure, sizeof failure, &err), AA_OK);
    h->kind->free_result(result);
    /* As if shard 2's output were lost and the array id never stored. */
    json_t *unrecorded = json_deep_copy(h->first_saved);
    char out[600], name[300];
    snprintf(out, sizeof out, "%s/job-14/stage-0/output-2.json", h->shared);
    assert_int_equal(unlink(out), 0);
    file_in(h, "name-1000", name, sizeof name);
    assert_int_equal(unlink(name), 0); /* squeue -n finds nothing */
    int rc = run(h, 14, unrecorded, &result, failure, sizeof failure, &err);
    json_decref(unrecorded);
    assert_int_equal(rc, AA_OK);
    assert_int_equal(result_steps(h, result), 100);
    char p[400];
    file_in(h, "sbatch.log", p, sizeof p);
    assert_int_equal(count_lines(p), 2);
    char *log = slurp(p);
    assert_non_null(strstr(log, "--array=2 "));
    free(log);
}

/* A state whose stage does not match the plan is refused rather than resubmitted. */
static void test_malformed_state_is_refused(void **state)
{
    harness *h = *state;
    use_spec(h, 0.1);
    json_t *bad = json_pack("{s:s,s:[{s:i,s:[],s:[],s:[]}]}", "executor", "slurm", "stages",
                            "shards", 9, "arrays", "shard_array", "retried");
    void *result = NULL;
    char failure[1200];
    aa_error err = {0};
    int rc = run(h, 12, bad, &result, failure, sizeof failure, &err);
    json_decref(bad);
    assert_int_equal(rc, AA_EINVAL);
    assert_non_null(strstr(err.message, "does not match"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_runs_and_merges_in_order, setup, teardown),
        cmocka_unit_test_setup_teardown(test_retries_a_failed_shard_once, setup, teardown),
        cmocka_unit_test_setup_teardown(test_second_failure_fails_the_job, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cancel_scancels_every_array, setup, teardown),
        cmocka_unit_test_setup_teardown(test_reattaches_from_saved_state, setup, teardown),
        cmocka_unit_test_setup_teardown(test_adopts_an_unrecorded_array_by_name, setup, teardown),
        cmocka_unit_test_setup_teardown(test_submits_an_unrecorded_stage, setup, teardown),
        cmocka_unit_test_setup_teardown(test_malformed_state_is_refused, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
