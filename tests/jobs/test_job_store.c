/* SQLite job store: insert, state changes, persistence across close/reopen, recovery visitor,
 * integrity check; the per-user byte quota, retention, migration of a first-schema database,
 * the list's viewer filter and derived pattern keys kept out of the database; the state
 * machine's edges (asserted where the store writes a state in Debug builds). */
#define _GNU_SOURCE
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>
#include <sqlite3.h>

#include "codec.h"
#include "job_retention.h"
#include "job_store.h"

typedef struct seen {
    int count;
    long long ids[8];
    job_state states[8];
} seen;

static void visit(void *user, long long id, const char *kind, json_t *spec, long long owner,
                  int priority, bool private_job, job_state state, double created)
{
    seen *s = user;
    (void)created;
    (void)priority;
    (void)private_job;
    assert_string_equal(kind, "sleep");
    assert_non_null(json_object_get(spec, "seconds"));
    assert_int_equal(owner, 1000);
    s->ids[s->count] = id;
    s->states[s->count++] = state;
}

static void make_dir(char *dir)
{
    assert_non_null(mkdtemp(dir));
}

/* A store in a new directory made from the template dir. */
static job_store *open_new_store(char *dir)
{
    make_dir(dir);
    aa_error err = {0};
    job_store *st = job_store_open(dir, &err);
    if (!st)
        fail_msg("job_store_open: %s", err.message);
    return st;
}

/* sql prepared on the store's database file in dir, opened on its own connection *db. */
static sqlite3_stmt *query_store_file(const char *dir, const char *sql, sqlite3 **db)
{
    char path[128];
    snprintf(path, sizeof path, "%s/jobs.db", dir);
    assert_int_equal(sqlite3_open(path, db), SQLITE_OK);
    sqlite3_stmt *q;
    assert_int_equal(sqlite3_prepare_v2(*db, sql, -1, &q, NULL), SQLITE_OK);
    return q;
}

static void remove_dir(const char *dir)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

static int insert(job_store *st, const json_t *spec, long long owner, double created, long long *id)
{
    aa_error err = {0};
    job_store_new n = {.kind = "sleep", .spec = spec, .owner = owner, .created = created};
    return job_store_insert(st, &n, id, &err);
}

static long long dumped_len(const json_t *j)
{
    char *s = json_dumps(j, JSON_COMPACT | JSON_ENCODE_ANY);
    long long n = (long long)strlen(s);
    free(s);
    return n;
}

static long long list_count(job_store *st, int state, const char *kind, long long viewer)
{
    job_store_filter f = {.limit = 100, .state = state, .kind = kind, .viewer = viewer};
    json_t *l = job_store_list(st, &f);
    long long n = (long long)json_array_size(l);
    json_decref(l);
    return n;
}

static void test_persistence(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-test-store-XXXXXX";
    job_store *st = open_new_store(dir);
    aa_error err = {0};
    json_t *spec = json_pack("{s:s,s:f}", "kind", "sleep", "seconds", 1.0);
    long long a, b, c;
    assert_int_equal(insert(st, spec, 1000, 1.0, &a), AA_OK);
    assert_int_equal(insert(st, spec, 1000, 2.0, &b), AA_OK);
    assert_int_equal(insert(st, spec, 1000, 3.0, &c), AA_OK);
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
    assert_string_equal(json_string_value(json_object_get(ja, "visibility")), "team");
    assert_true(json_is_false(json_object_get(ja, "pinned")));
    assert_int_equal(json_integer_value(json_object_get(ja, "owner_uid")), 1000);
    /* bytes: everything the row stores. */
    assert_int_equal(json_integer_value(json_object_get(ja, "bytes")),
                     dumped_len(spec) + dumped_len(best) + dumped_len(trace) + dumped_len(result));
    json_decref(ja);
    json_t *jb = job_store_get(st, b, false);
    assert_true(json_real_value(json_object_get(jb, "progress")) == 0.5);
    assert_true(json_real_value(json_object_get(jb, "best_e2")) == 0.25);
    json_decref(jb);
    assert_null(job_store_get(st, 999, false));

    seen s = {0};
    job_store_unfinished(st, visit, &s);
    assert_int_equal(s.count, 2);
    assert_int_equal(s.ids[0], b);
    assert_int_equal(s.states[0], JOB_RUNNING);
    assert_int_equal(s.ids[1], c);
    assert_int_equal(s.states[1], JOB_QUEUED);

    job_store_filter f = {.limit = 2, .state = -1, .viewer = JOB_VIEWER_ALL};
    json_t *list = job_store_list(st, &f);
    assert_int_equal(json_array_size(list), 2);
    assert_int_equal(json_integer_value(json_object_get(json_array_get(list, 0), "id")), c);
    json_decref(list);
    f = (job_store_filter){.limit = 10, .state = JOB_DONE, .viewer = JOB_VIEWER_ALL};
    list = job_store_list(st, &f);
    assert_int_equal(json_array_size(list), 1);
    assert_int_equal(json_integer_value(json_object_get(json_array_get(list, 0), "id")), a);
    json_decref(list);
    job_store_close(st);

    json_decref(spec);
    json_decref(best);
    json_decref(trace);
    json_decref(result);
    remove_dir(dir);
}

static json_t *spec_of_size(size_t bytes)
{
    char *blob = malloc(bytes + 1);
    memset(blob, 'x', bytes);
    blob[bytes] = 0;
    json_t *s = json_pack("{s:s,s:f,s:s}", "kind", "sleep", "seconds", 0.0, "blob", blob);
    free(blob);
    return s;
}

static long long usage(job_store *st, long long owner)
{
    job_store_usage u;
    assert_int_equal(job_store_usage_of(st, owner, &u), AA_OK);
    return u.bytes;
}

static long long count_rows(const char *dir, const char *sql)
{
    sqlite3 *db;
    sqlite3_stmt *q = query_store_file(dir, sql, &db);
    assert_int_equal(sqlite3_step(q), SQLITE_ROW);
    long long n = sqlite3_column_int64(q, 0);
    sqlite3_finalize(q);
    sqlite3_close(db);
    return n;
}

static void test_quota_accounting(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-test-store-XXXXXX";
    job_store *st = open_new_store(dir);
    aa_error err = {0};
    const long long quota = 1 << 20;
    job_store_set_user_quota(st, quota);
    json_t *spec = spec_of_size(100000);
    long long len = dumped_len(spec), reserve = 2 * len + JOB_STORE_RESERVE_EXTRA;
    long long a, b, c, d;
    assert_int_equal(insert(st, spec, 1000, 1.0, &a), AA_OK);
    /* An unfinished job counts with what it will store, not only its spec. */
    assert_int_equal(usage(st, 1000), reserve);
    assert_int_equal(insert(st, spec, 1000, 2.0, &b), AA_OK);
    assert_int_equal(usage(st, 1000), 2 * reserve);
    job_store_new n = {.kind = "sleep", .spec = spec, .owner = 1000, .created = 3.0};
    assert_int_equal(job_store_insert(st, &n, &c, &err), JOB_STORE_EQUOTA);
    assert_non_null(strstr(err.message, "limit is 1048576 bytes"));
    assert_int_equal(usage(st, 1000), 2 * reserve);
    /* Another user is not affected. */
    assert_int_equal(insert(st, spec, 1001, 3.0, &d), AA_OK);

    /* A progress write that would take uid 1000 over the quota keeps the old best. */
    json_t *small = json_pack("{s:f}", "e2", 0.5);
    assert_int_equal(job_store_update_progress(st, a, 0.1, small, NULL), AA_OK);
    json_t *big = json_pack("{s:f,s:o}", "e2", 0.25, "blob", json_object_get(spec, "blob"));
    json_incref(json_object_get(spec, "blob"));
    json_t *huge = json_array();
    for (int i = 0; i < 6; i++)
        json_array_append(huge, big);
    assert_int_equal(job_store_update_progress(st, a, 0.2, huge, NULL), JOB_STORE_EQUOTA);
    json_t *ja = job_store_get(st, a, true);
    assert_true(json_equal(json_object_get(ja, "best"), small));
    assert_true(json_real_value(json_object_get(ja, "progress")) == 0.2);
    json_decref(ja);
    assert_true(usage(st, 1000) <= quota);

    /* Finishing releases the reserve: the bytes are what is stored. */
    json_t *result = json_pack("{s:i}", "steps", 3);
    assert_int_equal(job_store_finish(st, a, JOB_DONE, 1, small, NULL, result, NULL, NULL, 4.0),
                     AA_OK);
    long long stored_a = len + dumped_len(small) + dumped_len(result);
    ja = job_store_get(st, a, false);
    assert_int_equal(json_integer_value(json_object_get(ja, "bytes")), stored_a);
    json_decref(ja);
    assert_int_equal(usage(st, 1000), stored_a + reserve);
    assert_int_equal(insert(st, spec, 1000, 5.0, &c), AA_OK);
    assert_true(usage(st, 1000) <= quota);

    /* A result that does not fit: failed, with the reason, nothing but spec and error stored. */
    assert_int_equal(job_store_finish(st, b, JOB_DONE, 1, NULL, NULL, huge, NULL, NULL, 6.0),
                     AA_OK);
    json_t *jb = job_store_get(st, b, true);
    assert_string_equal(json_string_value(json_object_get(jb, "state")), "failed");
    assert_string_equal(json_string_value(json_object_get(json_object_get(jb, "error"), "code")),
                        "quota_exceeded");
    assert_true(json_is_null(json_object_get(jb, "result")));
    assert_true(json_integer_value(json_object_get(jb, "bytes")) < len + 1000);
    json_decref(jb);
    assert_true(usage(st, 1000) <= quota);

    /* Deleting gives the bytes back. */
    long long before = usage(st, 1000);
    aa_error derr = {0};
    assert_int_equal(job_store_delete(st, c, &derr), JOB_STORE_EACTIVE);
    char want[160];
    snprintf(want, sizeof want, JOB_MSG_RUNNING, c); /* the answer to a purge, as it was */
    assert_string_equal(derr.message, want);
    assert_int_equal(job_store_delete(st, a, NULL), AA_OK);
    assert_int_equal(job_store_delete(st, a, &derr), JOB_STORE_ENOENT);
    snprintf(want, sizeof want, "no job %lld", a);
    assert_string_equal(derr.message, want);
    assert_string_equal(derr.field, "id");
    char sql[96];
    snprintf(sql, sizeof sql, "SELECT count(*) FROM job_specs WHERE job_id = %lld", a);
    assert_int_equal(count_rows(dir, sql), 0); /* the spec went with the row */
    snprintf(sql, sizeof sql, "SELECT count(*) FROM job_specs WHERE job_id = %lld", c);
    assert_int_equal(count_rows(dir, sql), 1);
    assert_int_equal(usage(st, 1000), before - stored_a);
    job_store_close(st);
    json_decref(small);
    json_decref(big);
    json_decref(huge);
    json_decref(result);
    json_decref(spec);
    remove_dir(dir);
}

static void test_retention_keeps_pinned(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-test-store-XXXXXX";
    job_store *st = open_new_store(dir);
    aa_error err = {0};
    json_t *spec = json_pack("{s:s,s:f}", "kind", "sleep", "seconds", 1.0);
    long long old_plain, old_pinned, recent, queued;
    assert_int_equal(insert(st, spec, 1000, 1.0, &old_plain), AA_OK);
    job_store_new n = {
        .kind = "sleep", .spec = spec, .owner = 1000, .created = 1.0, .pinned = true};
    assert_int_equal(job_store_insert(st, &n, &old_pinned, &err), AA_OK);
    assert_int_equal(insert(st, spec, 1000, 1.0, &recent), AA_OK);
    assert_int_equal(insert(st, spec, 1000, 1.0, &queued), AA_OK);
    job_store_finish(st, old_plain, JOB_DONE, 1, NULL, NULL, NULL, NULL, NULL, 100.0);
    job_store_finish(st, old_pinned, JOB_FAILED, 1, NULL, NULL, NULL, NULL, NULL, 100.0);
    job_store_finish(st, recent, JOB_CANCELLED, 1, NULL, NULL, NULL, NULL, NULL, 2000.0);
    long long deleted = -1;
    assert_int_equal(job_store_sweep(st, 1000.0, &deleted), AA_OK);
    assert_int_equal(deleted, 1);
    assert_false(job_store_owner(st, old_plain, NULL, NULL, NULL));
    assert_true(job_store_owner(st, old_pinned, NULL, NULL, NULL));
    assert_true(job_store_owner(st, recent, NULL, NULL, NULL));
    assert_true(job_store_owner(st, queued, NULL, NULL, NULL));

    /* Unpinned, the old job goes at the next sweep; the thread sweeps at start. */
    assert_int_equal(job_store_set_pinned(st, old_pinned, false, NULL), AA_OK);
    assert_int_equal(job_store_set_pinned(st, 99999, true, NULL), JOB_STORE_ENOENT);
    assert_true(job_retention_period(90) == 3600.0);
    assert_true(job_retention_period(0.0001) > 2.15 && job_retention_period(0.0001) < 2.17);
    job_retention *r = job_retention_start(st, 1.0, &err); /* 1 day: only the 1970 jobs */
    assert_non_null(r);
    for (int i = 0; i < 500 && job_retention_deleted(r) < 2; i++)
        usleep(10000);
    assert_int_equal(job_retention_deleted(r), 2);
    job_retention_stop(r);
    assert_false(job_store_owner(st, old_pinned, NULL, NULL, NULL));
    assert_false(job_store_owner(st, recent, NULL, NULL, NULL));
    assert_true(job_store_owner(st, queued, NULL, NULL, NULL)); /* never finished: kept */
    job_store_close(st);
    json_decref(spec);
    remove_dir(dir);
}

/* The first schema, as the daemon created it before the list columns existed. */
static const char old_schema[] = "CREATE TABLE IF NOT EXISTS jobs ("
                                 " id INTEGER PRIMARY KEY AUTOINCREMENT,"
                                 " kind TEXT NOT NULL,"
                                 " owner_uid INTEGER,"
                                 " state TEXT NOT NULL,"
                                 " progress REAL NOT NULL DEFAULT 0,"
                                 " spec TEXT NOT NULL,"
                                 " best TEXT, trace TEXT, result TEXT, error TEXT, reason TEXT,"
                                 " created REAL NOT NULL, started REAL, finished REAL);"
                                 "CREATE INDEX IF NOT EXISTS jobs_state ON jobs(state);"
                                 "ALTER TABLE jobs ADD COLUMN crashes INTEGER NOT NULL DEFAULT 0;";

static void test_migration_of_old_schema(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-test-store-XXXXXX";
    make_dir(dir);
    char path[128];
    snprintf(path, sizeof path, "%s/jobs.db", dir);
    sqlite3 *db;
    assert_int_equal(sqlite3_open(path, &db), SQLITE_OK);
    const char *best = "{\"pattern\":{\"family\":\"P(4,1+,2)\",\"mirrored\":[[0,0,1]]},"
                       "\"e2\":0.3125}";
    const char *spec = "{\"kind\":\"optimize\",\"family\":\"P(4,1+,2)\"}";
    const char *sleep_spec = "{\"kind\":\"sleep\",\"seconds\":1}";
    char sql[1024];
    snprintf(sql, sizeof sql,
             "PRAGMA journal_mode=WAL; %s"
             "INSERT INTO jobs(kind, owner_uid, state, spec, best, result, created, finished) "
             "VALUES ('optimize', 1000, 'done', '%s', '%s', '{\"e2\":0.3125}', 1.0, 2.0);"
             "INSERT INTO jobs(kind, owner_uid, state, spec, created) "
             "VALUES ('sleep', 1000, 'queued', '%s', 3.0);",
             old_schema, spec, best, sleep_spec);
    assert_int_equal(sqlite3_exec(db, sql, NULL, NULL, NULL), SQLITE_OK);
    sqlite3_close(db);

    for (int round = 0; round < 2; round++) { /* migrated once, then opened as it is */
        aa_error err = {0};
        job_store *st = job_store_open(dir, &err);
        assert_non_null(st);
        job_store_filter f = {.limit = 10, .state = -1, .viewer = 1001};
        json_t *l = job_store_list(st, &f);
        assert_int_equal(json_array_size(l), 2);
        json_t *done = json_array_get(l, 1);
        assert_true(json_real_value(json_object_get(done, "best_e2")) == 0.3125);
        assert_string_equal(json_string_value(json_object_get(done, "family")), "P(4,1+,2)");
        assert_string_equal(json_string_value(json_object_get(done, "visibility")), "team");
        assert_true(json_is_false(json_object_get(done, "pinned")));
        assert_int_equal(json_integer_value(json_object_get(done, "bytes")),
                         (long long)(strlen(spec) + strlen(best) + strlen("{\"e2\":0.3125}")));
        json_decref(l);
        /* The queued job holds its reserve; both count. */
        long long queued_reserve = 2 * (long long)strlen(sleep_spec) + JOB_STORE_RESERVE_EXTRA;
        job_store_usage u;
        assert_int_equal(job_store_usage_of(st, 1000, &u), AA_OK);
        assert_int_equal(u.jobs, 2);
        assert_int_equal(u.bytes, (long long)(strlen(spec) + strlen(best) + 13) + queued_reserve);
        json_t *full = job_store_get(st, 1, true);
        assert_string_equal(
            json_string_value(json_object_get(json_object_get(full, "spec"), "family")),
            "P(4,1+,2)");
        json_decref(full);
        /* Schema 4: the cluster column (Slurm state), NULL for old rows, kept across opens. */
        assert_null(job_store_get_cluster(st, 1));
        json_t *cl = job_store_get_cluster(st, 2);
        if (round == 0) {
            assert_null(cl);
            json_t *set = json_pack("{s:s,s:[{s:i,s:[I]}]}", "executor", "slurm", "stages",
                                    "shards", 2, "arrays", (json_int_t)123);
            assert_int_equal(job_store_set_cluster(st, 2, set), AA_OK);
            json_decref(set);
            assert_int_equal(job_store_set_cluster(st, 99, json_null()), JOB_STORE_ENOENT);
        } else {
            assert_non_null(cl);
            assert_string_equal(json_string_value(json_object_get(cl, "executor")), "slurm");
        }
        json_decref(cl);
        assert_true(job_store_integrity_ok(st));
        job_store_close(st);
    }
    remove_dir(dir);
}

static void test_list_filter_by_viewer(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-test-store-XXXXXX";
    job_store *st = open_new_store(dir);
    aa_error err = {0};
    json_t *spec = json_pack("{s:s,s:f}", "kind", "sleep", "seconds", 1.0);
    long long id;
    job_store_new n = {.kind = "sleep", .spec = spec, .owner = 1000, .visibility = "private"};
    assert_int_equal(job_store_insert(st, &n, &id, &err), AA_OK);
    n = (job_store_new){.kind = "optimize", .spec = spec, .owner = 1001};
    assert_int_equal(job_store_insert(st, &n, &id, &err), AA_OK);
    n = (job_store_new){.kind = "sleep", .spec = spec, .owner = 1001, .visibility = "private"};
    assert_int_equal(job_store_insert(st, &n, &id, &err), AA_OK);
    job_store_finish(st, id, JOB_DONE, 1, NULL, NULL, NULL, NULL, NULL, 5.0);

    assert_int_equal(list_count(st, -1, NULL, JOB_VIEWER_ALL), 3);
    assert_int_equal(list_count(st, -1, NULL, 1000), 2);
    assert_int_equal(list_count(st, -1, NULL, 1001), 2);
    assert_int_equal(list_count(st, -1, NULL, 1002), 1);
    assert_int_equal(list_count(st, -1, NULL, -2), 1);
    assert_int_equal(list_count(st, -1, "sleep", JOB_VIEWER_ALL), 2);
    assert_int_equal(list_count(st, -1, "sleep", 1000), 1);
    assert_int_equal(list_count(st, JOB_DONE, NULL, 1001), 1);
    assert_int_equal(list_count(st, JOB_DONE, NULL, 1000), 0);
    job_store_filter f = {.limit = 100, .state = -1, .viewer = 1000};
    json_t *l = job_store_list(st, &f);
    json_t *first = json_array_get(l, 1); /* the private one of 1000 */
    assert_string_equal(json_string_value(json_object_get(first, "visibility")), "private");
    assert_int_equal(json_integer_value(json_object_get(first, "owner_uid")), 1000);
    json_decref(l);
    job_store_close(st);
    json_decref(spec);
    remove_dir(dir);
}

static json_t *encoded_pattern(const char *text)
{
    json_t *in = json_loads(text, 0, NULL);
    aa_pattern p;
    aa_error err = {0};
    assert_int_equal(proto_decode_pattern(in, 0, &p, "", &err), AA_OK);
    json_t *enc = proto_encode_pattern(&p);
    aa_pattern_free(&p);
    json_decref(in);
    assert_non_null(json_object_get(enc, "kernels_expanded"));
    return enc;
}

static bool column_mentions(const char *dir, const char *column, const char *needle)
{
    char sql[128];
    snprintf(sql, sizeof sql, "SELECT %s FROM jobs", column);
    sqlite3 *db;
    sqlite3_stmt *q = query_store_file(dir, sql, &db);
    bool found = false;
    while (sqlite3_step(q) == SQLITE_ROW) {
        const unsigned char *t = sqlite3_column_text(q, 0);
        found |= t && strstr((const char *)t, needle);
    }
    sqlite3_finalize(q);
    sqlite3_close(db);
    return found;
}

static void test_derived_keys_not_stored(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-test-store-XXXXXX";
    job_store *st = open_new_store(dir);
    json_t *mirrored = encoded_pattern("{\"mirrored\":[[-0.5,0.1667,0.25],[0.5,-0.1667,0.25],"
                                       "[0.1667,0.5,0.25],[-0.1667,-0.5,0.25]]}");
    json_t *kernels = encoded_pattern("{\"kernels\":[[[-0.125,-0.375,0.25],[0.375,-0.125,0.25],"
                                      "[0.125,0.375,0.25],[-0.375,0.125,0.25]]]}");
    json_t *tile = encoded_pattern("{\"tile\":{\"size\":2,\"samples\":[[0.1,0.2],[-0.3,0.25],"
                                   "[0.4,-0.1],[-0.2,-0.4]]}}");
    json_t *best = json_pack("{s:O,s:f}", "pattern", mirrored, "e2", 0.364);
    json_t *result = json_pack("{s:O,s:[O,O]}", "pattern", mirrored, "patterns", kernels, tile);
    json_t *spec = json_pack("{s:s,s:f}", "kind", "sleep", "seconds", 1.0);
    long long a, b;
    assert_int_equal(insert(st, spec, 1000, 1.0, &a), AA_OK);
    assert_int_equal(insert(st, spec, 1000, 1.0, &b), AA_OK);
    assert_int_equal(job_store_update_progress(st, a, 0.5, best, NULL), AA_OK);
    assert_int_equal(job_store_finish(st, b, JOB_DONE, 1, best, NULL, result, NULL, NULL, 2.0),
                     AA_OK);
    assert_false(column_mentions(dir, "best", "kernels_expanded"));
    assert_false(column_mentions(dir, "result", "kernels_expanded"));
    assert_true(column_mentions(dir, "best", "mirrored"));
    /* The caller's JSON is not modified... */
    assert_non_null(json_object_get(json_object_get(best, "pattern"), "kernels_expanded"));
    /* ...and what the API shows is the same as before. */
    json_t *ja = job_store_get(st, a, true), *jb = job_store_get(st, b, true);
    assert_true(json_equal(json_object_get(ja, "best"), best));
    assert_true(json_equal(json_object_get(jb, "best"), best));
    assert_true(json_equal(json_object_get(jb, "result"), result));
    char *want = json_dumps(result, JSON_COMPACT),
         *got = json_dumps(json_object_get(jb, "result"), JSON_COMPACT);
    assert_string_equal(got, want); /* same text, key order included */
    free(want);
    free(got);
    assert_string_equal(json_string_value(json_object_get(ja, "family")),
                        json_string_value(json_object_get(mirrored, "family")));
    json_decref(ja);
    json_decref(jb);
    job_store_close(st);
    json_decref(mirrored);
    json_decref(kernels);
    json_decref(tile);
    json_decref(best);
    json_decref(result);
    json_decref(spec);
    remove_dir(dir);
}

static void test_corrupt_file_refused(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-test-store-XXXXXX";
    make_dir(dir);
    char path[96];
    snprintf(path, sizeof path, "%s/jobs.db", dir);
    FILE *f = fopen(path, "w");
    fputs("this is not a database, just text long enough to be read as a header...........", f);
    fclose(f);
    aa_error err = {0};
    job_store *st = job_store_open(dir, &err);
    assert_null(st);
    assert_true(strlen(err.message) > 0);
    remove_dir(dir);
}

/* The state machine's edges (job_store.h): only queued and running jobs change state. */
static void test_state_edges(void **state)
{
    (void)state;
    for (int from = 0; from < JOB_STATE_COUNT; from++)
        for (int to = 0; to < JOB_STATE_COUNT; to++)
            assert_int_equal(job_state_edge_legal((job_state)from, (job_state)to),
                             from == JOB_QUEUED || from == JOB_RUNNING);
    assert_false(job_state_edge_legal(JOB_QUEUED, (job_state)JOB_STATE_COUNT));
}

#ifndef NDEBUG
/* In a child: rewrites a finished job's state, which must die on the store's edge assert. */
static bool rewrite_aborts(job_store *st, long long id, bool finish)
{
    fflush(NULL);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        freopen("/dev/null", "w", stderr); /* the assert's message is expected */
        if (finish)
            job_store_finish(st, id, JOB_FAILED, 1, NULL, NULL, NULL, NULL, NULL, 9.0);
        else
            job_store_set_state(st, id, JOB_RUNNING, 9.0, NULL);
        _exit(0);
    }
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    return WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT;
}

/* Debug builds assert the edge where the store writes a state (Release compiles the check out:
 * the job manager never writes a finished job's state again). */
static void test_final_state_rewrite_aborts(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-test-store-XXXXXX";
    job_store *st = open_new_store(dir);
    json_t *spec = json_pack("{s:s,s:f}", "kind", "sleep", "seconds", 1.0);
    long long id;
    assert_int_equal(insert(st, spec, 1000, 1.0, &id), AA_OK);
    assert_int_equal(job_store_set_state(st, id, JOB_RUNNING, 2.0, NULL), AA_OK);
    assert_int_equal(job_store_finish(st, id, JOB_DONE, 1, NULL, NULL, NULL, NULL, NULL, 3.0),
                     AA_OK);
    assert_true(rewrite_aborts(st, id, true));
    assert_true(rewrite_aborts(st, id, false));
    long long counts[JOB_STATE_COUNT];
    job_store_counts(st, counts);
    assert_int_equal(counts[JOB_DONE], 1); /* the children changed nothing */
    json_decref(spec);
    job_store_close(st);
    remove_dir(dir);
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_persistence),
        cmocka_unit_test(test_quota_accounting),
        cmocka_unit_test(test_retention_keeps_pinned),
        cmocka_unit_test(test_migration_of_old_schema),
        cmocka_unit_test(test_list_filter_by_viewer),
        cmocka_unit_test(test_derived_keys_not_stored),
        cmocka_unit_test(test_corrupt_file_refused),
        cmocka_unit_test(test_state_edges),
#ifndef NDEBUG
        cmocka_unit_test(test_final_state_rewrite_aborts),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
