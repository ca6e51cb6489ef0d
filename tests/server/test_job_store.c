/* SQLite job store: insert, state changes, persistence across close/reopen, recovery visitor,
 * integrity check. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "job_store.h"

typedef struct seen {
    int count;
    long long ids[8];
    job_state states[8];
} seen;

static void visit(void *user, long long id, const char *kind, json_t *spec, long long owner,
                  job_state state, double created)
{
    seen *s = user;
    assert_string_equal(kind, "sleep");
    assert_non_null(json_object_get(spec, "seconds"));
    assert_int_equal(owner, 1000);
    s->ids[s->count] = id;
    s->states[s->count++] = state;
}

static void test_persistence(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-test-store-XXXXXX";
    assert_non_null(mkdtemp(dir));
    aa_error err = {0};
    job_store *st = job_store_open(dir, &err);
    assert_non_null(st);
    json_t *spec = json_pack("{s:s,s:f}", "kind", "sleep", "seconds", 1.0);
    long long a, b, c;
    assert_int_equal(job_store_insert(st, "sleep", spec, 1000, 1.0, &a, &err), AA_OK);
    assert_int_equal(job_store_insert(st, "sleep", spec, 1000, 2.0, &b, &err), AA_OK);
    assert_int_equal(job_store_insert(st, "sleep", spec, 1000, 3.0, &c, &err), AA_OK);
    assert_true(a < b && b < c);
    json_t *best = json_pack("{s:f}", "e2", 0.25);
    json_t *trace = json_pack("[{s:f,s:f}]", "seconds", 0.5, "best_e2", 0.25);
    json_t *result = json_pack("{s:s,s:[i,i]}", "answer", "yes", "list", 1, 2);
    assert_int_equal(job_store_set_state(st, a, JOB_RUNNING, 4.0, NULL), AA_OK);
    assert_int_equal(job_store_finish(st, a, JOB_DONE, 1.0, best, trace, result, NULL, NULL, 5.0),
                     AA_OK);
    assert_int_equal(job_store_set_state(st, b, JOB_RUNNING, 6.0, NULL), AA_OK);
    assert_int_equal(job_store_update_progress(st, b, 0.5, best, trace), AA_OK);
    long long counts[JOB_STATE_COUNT];
    job_store_counts(st, counts);
    assert_int_equal(counts[JOB_DONE], 1);
    assert_int_equal(counts[JOB_RUNNING], 1);
    assert_int_equal(counts[JOB_QUEUED], 1);
    job_store_close(st);

    st = job_store_open(dir, &err);
    assert_non_null(st);
    assert_true(job_store_integrity_ok(st));
    json_t *ja = job_store_get(st, a, true);
    assert_non_null(ja);
    assert_string_equal(json_string_value(json_object_get(ja, "state")), "done");
    assert_true(json_equal(json_object_get(ja, "result"), result));
    assert_true(json_equal(json_object_get(ja, "trace"), trace));
    assert_true(json_equal(json_object_get(ja, "spec"), spec));
    assert_true(json_real_value(json_object_get(ja, "finished")) == 5.0);
    assert_true(json_real_value(json_object_get(ja, "best_e2")) == 0.25);
    json_decref(ja);
    json_t *jb = job_store_get(st, b, false);
    assert_true(json_real_value(json_object_get(jb, "progress")) == 0.5);
    json_decref(jb);
    assert_null(job_store_get(st, 999, false));

    seen s = {0};
    job_store_unfinished(st, visit, &s);
    assert_int_equal(s.count, 2);
    assert_int_equal(s.ids[0], b);
    assert_int_equal(s.states[0], JOB_RUNNING);
    assert_int_equal(s.ids[1], c);
    assert_int_equal(s.states[1], JOB_QUEUED);

    json_t *list = job_store_list(st, 2, -1);
    assert_int_equal(json_array_size(list), 2);
    assert_int_equal(json_integer_value(json_object_get(json_array_get(list, 0), "id")), c);
    json_decref(list);
    list = job_store_list(st, 10, JOB_DONE);
    assert_int_equal(json_array_size(list), 1);
    assert_int_equal(json_integer_value(json_object_get(json_array_get(list, 0), "id")), a);
    json_decref(list);
    job_store_close(st);

    json_decref(spec);
    json_decref(best);
    json_decref(trace);
    json_decref(result);
    char cmd[96];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

static void test_corrupt_file_refused(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-test-store-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[96];
    snprintf(path, sizeof path, "%s/jobs.db", dir);
    FILE *f = fopen(path, "w");
    fputs("this is not a database, just text long enough to be read as a header...........", f);
    fclose(f);
    aa_error err = {0};
    job_store *st = job_store_open(dir, &err);
    assert_null(st);
    assert_true(strlen(err.message) > 0);
    char cmd[96];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_persistence),
        cmocka_unit_test(test_corrupt_file_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
