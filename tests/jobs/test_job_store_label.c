/* A job database of schema version 2 (list columns, specs in job_specs, no label column) opens
 * as version 3: the label column is added and filled from specs that carried a label, and the
 * rows keep their results, list columns and byte counts (the version-0 backfill does not run
 * again over them). */
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

#include "job_store.h"

static const char version2[] =
    "PRAGMA journal_mode=WAL;"
    "CREATE TABLE jobs (id INTEGER PRIMARY KEY AUTOINCREMENT, kind TEXT NOT NULL,"
    " owner_uid INTEGER, state TEXT NOT NULL, progress REAL NOT NULL DEFAULT 0,"
    " spec TEXT NOT NULL, best TEXT, trace TEXT, result TEXT, error TEXT, reason TEXT,"
    " created REAL NOT NULL, started REAL, finished REAL,"
    " crashes INTEGER NOT NULL DEFAULT 0, best_e2 REAL, family TEXT,"
    " visibility TEXT NOT NULL DEFAULT 'team', pinned INTEGER NOT NULL DEFAULT 0,"
    " bytes INTEGER NOT NULL DEFAULT 0, reserve INTEGER NOT NULL DEFAULT 0,"
    " priority INTEGER NOT NULL DEFAULT 0);"
    "CREATE INDEX jobs_state ON jobs(state);"
    "CREATE TABLE job_specs (job_id INTEGER PRIMARY KEY REFERENCES jobs(id) ON DELETE CASCADE,"
    " spec TEXT NOT NULL);"
    "CREATE INDEX jobs_list ON jobs(id, state, kind, owner_uid, visibility, pinned, progress,"
    " created, started, finished, best_e2, family, bytes, reason, error);"
    "CREATE INDEX jobs_usage ON jobs(owner_uid, bytes, reserve);"
    "CREATE INDEX jobs_retention ON jobs(pinned, finished);"
    "INSERT INTO jobs(kind, owner_uid, state, spec, best, result, created, finished, best_e2,"
    " family, bytes) VALUES ('compare', 1000, 'done', '', NULL, '{\"rows\":[]}', 1, 2, NULL,"
    " NULL, 4321);"
    "INSERT INTO job_specs VALUES (1, '{\"kind\":\"compare\",\"label\":\"before\","
    "\"patterns\":[\"rgss\"]}');"
    "INSERT INTO jobs(kind, owner_uid, state, spec, best, result, created, finished, best_e2,"
    " family, bytes) VALUES ('optimize', 1000, 'done', '', '{\"e2\":0.25}', '{\"e2\":0.25}',"
    " 3, 4, 0.25, 'P(4,1+,2)', 1234);"
    "INSERT INTO job_specs VALUES (2, '{\"kind\":\"optimize\",\"family\":\"P(4,1+,2)\"}');"
    "PRAGMA user_version = 2;";

static void test_version2_gains_labels(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-test-label-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[128];
    snprintf(path, sizeof path, "%s/jobs.db", dir);
    sqlite3 *db;
    assert_int_equal(sqlite3_open(path, &db), SQLITE_OK);
    assert_int_equal(sqlite3_exec(db, version2, NULL, NULL, NULL), SQLITE_OK);
    sqlite3_close(db);

    for (int round = 0; round < 2; round++) { /* migrated once, then opened as it is */
        aa_error err = {0};
        job_store *st = job_store_open(dir, &err);
        if (!st)
            fail_msg("open: %s", err.message);
        job_store_filter f = {.limit = 10, .state = -1, .viewer = JOB_VIEWER_ALL};
        json_t *l = job_store_list(st, &f);
        /* Newest first: the job inserted in round 0 comes before the two old ones. */
        assert_int_equal(json_array_size(l), 2 + round);
        json_t *opt = json_array_get(l, round), *cmp = json_array_get(l, round + 1);
        assert_string_equal(json_string_value(json_object_get(cmp, "label")), "before");
        assert_true(json_is_null(json_object_get(opt, "label")));
        assert_true(json_is_null(json_object_get(cmp, "family")));
        assert_true(json_is_null(json_object_get(cmp, "best_e2")));
        assert_string_equal(json_string_value(json_object_get(opt, "family")), "P(4,1+,2)");
        assert_true(json_number_value(json_object_get(opt, "best_e2")) == 0.25);
        assert_int_equal(json_integer_value(json_object_get(opt, "bytes")), 1234);
        assert_int_equal(json_integer_value(json_object_get(cmp, "bytes")), 4321);
        json_decref(l);
        json_t *full = job_store_get(st, 2, true);
        assert_true(json_number_value(json_object_get(json_object_get(full, "result"), "e2")) ==
                    0.25);
        json_decref(full);
        /* New jobs store their label. */
        json_t *spec = json_pack("{s:s,s:f}", "kind", "sleep", "seconds", 0.0);
        job_store_new n = {.kind = "sleep", .spec = spec, .owner = 1000, .label = "fresh"};
        long long id = 0;
        if (round == 0) {
            assert_int_equal(job_store_insert(st, &n, &id, &err), AA_OK);
            json_t *got = job_store_get(st, id, false);
            assert_string_equal(json_string_value(json_object_get(got, "label")), "fresh");
            json_decref(got);
        }
        json_decref(spec);
        assert_true(job_store_integrity_ok(st));
        job_store_close(st);
    }
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_version2_gains_labels),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
