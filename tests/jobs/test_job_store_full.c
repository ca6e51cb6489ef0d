/* A job store that cannot grow (SQLite's max_page_count standing in for a full disk):
 * writes that need new pages fail with JOB_STORE_EUNAVAILABLE (the HTTP layer's 503), the row
 * is left as it was, a missing job is still JOB_STORE_ENOENT (404), and the same write succeeds
 * once the store can grow again. tests/e2e/e2e_users_diskfull.py does it on a real full tmpfs. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>
#include <sqlite3.h>

#include "job_store_impl.h"

static long long page_count(sqlite3 *db)
{
    sqlite3_stmt *q;
    long long n = -1;
    assert_int_equal(sqlite3_prepare_v2(db, "PRAGMA page_count", -1, &q, NULL), SQLITE_OK);
    if (sqlite3_step(q) == SQLITE_ROW)
        n = sqlite3_column_int64(q, 0);
    sqlite3_finalize(q);
    return n;
}

static void set_max_pages(job_store *st, long long n)
{
    char sql[64];
    snprintf(sql, sizeof sql, "PRAGMA max_page_count = %lld", n);
    pthread_mutex_lock(&st->lock);
    assert_int_equal(sqlite3_exec(st->db, sql, NULL, NULL, NULL), SQLITE_OK);
    pthread_mutex_unlock(&st->lock);
}

static const char *state_of(job_store *st, long long id, char *buf, size_t cap)
{
    json_t *o = job_store_get(st, id, false);
    assert_non_null(o);
    snprintf(buf, cap, "%s", json_string_value(json_object_get(o, "state")));
    json_decref(o);
    return buf;
}

static void test_full_store(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-test-full-XXXXXX";
    assert_non_null(mkdtemp(dir));
    aa_error err = {0};
    job_store *st = job_store_open(dir, &err);
    assert_non_null(st);
    json_t *spec = json_pack("{s:s,s:f}", "kind", "sleep", "seconds", 1.0);
    job_store_new rec = {.kind = "sleep", .spec = spec, .owner = 1000, .created = 1};
    long long id = 0;
    assert_int_equal(job_store_insert(st, &rec, &id, &err), AA_OK);
    assert_int_equal(job_store_set_state(st, id, JOB_RUNNING, 2, NULL), AA_OK);

    /* A result of 256 KiB needs new pages, which the store may not take. */
    size_t big_len = 256 * 1024;
    char *big = malloc(big_len + 1);
    assert_non_null(big);
    memset(big, 'x', big_len);
    big[big_len] = 0;
    json_t *result = json_pack("{s:s}", "blob", big);
    set_max_pages(st, page_count(st->db));
    int rc = job_store_finish(st, id, JOB_DONE, 1, NULL, NULL, result, NULL, NULL, 3);
    assert_int_equal(rc, JOB_STORE_EUNAVAILABLE);
    char buf[32];
    assert_string_equal(state_of(st, id, buf, sizeof buf), "running");
    /* A missing job stays a 404, not a 503. */
    assert_int_equal(job_store_set_pinned(st, id + 100, true, NULL), JOB_STORE_ENOENT);
    /* A big new job is refused with a message, and takes no id. */
    json_t *big_spec = json_pack("{s:s,s:s}", "kind", "sleep", "note", big);
    job_store_new big_rec = {.kind = "sleep", .spec = big_spec, .owner = 1000, .created = 4};
    long long id2 = 0;
    err = (aa_error){0};
    assert_int_not_equal(job_store_insert(st, &big_rec, &id2, &err), AA_OK);
    assert_non_null(strstr(err.message, "full"));
    assert_int_equal(id2, 0);

    /* Room again: the same final write goes through. */
    set_max_pages(st, 1 << 30);
    assert_int_equal(job_store_finish(st, id, JOB_DONE, 1, NULL, NULL, result, NULL, NULL, 3),
                     AA_OK);
    assert_string_equal(state_of(st, id, buf, sizeof buf), "done");
    assert_int_equal(job_store_delete(st, id, NULL), AA_OK);
    assert_true(job_store_integrity_ok(st));

    json_decref(big_spec);
    json_decref(result);
    json_decref(spec);
    free(big);
    job_store_close(st);
    char cmd[96];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_full_store)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
