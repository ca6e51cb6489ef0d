#define _POSIX_C_SOURCE 200809L
#include "job_store.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <sqlite3.h>

struct job_store {
    sqlite3 *db;
    pthread_mutex_t lock;
};

static const char *const state_names[JOB_STATE_COUNT] = {"queued", "running",   "done",
                                                         "failed", "cancelled", "interrupted"};

const char *job_state_name(job_state s)
{
    return (unsigned)s < JOB_STATE_COUNT ? state_names[s] : "unknown";
}

bool job_state_final(job_state s)
{
    return s == JOB_DONE || s == JOB_FAILED || s == JOB_CANCELLED || s == JOB_INTERRUPTED;
}

static job_state state_from_name(const char *n)
{
    for (int i = 0; i < JOB_STATE_COUNT; i++)
        if (n && !strcmp(n, state_names[i]))
            return (job_state)i;
    return JOB_INTERRUPTED;
}

static const char schema_sql[] = "CREATE TABLE IF NOT EXISTS jobs ("
                                 " id INTEGER PRIMARY KEY AUTOINCREMENT,"
                                 " kind TEXT NOT NULL,"
                                 " owner_uid INTEGER,"
                                 " state TEXT NOT NULL,"
                                 " progress REAL NOT NULL DEFAULT 0,"
                                 " spec TEXT NOT NULL,"
                                 " best TEXT, trace TEXT, result TEXT, error TEXT, reason TEXT,"
                                 " created REAL NOT NULL, started REAL, finished REAL);"
                                 "CREATE INDEX IF NOT EXISTS jobs_state ON jobs(state);";

bool job_store_integrity_ok(job_store *st)
{
    pthread_mutex_lock(&st->lock);
    sqlite3_stmt *q;
    bool ok = false;
    if (sqlite3_prepare_v2(st->db, "PRAGMA integrity_check", -1, &q, NULL) == SQLITE_OK) {
        if (sqlite3_step(q) == SQLITE_ROW) {
            const unsigned char *t = sqlite3_column_text(q, 0);
            ok = t && !strcmp((const char *)t, "ok");
        }
        sqlite3_finalize(q);
    }
    pthread_mutex_unlock(&st->lock);
    return ok;
}

job_store *job_store_open(const char *dir, aa_error *err)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/jobs.db", dir);
    job_store *st = calloc(1, sizeof *st);
    if (!st) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    pthread_mutex_init(&st->lock, NULL);
    int rc = sqlite3_open_v2(
        path, &st->db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX, NULL);
    if (rc != SQLITE_OK) {
        aa_error_set(err, AA_EINVAL, "state_dir", "cannot open %s: %s", path,
                     st->db ? sqlite3_errmsg(st->db) : sqlite3_errstr(rc));
        goto fail;
    }
    chmod(path, 0600);
    sqlite3_busy_timeout(st->db, 5000);
    char *msg = NULL;
    /* WAL: readers never block the writer; synchronous=FULL so a finished job survives a
     * power cut, not just a crash (writes are few). */
    if (sqlite3_exec(st->db,
                     "PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL; PRAGMA foreign_keys=ON;",
                     NULL, NULL, &msg) != SQLITE_OK ||
        sqlite3_exec(st->db, schema_sql, NULL, NULL, &msg) != SQLITE_OK) {
        aa_error_set(err, AA_EINVAL, "state_dir", "cannot initialise %s: %s", path,
                     msg ? msg : sqlite3_errmsg(st->db));
        sqlite3_free(msg);
        goto fail;
    }
    /* Added after the first schema: ignore "duplicate column" on databases that have it. */
    sqlite3_exec(st->db, "ALTER TABLE jobs ADD COLUMN crashes INTEGER NOT NULL DEFAULT 0", NULL,
                 NULL, NULL);
    if (!job_store_integrity_ok(st)) {
        aa_error_set(err, AA_EINVAL, "state_dir", "%s failed PRAGMA integrity_check", path);
        goto fail;
    }
    return st;
fail:
    job_store_close(st);
    return NULL;
}

void job_store_close(job_store *st)
{
    if (!st)
        return;
    if (st->db) {
        sqlite3_exec(st->db, "PRAGMA wal_checkpoint(TRUNCATE);", NULL, NULL, NULL);
        sqlite3_close(st->db);
    }
    pthread_mutex_destroy(&st->lock);
    free(st);
}

/* Binds a JSON value as compact text, or NULL. */
static void bind_json(sqlite3_stmt *q, int i, const json_t *j)
{
    char *s = j ? json_dumps(j, JSON_COMPACT | JSON_ENCODE_ANY) : NULL;
    if (s)
        sqlite3_bind_text(q, i, s, -1, free);
    else
        sqlite3_bind_null(q, i);
}

static void bind_text_or_null(sqlite3_stmt *q, int i, const char *s)
{
    if (s)
        sqlite3_bind_text(q, i, s, -1, SQLITE_TRANSIENT);
    else
        sqlite3_bind_null(q, i);
}

static int exec_stmt(job_store *st, sqlite3_stmt *q)
{
    int rc = sqlite3_step(q);
    sqlite3_finalize(q);
    return rc == SQLITE_DONE ? AA_OK : AA_EINVAL;
}

int job_store_insert(job_store *st, const char *kind, const json_t *spec, long long owner,
                     double created, long long *id, aa_error *err)
{
    pthread_mutex_lock(&st->lock);
    sqlite3_stmt *q;
    int rc = sqlite3_prepare_v2(st->db,
                                "INSERT INTO jobs(kind, owner_uid, state, spec, created) "
                                "VALUES (?, ?, 'queued', ?, ?)",
                                -1, &q, NULL);
    if (rc == SQLITE_OK) {
        sqlite3_bind_text(q, 1, kind, -1, SQLITE_TRANSIENT);
        if (owner >= 0)
            sqlite3_bind_int64(q, 2, owner);
        else
            sqlite3_bind_null(q, 2);
        bind_json(q, 3, spec);
        sqlite3_bind_double(q, 4, created);
        rc = sqlite3_step(q);
        sqlite3_finalize(q);
    }
    int out = AA_OK;
    if (rc != SQLITE_DONE)
        out =
            aa_error_set(err, AA_EINVAL, "", "job store write failed: %s", sqlite3_errmsg(st->db));
    else
        *id = sqlite3_last_insert_rowid(st->db);
    pthread_mutex_unlock(&st->lock);
    return out;
}

int job_store_set_state(job_store *st, long long id, job_state state, double when,
                        const char *reason)
{
    pthread_mutex_lock(&st->lock);
    sqlite3_stmt *q;
    const char *sql = state == JOB_RUNNING
                          ? "UPDATE jobs SET state=?, started=?, reason=coalesce(?, reason) "
                            "WHERE id=?"
                          : "UPDATE jobs SET state=?, finished=CASE WHEN ?2 > 0 AND ?1 NOT IN "
                            "('queued','running') THEN ?2 ELSE finished END, "
                            "reason=coalesce(?, reason) WHERE id=?";
    int rc = AA_EINVAL;
    if (sqlite3_prepare_v2(st->db, sql, -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_text(q, 1, job_state_name(state), -1, SQLITE_STATIC);
        sqlite3_bind_double(q, 2, when);
        bind_text_or_null(q, 3, reason);
        sqlite3_bind_int64(q, 4, id);
        rc = exec_stmt(st, q);
    }
    pthread_mutex_unlock(&st->lock);
    return rc;
}

int job_store_bump_crashes(job_store *st, long long id)
{
    pthread_mutex_lock(&st->lock);
    sqlite3_stmt *q;
    int n = -1;
    if (sqlite3_prepare_v2(st->db,
                           "UPDATE jobs SET crashes = crashes + 1 WHERE id=? RETURNING crashes", -1,
                           &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int64(q, 1, id);
        if (sqlite3_step(q) == SQLITE_ROW)
            n = sqlite3_column_int(q, 0);
        sqlite3_finalize(q);
    }
    pthread_mutex_unlock(&st->lock);
    return n;
}

int job_store_update_progress(job_store *st, long long id, double progress, const json_t *best,
                              const json_t *trace)
{
    pthread_mutex_lock(&st->lock);
    sqlite3_stmt *q;
    int rc = AA_EINVAL;
    if (sqlite3_prepare_v2(st->db,
                           "UPDATE jobs SET progress=?, best=coalesce(?, best), "
                           "trace=coalesce(?, trace) WHERE id=?",
                           -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_double(q, 1, progress);
        bind_json(q, 2, best);
        bind_json(q, 3, trace);
        sqlite3_bind_int64(q, 4, id);
        rc = exec_stmt(st, q);
    }
    pthread_mutex_unlock(&st->lock);
    return rc;
}

int job_store_finish(job_store *st, long long id, job_state state, double progress,
                     const json_t *best, const json_t *trace, const json_t *result,
                     const json_t *error, const char *reason, double finished)
{
    pthread_mutex_lock(&st->lock);
    sqlite3_stmt *q;
    int rc = AA_EINVAL;
    if (sqlite3_prepare_v2(st->db,
                           "UPDATE jobs SET state=?, progress=?, best=coalesce(?, best), "
                           "trace=coalesce(?, trace), result=?, error=?, "
                           "reason=coalesce(?, reason), finished=? WHERE id=?",
                           -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_text(q, 1, job_state_name(state), -1, SQLITE_STATIC);
        sqlite3_bind_double(q, 2, progress);
        bind_json(q, 3, best);
        bind_json(q, 4, trace);
        bind_json(q, 5, result);
        bind_json(q, 6, error);
        bind_text_or_null(q, 7, reason);
        if (job_state_final(state))
            sqlite3_bind_double(q, 8, finished);
        else
            sqlite3_bind_null(q, 8);
        sqlite3_bind_int64(q, 9, id);
        rc = exec_stmt(st, q);
    }
    pthread_mutex_unlock(&st->lock);
    return rc;
}

static json_t *column_json(sqlite3_stmt *q, int i)
{
    const unsigned char *t = sqlite3_column_text(q, i);
    if (!t)
        return json_null();
    json_t *j = json_loads((const char *)t, JSON_DECODE_ANY, NULL);
    return j ? j : json_null();
}

static json_t *column_number_or_null(sqlite3_stmt *q, int i)
{
    return sqlite3_column_type(q, i) == SQLITE_NULL ? json_null()
                                                    : json_real(sqlite3_column_double(q, i));
}

/* Row (id, kind, owner_uid, state, progress, created, started, finished, reason, error, best,
 * spec, trace, result) -> API object. */
static json_t *row_to_json(sqlite3_stmt *q, bool full)
{
    json_t *o = json_object();
    json_object_set_new(o, "id", json_integer(sqlite3_column_int64(q, 0)));
    json_object_set_new(o, "kind", json_string((const char *)sqlite3_column_text(q, 1)));
    json_object_set_new(o, "owner_uid",
                        sqlite3_column_type(q, 2) == SQLITE_NULL
                            ? json_null()
                            : json_integer(sqlite3_column_int64(q, 2)));
    json_object_set_new(o, "state", json_string((const char *)sqlite3_column_text(q, 3)));
    json_object_set_new(o, "progress", json_real(sqlite3_column_double(q, 4)));
    json_object_set_new(o, "created", column_number_or_null(q, 5));
    json_object_set_new(o, "started", column_number_or_null(q, 6));
    json_object_set_new(o, "finished", column_number_or_null(q, 7));
    if (sqlite3_column_type(q, 8) != SQLITE_NULL)
        json_object_set_new(o, "reason", json_string((const char *)sqlite3_column_text(q, 8)));
    if (sqlite3_column_type(q, 9) != SQLITE_NULL)
        json_object_set_new(o, "error", column_json(q, 9));
    json_t *best = column_json(q, 10);
    json_t *e2 = json_is_object(best) ? json_object_get(best, "e2") : NULL;
    if (json_is_number(e2))
        json_object_set(o, "best_e2", e2);
    if (full) {
        json_object_set_new(o, "best", best);
        json_object_set_new(o, "spec", column_json(q, 11));
        json_t *trace = column_json(q, 12);
        json_object_set_new(o, "trace", json_is_array(trace) ? trace : json_array());
        if (!json_is_array(trace))
            json_decref(trace);
        json_object_set_new(o, "result", column_json(q, 13));
    } else {
        json_decref(best);
    }
    return o;
}

#define JOB_COLUMNS                                                                                \
    "id, kind, owner_uid, state, progress, created, started, finished, reason, error, best, "      \
    "spec, trace, result"

json_t *job_store_get(job_store *st, long long id, bool full)
{
    pthread_mutex_lock(&st->lock);
    sqlite3_stmt *q;
    json_t *o = NULL;
    if (sqlite3_prepare_v2(st->db, "SELECT " JOB_COLUMNS " FROM jobs WHERE id=?", -1, &q, NULL) ==
        SQLITE_OK) {
        sqlite3_bind_int64(q, 1, id);
        if (sqlite3_step(q) == SQLITE_ROW)
            o = row_to_json(q, full);
        sqlite3_finalize(q);
    }
    pthread_mutex_unlock(&st->lock);
    return o;
}

json_t *job_store_list(job_store *st, int limit, int state)
{
    pthread_mutex_lock(&st->lock);
    sqlite3_stmt *q;
    json_t *a = json_array();
    if (sqlite3_prepare_v2(st->db,
                           "SELECT id, kind, owner_uid, state, progress, created, started, "
                           "finished, reason, error, best FROM jobs WHERE ?2 IS NULL OR "
                           "state = ?2 ORDER BY id DESC LIMIT ?1",
                           -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int(q, 1, limit);
        if (state >= 0)
            sqlite3_bind_text(q, 2, job_state_name((job_state)state), -1, SQLITE_STATIC);
        while (sqlite3_step(q) == SQLITE_ROW)
            json_array_append_new(a, row_to_json(q, false));
        sqlite3_finalize(q);
    }
    pthread_mutex_unlock(&st->lock);
    return a;
}

int job_store_counts(job_store *st, long long counts[JOB_STATE_COUNT])
{
    memset(counts, 0, sizeof(long long) * JOB_STATE_COUNT);
    pthread_mutex_lock(&st->lock);
    sqlite3_stmt *q;
    int rc = AA_EINVAL;
    if (sqlite3_prepare_v2(st->db, "SELECT state, count(*) FROM jobs GROUP BY state", -1, &q,
                           NULL) == SQLITE_OK) {
        while (sqlite3_step(q) == SQLITE_ROW)
            counts[state_from_name((const char *)sqlite3_column_text(q, 0))] +=
                sqlite3_column_int64(q, 1);
        sqlite3_finalize(q);
        rc = AA_OK;
    }
    pthread_mutex_unlock(&st->lock);
    return rc;
}

int job_store_unfinished(job_store *st, job_store_visit_fn fn, void *user)
{
    /* Collect first, call after unlocking: fn may write to the store. */
    pthread_mutex_lock(&st->lock);
    sqlite3_stmt *q;
    json_t *rows = json_array();
    if (sqlite3_prepare_v2(st->db,
                           "SELECT id, kind, spec, owner_uid, state, created FROM jobs "
                           "WHERE state IN ('queued','running') ORDER BY id",
                           -1, &q, NULL) == SQLITE_OK) {
        while (sqlite3_step(q) == SQLITE_ROW) {
            json_t *spec = column_json(q, 2);
            json_array_append_new(
                rows,
                json_pack("{s:I,s:s,s:o,s:I,s:s,s:f}", "id", (json_int_t)sqlite3_column_int64(q, 0),
                          "kind", (const char *)sqlite3_column_text(q, 1), "spec", spec, "owner",
                          (json_int_t)(sqlite3_column_type(q, 3) == SQLITE_NULL
                                           ? -1
                                           : sqlite3_column_int64(q, 3)),
                          "state", (const char *)sqlite3_column_text(q, 4), "created",
                          sqlite3_column_double(q, 5)));
        }
        sqlite3_finalize(q);
    }
    pthread_mutex_unlock(&st->lock);
    size_t i;
    json_t *r;
    json_array_foreach(rows, i, r)
    {
        fn(user, json_integer_value(json_object_get(r, "id")),
           json_string_value(json_object_get(r, "kind")), json_object_get(r, "spec"),
           json_integer_value(json_object_get(r, "owner")),
           state_from_name(json_string_value(json_object_get(r, "state"))),
           json_real_value(json_object_get(r, "created")));
    }
    json_decref(rows);
    return AA_OK;
}
