/* The job manager shares its workers between users: a job whose slice is over yields to a
 * waiting user's job and resumes later with exactly the result it has when it runs alone; a
 * pause costs it none of its time budget; --max-job-seconds stops a job that runs too long. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "job_manager.h"

#define ALICE 2001
#define BOB 2002

static void nap_ms(int ms)
{
    struct timespec d = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&d, NULL);
}

static job_manager *open_manager(char *dir, int workers, double slice, double max_job_seconds)
{
    assert_non_null(mkdtemp(dir));
    job_manager_config cfg = {.workers = workers,
                              .queue_size = 64,
                              .user_quota = 64,
                              .test_kinds = true,
                              .user_workers = 1,
                              .slice_seconds = slice,
                              .max_job_seconds = max_job_seconds};
    aa_error err = {0};
    job_manager *jm = job_manager_create(dir, &cfg, &err);
    if (!jm)
        fail_msg("job_manager_create: %s", err.message);
    return jm;
}

static void close_manager(job_manager *jm, const char *dir)
{
    job_manager_destroy(jm);
    char cmd[160];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

static long long submit(job_manager *jm, const char *spec_text, long long owner)
{
    json_error_t je;
    json_t *spec = json_loads(spec_text, JSON_REJECT_DUPLICATES, &je);
    assert_non_null(spec);
    long long id = 0;
    aa_error err = {0};
    int rc = job_manager_submit(jm, spec, owner, &id, &err);
    json_decref(spec);
    if (rc)
        fail_msg("submit %s: %s (%s)", spec_text, err.message, err.field);
    return id;
}

/* Polls until the job is final; counts the polls that saw it paused. */
static json_t *wait_final(job_manager *jm, long long id, int *paused_seen, double timeout)
{
    for (double t = 0; t < timeout; t += 0.005) {
        json_t *o = job_manager_get(jm, id);
        assert_non_null(o);
        const char *st = json_string_value(json_object_get(o, "state"));
        if (paused_seen && json_is_true(json_object_get(o, "paused")))
            (*paused_seen)++;
        if (strcmp(st, "queued") && strcmp(st, "running"))
            return o;
        json_decref(o);
        nap_ms(5);
    }
    fail_msg("job %lld did not finish in %.0f s", id, timeout);
    return NULL;
}

/* An optimize job bounded by iterations and stall only (its max_seconds far away) is
 * deterministic; run alone and then paused again and again for bob's jobs, it must give the
 * same E2 and the same pattern to the last digit. */
static void test_pause_keeps_the_result(void **state)
{
    (void)state;
    static const char spec[] = "{\"kind\":\"optimize\",\"family\":\"P(1,1,5)\",\"seeds\":96,"
                               "\"max_seconds\":600,\"rng_seed\":7}";
    char dir1[] = "/tmp/aalab-share-XXXXXX";
    job_manager *jm = open_manager(dir1, 1, 3600, 86400);
    json_t *alone = wait_final(jm, submit(jm, spec, ALICE), NULL, 300);
    close_manager(jm, dir1);

    char dir2[] = "/tmp/aalab-share-XXXXXX";
    jm = open_manager(dir2, 1, 0.05, 86400);
    long long id = submit(jm, spec, ALICE);
    long long bobs[6];
    for (int i = 0; i < 6; i++) {
        nap_ms(40);
        bobs[i] = submit(jm, "{\"kind\":\"sleep\",\"seconds\":0.1}", BOB);
    }
    int paused = 0;
    json_t *shared = wait_final(jm, id, &paused, 300);
    for (int i = 0; i < 6; i++) {
        json_t *b = wait_final(jm, bobs[i], NULL, 60);
        assert_string_equal(json_string_value(json_object_get(b, "state")), "done");
        json_decref(b);
    }
    close_manager(jm, dir2);

    printf("# optimize job seen paused in %d polls; E2 alone %.17g, shared %.17g\n", paused,
           json_real_value(json_object_get(json_object_get(alone, "result"), "e2")),
           json_real_value(json_object_get(json_object_get(shared, "result"), "e2")));
    assert_true(paused > 0);
    assert_string_equal(json_string_value(json_object_get(shared, "state")), "done");
    json_t *ra = json_object_get(alone, "result"), *rs = json_object_get(shared, "result");
    assert_true(json_real_value(json_object_get(ra, "e2")) ==
                json_real_value(json_object_get(rs, "e2")));
    assert_non_null(json_object_get(ra, "best"));
    assert_int_equal(json_integer_value(json_object_get(ra, "iterations")),
                     json_integer_value(json_object_get(rs, "iterations")));
    assert_int_equal(json_integer_value(json_object_get(ra, "evaluations")),
                     json_integer_value(json_object_get(rs, "evaluations")));
    if (!json_equal(json_object_get(ra, "best"), json_object_get(rs, "best"))) {
        char *x = json_dumps(ra, JSON_COMPACT), *y = json_dumps(rs, JSON_COMPACT);
        printf("alone  %s\nshared %s\n", x, y);
        free(x);
        free(y);
        fail_msg("the paused run's pattern differs");
    }
    assert_true(json_equal(json_object_get(ra, "per_seed"), json_object_get(rs, "per_seed")));
    json_decref(alone);
    json_decref(shared);
}

/* Bob's short job starts within one slice while alice's long jobs hold every worker; alice's
 * jobs sleep their full time on their own clock although they were paused. */
static void test_short_job_within_a_slice(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-share-XXXXXX";
    job_manager *jm = open_manager(dir, 2, 0.3, 86400);
    long long alice[4];
    for (int i = 0; i < 4; i++)
        alice[i] = submit(jm, "{\"kind\":\"sleep\",\"seconds\":1.5}", ALICE);
    nap_ms(100);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    long long b = submit(jm, "{\"kind\":\"sleep\",\"seconds\":0.2}", BOB);
    json_t *o = wait_final(jm, b, NULL, 30);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double waited = (double)(t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) * 1e-9;
    printf("# bob's 0.2 s job done %.2f s after submission (slice 0.3 s, alice: 4 x 1.5 s)\n",
           waited);
    assert_string_equal(json_string_value(json_object_get(o, "state")), "done");
    assert_true(waited < 0.3 + 0.2 + 0.5);
    json_decref(o);
    for (int i = 0; i < 4; i++) {
        o = wait_final(jm, alice[i], NULL, 60);
        assert_string_equal(json_string_value(json_object_get(o, "state")), "done");
        double slept =
            json_real_value(json_object_get(json_object_get(o, "result"), "slept_seconds"));
        assert_true(slept >= 1.5 && slept < 1.6);
        json_decref(o);
    }
    close_manager(jm, dir);
}

static void test_max_job_seconds(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-share-XXXXXX";
    job_manager *jm = open_manager(dir, 1, 60, 1);
    /* A spec asking for more than the ceiling is refused naming max_seconds. */
    json_error_t je;
    json_t *spec =
        json_loads("{\"kind\":\"optimize\",\"family\":\"P(1,1,3)\",\"max_seconds\":5}", 0, &je);
    long long id = 0;
    aa_error err = {0};
    assert_true(job_manager_submit(jm, spec, ALICE, &id, &err) < 0);
    assert_string_equal(err.field, "max_seconds");
    json_decref(spec);
    /* table3 spends max_seconds per seed and distribution: 0.5 is refused under a ceiling of 1,
     * and the message says what it adds up to instead of "must be at most 1" (issue 34). */
    spec = json_loads("{\"kind\":\"table3\",\"family\":\"P(4,4,2)\",\"seeds\":2,"
                      "\"count\":10,\"max_seconds\":0.5}",
                      0, &je);
    assert_non_null(spec);
    err = (aa_error){0};
    assert_true(job_manager_submit(jm, spec, ALICE, &id, &err) < 0);
    assert_string_equal(err.field, "max_seconds");
    assert_non_null(strstr(err.message, "max_seconds 0.5 makes this table3 job's whole budget"));
    assert_null(strstr(err.message, "must be at most"));
    json_decref(spec);
    /* A job that runs past it fails with code time_limit, its best kept. */
    id = submit(jm, "{\"kind\":\"sleep\",\"seconds\":30,\"pattern\":{\"preset\":\"rgss\"}}", ALICE);
    json_t *o = wait_final(jm, id, NULL, 20);
    assert_string_equal(json_string_value(json_object_get(o, "state")), "failed");
    assert_string_equal(json_string_value(json_object_get(json_object_get(o, "error"), "code")),
                        "time_limit");
    assert_true(json_is_object(json_object_get(o, "best")));
    json_decref(o);
    close_manager(jm, dir);
}

/* The kinds that can run on Slurm are named from the kind table (job_kind_names.h): the kinds
 * with a split, test-only ones left out; the sleep kind splits but is a test kind. */
static void test_slurm_refusal_names_the_split_kinds(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-share-XXXXXX";
    job_manager *jm = open_manager(dir, 1, 60, 60);
    json_error_t je;
    json_t *spec = json_loads("{\"kind\":\"compare\",\"executor\":\"slurm\"}", 0, &je);
    assert_non_null(spec);
    long long id = 0;
    aa_error err = {0};
    assert_int_equal(job_manager_submit(jm, spec, ALICE, &id, &err), AA_EINVAL);
    assert_string_equal(err.field, "executor");
    assert_string_equal(err.message, "kind compare cannot run on Slurm (optimize, family-sweep, "
                                     "random-stats and table3 can)");
    json_decref(spec);
    close_manager(jm, dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pause_keeps_the_result),
        cmocka_unit_test(test_short_job_within_a_slice),
        cmocka_unit_test(test_max_job_seconds),
        cmocka_unit_test(test_slurm_refusal_names_the_split_kinds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
