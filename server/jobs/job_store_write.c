/* Writes to the job store, under the store mutex on the write connection. Every write keeps
 * the row's bytes column (spec + best + trace + result + error) up to date and refuses to take
 * an owner over the user quota (job_store.h). JSON is encoded before the mutex is taken. */
#define _POSIX_C_SOURCE 200809L
#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "job_derived.h"
#include "job_store_impl.h"
#include "lock_held.h"
#include "wire_error.h"

/* A JSON value encoded for a column, derived keys stripped; text NULL = SQL NULL. */
typedef struct encoded {
    char *text;
    long long len;
} encoded;

static encoded encode(const json_t *j, bool strip_derived)
{
    encoded e = {0};
    if (!j)
        return e;
    json_t *stripped = strip_derived ? job_derived_stripped(j) : NULL;
    e.text = json_dumps(stripped ? stripped : j, JSON_COMPACT | JSON_ENCODE_ANY);
    json_decref(stripped);
    e.len = e.text ? (long long)strlen(e.text) : 0;
    return e;
}

static void bind_encoded(sqlite3_stmt *q, int i, const encoded *e)
{
    if (e->text)
        sqlite3_bind_text(q, i, e->text, (int)e->len, SQLITE_STATIC);
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

/* A failed write: JOB_STORE_EUNAVAILABLE when the database could not be written now (disk
 * full, I/O, locked), which passes, else JOB_STORE_EWRITE. */
static int write_error(int rc)
{
    switch (rc & 0xff) {
    case SQLITE_FULL:
    case SQLITE_IOERR:
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
    case SQLITE_READONLY:
    case SQLITE_CANTOPEN:
    case SQLITE_NOMEM:
        return JOB_STORE_EUNAVAILABLE;
    default:
        return JOB_STORE_EWRITE;
    }
}

static int step_done(sqlite3_stmt *q)
{
    int rc = sqlite3_step(q);
    sqlite3_finalize(q);
    return rc == SQLITE_DONE ? AA_OK : write_error(rc);
}

/* Gives free pages back to the file system once more than 1 MiB is free, so jobs.db follows
 * what is stored (auto_vacuum=INCREMENTAL databases; elsewhere freelist pages are reused by
 * later writes). Not after progress writes: the next one reuses the pages they free.
 * Caller holds st->lock. */
static void trim(job_store *st)
{
    ASSERT_LOCK_HELD(&st->lock);
    sqlite3_stmt *q;
    long long free_pages = 0;
    if (sqlite3_prepare_v2(st->db, "PRAGMA freelist_count", -1, &q, NULL) == SQLITE_OK) {
        if (sqlite3_step(q) == SQLITE_ROW)
            free_pages = sqlite3_column_int64(q, 0);
        sqlite3_finalize(q);
    }
    if (free_pages > 256)
        sqlite3_exec(st->db, "PRAGMA incremental_vacuum", NULL, NULL, NULL);
}

/* Stored bytes plus reserves of owner's jobs other than `except`. Caller holds st->lock. */
static long long usage_except(job_store *st, long long owner, long long except)
{
    ASSERT_LOCK_HELD(&st->lock);
    sqlite3_stmt *q;
    long long sum = 0;
    if (sqlite3_prepare_v2(st->db,
                           "SELECT coalesce(sum(max(bytes, reserve)), 0) FROM jobs "
                           "INDEXED BY jobs_usage WHERE owner_uid = ? AND id <> ?",
                           -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int64(q, 1, owner);
        sqlite3_bind_int64(q, 2, except);
        if (sqlite3_step(q) == SQLITE_ROW)
            sum = sqlite3_column_int64(q, 0);
        sqlite3_finalize(q);
    }
    return sum;
}

int job_store_insert(job_store *st, const job_store_new *job, long long *id, aa_error *err)
{
    encoded spec = encode(job->spec, false);
    if (!spec.text)
        return aa_error_set(err, JOB_STORE_EUNAVAILABLE, "", "out of memory");
    long long reserve = 2 * spec.len + JOB_STORE_RESERVE_EXTRA;
    pthread_mutex_lock(&st->lock);
    job_store_sync(st, true);
    int out = AA_OK;
    /* Checked and inserted under one lock: two submissions cannot both take the last bytes. */
    if (job->owner >= 0 && st->user_quota > 0) {
        long long used = usage_except(st, job->owner, 0);
        if (used + reserve > st->user_quota)
            out = aa_error_set(err, JOB_STORE_EQUOTA, "",
                               "uid %lld stores %lld bytes of jobs; this job needs %lld more (its "
                               "%lld-byte spec and a reserve for its best, trace and result) and "
                               "the limit is %lld bytes: purge jobs (DELETE /v1/jobs/ID?purge=1)",
                               job->owner, used, reserve, spec.len, st->user_quota);
    }
    /* The row and its spec (job_specs) in one transaction. */
    bool began = !out && sqlite3_exec(st->db, "BEGIN IMMEDIATE", NULL, NULL, NULL) == SQLITE_OK;
    bool ok = false;
    long long new_id = 0;
    sqlite3_stmt *q = NULL;
    if (began && sqlite3_prepare_v2(st->db,
                                    "INSERT INTO jobs(kind, owner_uid, state, spec, created, "
                                    "visibility, pinned, priority, family, bytes, reserve, label) "
                                    "VALUES (?, ?, 'queued', '', ?, ?, ?, ?, ?, ?, ?, ?)",
                                    -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_text(q, 1, job->kind, -1, SQLITE_TRANSIENT);
        if (job->owner >= 0)
            sqlite3_bind_int64(q, 2, job->owner);
        else
            sqlite3_bind_null(q, 2);
        sqlite3_bind_double(q, 3, job->created);
        sqlite3_bind_text(q, 4, job->visibility ? job->visibility : "team", -1, SQLITE_TRANSIENT);
        sqlite3_bind_int(q, 5, job->pinned);
        sqlite3_bind_int(q, 6, job->priority);
        bind_text_or_null(q, 7, job->family);
        sqlite3_bind_int64(q, 8, spec.len);
        sqlite3_bind_int64(q, 9, reserve);
        bind_text_or_null(q, 10, job->label && *job->label ? job->label : NULL);
        ok = step_done(q) == AA_OK;
        new_id = sqlite3_last_insert_rowid(st->db);
    }
    if (ok && sqlite3_prepare_v2(st->db, "INSERT INTO job_specs(job_id, spec) VALUES (?, ?)", -1,
                                 &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int64(q, 1, new_id);
        bind_encoded(q, 2, &spec);
        ok = step_done(q) == AA_OK;
    } else {
        ok = false;
    }
    if (ok)
        ok = sqlite3_exec(st->db, "COMMIT", NULL, NULL, NULL) == SQLITE_OK;
    if (ok) {
        *id = new_id;
    } else if (!out) {
        out = aa_error_set(err, JOB_STORE_EWRITE, "", "job store write failed: %s",
                           sqlite3_errmsg(st->db));
        if (began)
            sqlite3_exec(st->db, "ROLLBACK", NULL, NULL, NULL);
    }
    pthread_mutex_unlock(&st->lock);
    free(spec.text);
    return out;
}

#ifndef NDEBUG
/* May the row go to `to` from its stored state (job_state_edge_legal)? No row: the write
 * changes nothing. Debug builds only (asserts): one more query per state change. */
static bool stored_edge_legal(job_store *st, long long id, job_state to)
{
    ASSERT_LOCK_HELD(&st->lock);
    sqlite3_stmt *q;
    bool legal = true;
    if (sqlite3_prepare_v2(st->db, "SELECT state FROM jobs WHERE id = ?", -1, &q, NULL) ==
        SQLITE_OK) {
        sqlite3_bind_int64(q, 1, id);
        if (sqlite3_step(q) == SQLITE_ROW)
            legal = job_state_edge_legal(
                job_state_from_name((const char *)sqlite3_column_text(q, 0)), to);
        sqlite3_finalize(q);
    }
    return legal;
}
#endif

int job_store_set_state(job_store *st, long long id, job_state state, double when,
                        const char *reason)
{
    pthread_mutex_lock(&st->lock);
    assert(stored_edge_legal(st, id, state));
    job_store_sync(st, true);
    sqlite3_stmt *q;
    const char *sql = state == JOB_RUNNING
                          ? "UPDATE jobs SET state=?, started=?, reason=coalesce(?, reason) "
                            "WHERE id=?"
                          : "UPDATE jobs SET state=?, finished=CASE WHEN ?2 > 0 AND ?1 NOT IN "
                            "('queued','running') THEN ?2 ELSE finished END, "
                            "reason=coalesce(?, reason) WHERE id=?";
    int rc = JOB_STORE_EWRITE;
    if (sqlite3_prepare_v2(st->db, sql, -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_text(q, 1, job_state_name(state), -1, SQLITE_STATIC);
        sqlite3_bind_double(q, 2, when);
        bind_text_or_null(q, 3, reason);
        sqlite3_bind_int64(q, 4, id);
        rc = step_done(q);
    }
    pthread_mutex_unlock(&st->lock);
    return rc;
}

int job_store_bump_crashes(job_store *st, long long id)
{
    pthread_mutex_lock(&st->lock);
    job_store_sync(st, true);
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

/* Sizes of a row's JSON columns, its owner and reserve. Caller holds st->lock. */
typedef struct row_sizes {
    long long owner, reserve;
    long long spec, best, trace, result, error;
} row_sizes;

static bool read_sizes(job_store *st, long long id, row_sizes *s)
{
    ASSERT_LOCK_HELD(&st->lock);
    sqlite3_stmt *q;
    bool found = false;
    if (sqlite3_prepare_v2(st->db,
                           "SELECT coalesce(owner_uid, -1), reserve, bytes, "
                           "coalesce(length(CAST(best AS BLOB)), 0), "
                           "coalesce(length(CAST(trace AS BLOB)), 0), "
                           "coalesce(length(CAST(result AS BLOB)), 0), "
                           "coalesce(length(CAST(error AS BLOB)), 0) FROM jobs WHERE id = ?",
                           -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int64(q, 1, id);
        if (sqlite3_step(q) == SQLITE_ROW) {
            found = true;
            long long *f[] = {&s->owner, &s->reserve, &s->spec, &s->best,
                              &s->trace, &s->result,  &s->error};
            for (int i = 0; i < 7; i++)
                *f[i] = sqlite3_column_int64(q, i);
            /* bytes is spec + the rest: the spec itself need not be read. */
            s->spec -= s->best + s->trace + s->result + s->error;
        }
        sqlite3_finalize(q);
    }
    return found;
}

/* Would the owner's jobs exceed the quota with this job at `bytes` (reserve kept)? */
static bool over_quota(job_store *st, long long id, const row_sizes *s, long long bytes,
                       long long reserve)
{
    if (s->owner < 0 || st->user_quota <= 0)
        return false;
    long long mine = bytes > reserve ? bytes : reserve;
    return usage_except(st, s->owner, id) + mine > st->user_quota;
}

static void bind_summary(sqlite3_stmt *q, int i, const json_t *best)
{
    double e2 = job_derived_best_e2(best);
    if (isfinite(e2))
        sqlite3_bind_double(q, i, e2);
    else
        sqlite3_bind_null(q, i);
    bind_text_or_null(q, i + 1, job_derived_family(best));
}

int job_store_update_progress(job_store *st, long long id, double progress, const json_t *best,
                              const json_t *trace)
{
    encoded b = encode(best, true), t = encode(trace, false);
    pthread_mutex_lock(&st->lock);
    job_store_sync(st, false);
    int rc = JOB_STORE_EWRITE;
    row_sizes s;
    if (read_sizes(st, id, &s)) {
        long long bytes =
            s.spec + (b.text ? b.len : s.best) + (t.text ? t.len : s.trace) + s.result + s.error;
        bool keep = (b.text || t.text) && over_quota(st, id, &s, bytes, s.reserve);
        sqlite3_stmt *q;
        if (sqlite3_prepare_v2(st->db,
                               keep ? "UPDATE jobs SET progress=?1 WHERE id=?4"
                                    : "UPDATE jobs SET progress=?1, best=coalesce(?2, best), "
                                      "trace=coalesce(?3, trace), bytes=?4, "
                                      "best_e2=CASE WHEN ?2 IS NULL THEN best_e2 ELSE ?5 END, "
                                      "family=CASE WHEN ?2 IS NULL OR ?6 IS NULL THEN family "
                                      "ELSE ?6 END WHERE id=?7",
                               -1, &q, NULL) == SQLITE_OK) {
            sqlite3_bind_double(q, 1, progress);
            if (keep) {
                sqlite3_bind_int64(q, 4, id);
            } else {
                bind_encoded(q, 2, &b);
                bind_encoded(q, 3, &t);
                sqlite3_bind_int64(q, 4, bytes);
                bind_summary(q, 5, best);
                sqlite3_bind_int64(q, 7, id);
            }
            rc = step_done(q);
            if (!rc && keep)
                rc = JOB_STORE_EQUOTA;
        }
    }
    job_store_sync(st, true);
    pthread_mutex_unlock(&st->lock);
    free(b.text);
    free(t.text);
    return rc;
}

int job_store_finish(job_store *st, long long id, job_state state, double progress,
                     const json_t *best, const json_t *trace, const json_t *result,
                     const json_t *error, const char *reason, double finished)
{
    encoded b = encode(best, true), t = encode(trace, false), r = encode(result, true),
            e = encode(error, false);
    char quota_reason[256] = "";
    pthread_mutex_lock(&st->lock);
    assert(stored_edge_legal(st, id, state));
    job_store_sync(st, true);
    int rc = JOB_STORE_EWRITE;
    row_sizes s;
    if (read_sizes(st, id, &s)) {
        long long reserve = job_state_final(state) ? 0 : s.reserve;
        long long bytes =
            s.spec + (b.text ? b.len : s.best) + (t.text ? t.len : s.trace) + r.len + e.len;
        bool drop = over_quota(st, id, &s, bytes, reserve);
        if (drop) {
            /* The output does not fit: keep the spec and say why, store nothing else. */
            snprintf(quota_reason, sizeof quota_reason,
                     "the job's output (%lld bytes) would take uid %lld over its store quota "
                     "of %lld bytes; best, trace and result were not stored",
                     bytes - s.spec, s.owner, st->user_quota);
            free(b.text);
            free(t.text);
            free(r.text);
            free(e.text);
            b = t = r = (encoded){0};
            json_t *ej =
                json_pack("{s:s,s:s,s:s}", "code", proto_wire_row_of(WIRE_QUOTA_EXCEEDED)->code,
                          "message", quota_reason, "field", "");
            e = encode(ej, false);
            json_decref(ej);
            if (state == JOB_DONE)
                state = JOB_FAILED;
            reason = quota_reason;
            bytes = s.spec + e.len;
        }
        sqlite3_stmt *q;
        if (sqlite3_prepare_v2(
                st->db,
                "UPDATE jobs SET state=?1, progress=?2, "
                "best=CASE WHEN ?12 THEN NULL ELSE coalesce(?3, best) END, "
                "trace=CASE WHEN ?12 THEN NULL ELSE coalesce(?4, trace) END, result=?5, "
                "error=?6, reason=coalesce(?7, reason), finished=?8, bytes=?10, reserve=?11, "
                "best_e2=CASE WHEN ?12 THEN NULL WHEN ?3 IS NULL THEN best_e2 ELSE ?13 END, "
                "family=CASE WHEN ?3 IS NULL OR ?14 IS NULL THEN family ELSE ?14 END "
                "WHERE id=?9",
                -1, &q, NULL) == SQLITE_OK) {
            sqlite3_bind_text(q, 1, job_state_name(state), -1, SQLITE_STATIC);
            sqlite3_bind_double(q, 2, progress);
            bind_encoded(q, 3, &b);
            bind_encoded(q, 4, &t);
            bind_encoded(q, 5, &r);
            bind_encoded(q, 6, &e);
            bind_text_or_null(q, 7, reason);
            if (job_state_final(state))
                sqlite3_bind_double(q, 8, finished);
            else
                sqlite3_bind_null(q, 8);
            sqlite3_bind_int64(q, 9, id);
            sqlite3_bind_int64(q, 10, bytes);
            sqlite3_bind_int64(q, 11, reserve);
            sqlite3_bind_int(q, 12, drop);
            bind_summary(q, 13, drop ? NULL : best);
            rc = step_done(q);
        }
    }
    trim(st);
    pthread_mutex_unlock(&st->lock);
    free(b.text);
    free(t.text);
    free(r.text);
    free(e.text);
    return rc;
}

int job_store_delete(job_store *st, long long id, aa_error *err)
{
    pthread_mutex_lock(&st->lock);
    job_store_sync(st, true);
    sqlite3_stmt *q;
    int rc = JOB_STORE_EWRITE;
    if (sqlite3_prepare_v2(st->db,
                           "DELETE FROM jobs WHERE id = ? AND state NOT IN ('queued', 'running')",
                           -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int64(q, 1, id);
        rc = step_done(q);
        if (!rc && sqlite3_changes(st->db) == 0) {
            row_sizes s;
            rc = read_sizes(st, id, &s)
                     ? aa_error_set(err, JOB_STORE_EACTIVE, "", JOB_MSG_RUNNING, id)
                     : aa_error_set(err, JOB_STORE_ENOENT, "id", JOB_MSG_NOT_FOUND, id);
        }
    }
    trim(st);
    pthread_mutex_unlock(&st->lock);
    if (rc == JOB_STORE_EUNAVAILABLE || rc == JOB_STORE_EWRITE)
        aa_error_set(err, rc, "", JOB_MSG_UNWRITABLE, id);
    return rc;
}

int job_store_set_pinned(job_store *st, long long id, bool pinned, aa_error *err)
{
    pthread_mutex_lock(&st->lock);
    job_store_sync(st, true);
    sqlite3_stmt *q;
    int rc = JOB_STORE_EWRITE;
    if (sqlite3_prepare_v2(st->db, "UPDATE jobs SET pinned = ? WHERE id = ?", -1, &q, NULL) ==
        SQLITE_OK) {
        sqlite3_bind_int(q, 1, pinned);
        sqlite3_bind_int64(q, 2, id);
        rc = step_done(q);
        if (!rc && sqlite3_changes(st->db) == 0)
            rc = aa_error_set(err, JOB_STORE_ENOENT, "id", JOB_MSG_NOT_FOUND, id);
    }
    pthread_mutex_unlock(&st->lock);
    if (rc == JOB_STORE_EUNAVAILABLE || rc == JOB_STORE_EWRITE)
        aa_error_set(err, rc, "", JOB_MSG_UNWRITABLE, id);
    return rc;
}

int job_store_sweep(job_store *st, double before, long long *deleted)
{
    pthread_mutex_lock(&st->lock);
    job_store_sync(st, true);
    sqlite3_stmt *q;
    int rc = JOB_STORE_EWRITE;
    *deleted = 0;
    if (sqlite3_prepare_v2(st->db,
                           "DELETE FROM jobs WHERE pinned = 0 AND finished < ? AND state NOT IN "
                           "('queued', 'running')",
                           -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_double(q, 1, before);
        rc = step_done(q);
        if (!rc)
            *deleted = sqlite3_changes(st->db);
    }
    trim(st);
    pthread_mutex_unlock(&st->lock);
    return rc;
}

int job_store_set_cluster(job_store *st, long long id, const json_t *cluster)
{
    if (json_is_null(cluster))
        cluster = NULL; /* a local job again: the column is cleared */
    char *text = cluster ? json_dumps(cluster, JSON_COMPACT) : NULL;
    if (cluster && !text)
        return AA_ENOMEM;
    pthread_mutex_lock(&st->lock);
    /* The array ids must survive a crash: a lost write would resubmit running arrays. */
    job_store_sync(st, true);
    sqlite3_stmt *q;
    int rc = JOB_STORE_EWRITE;
    if (sqlite3_prepare_v2(st->db, "UPDATE jobs SET cluster=? WHERE id=?", -1, &q, NULL) ==
        SQLITE_OK) {
        bind_text_or_null(q, 1, text);
        sqlite3_bind_int64(q, 2, id);
        rc = step_done(q);
        if (!rc && sqlite3_changes(st->db) == 0)
            rc = JOB_STORE_ENOENT;
    }
    pthread_mutex_unlock(&st->lock);
    free(text);
    return rc;
}
