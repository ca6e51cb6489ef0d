/* Reads from the job store on the read connections (WAL readers: never blocked by, never
 * blocking, the writer). Column texts are copied out and parsed after the connection is
 * released, so a large job held by one reader delays nobody. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "job_derived.h"
#include "job_store_impl.h"

static char *column_dup(sqlite3_stmt *q, int i)
{
    const unsigned char *t = sqlite3_column_text(q, i);
    return t ? strdup((const char *)t) : NULL;
}

static json_t *number_or_null(sqlite3_stmt *q, int i)
{
    return sqlite3_column_type(q, i) == SQLITE_NULL ? json_null()
                                                    : json_real(sqlite3_column_double(q, i));
}

static json_t *text_or_null(sqlite3_stmt *q, int i)
{
    const unsigned char *t = sqlite3_column_text(q, i);
    return t ? json_string((const char *)t) : json_null();
}

/* Parses a stored JSON text (NULL or invalid -> JSON null); frees the text. */
static json_t *parse_owned(char *text)
{
    json_t *j = text ? json_loads(text, JSON_DECODE_ANY, NULL) : NULL;
    free(text);
    return j ? j : json_null();
}

/* JOB_SUMMARY_COLUMNS of the row -> the job object; *error_text gets the error column to parse
 * once the connection is released. */
static json_t *row_summary(sqlite3_stmt *q, char **error_text)
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
    json_object_set_new(o, "created", number_or_null(q, 5));
    json_object_set_new(o, "started", number_or_null(q, 6));
    json_object_set_new(o, "finished", number_or_null(q, 7));
    if (sqlite3_column_type(q, 8) != SQLITE_NULL)
        json_object_set_new(o, "reason", json_string((const char *)sqlite3_column_text(q, 8)));
    *error_text = column_dup(q, 9);
    json_object_set_new(o, "best_e2", number_or_null(q, 10));
    json_object_set_new(o, "family", text_or_null(q, 11));
    const unsigned char *vis = sqlite3_column_text(q, 12);
    json_object_set_new(o, "visibility", json_string(vis ? (const char *)vis : "team"));
    json_object_set_new(o, "pinned", json_boolean(sqlite3_column_int(q, 13)));
    json_object_set_new(o, "bytes", json_integer(sqlite3_column_int64(q, 14)));
    json_object_set_new(o, "label", text_or_null(q, 15));
    return o;
}

static void attach_error(json_t *o, char *error_text)
{
    if (error_text)
        json_object_set_new(o, "error", parse_owned(error_text));
}

json_t *job_store_get(job_store *st, long long id, bool full)
{
    job_store_reader *r = job_store_reader_acquire(st);
    sqlite3_stmt *q;
    json_t *o = NULL;
    char *error_text = NULL, *big[4] = {NULL, NULL, NULL, NULL}; /* best spec trace result */
    if (sqlite3_prepare_v2(r->db,
                           full ? "SELECT " JOB_SUMMARY_COLUMNS ", best, " JOB_SPEC_EXPR
                                  ", trace, result FROM jobs WHERE id=?"
                                : "SELECT " JOB_SUMMARY_COLUMNS " FROM jobs WHERE id=?",
                           -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int64(q, 1, id);
        if (sqlite3_step(q) == SQLITE_ROW) {
            o = row_summary(q, &error_text);
            for (int i = 0; full && i < 4; i++)
                big[i] = column_dup(q, JOB_SUMMARY_COUNT + i);
        }
        sqlite3_finalize(q);
    }
    job_store_reader_release(r);
    if (!o)
        return NULL;
    attach_error(o, error_text);
    if (full) {
        json_t *best = parse_owned(big[0]);
        job_derived_restore(best);
        json_object_set_new(o, "best", best);
        json_object_set_new(o, "spec", parse_owned(big[1]));
        json_t *trace = parse_owned(big[2]);
        if (!json_is_array(trace)) {
            json_decref(trace);
            trace = json_array();
        }
        json_object_set_new(o, "trace", trace);
        json_t *result = parse_owned(big[3]);
        job_derived_restore(result);
        json_object_set_new(o, "result", result);
    }
    return o;
}

bool job_store_owner(job_store *st, long long id, long long *owner, job_state *state,
                     bool *private_job)
{
    job_store_reader *r = job_store_reader_acquire(st);
    sqlite3_stmt *q;
    bool found = false;
    if (sqlite3_prepare_v2(
            r->db,
            "SELECT coalesce(owner_uid, -1), state, visibility = 'private' FROM jobs WHERE id=?",
            -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int64(q, 1, id);
        if (sqlite3_step(q) == SQLITE_ROW) {
            found = true;
            if (owner)
                *owner = sqlite3_column_int64(q, 0);
            if (state)
                *state = job_state_from_name((const char *)sqlite3_column_text(q, 1));
            if (private_job)
                *private_job = sqlite3_column_int(q, 2) != 0;
        }
        sqlite3_finalize(q);
    }
    job_store_reader_release(r);
    return found;
}

json_t *job_store_list(job_store *st, const job_store_filter *f)
{
    job_store_reader *r = job_store_reader_acquire(st);
    sqlite3_stmt *q;
    json_t *a = json_array();
    char **errors = NULL;
    /* jobs_list covers every column read: the rows' JSON is never touched. */
    if (sqlite3_prepare_v2(r->db,
                           "SELECT " JOB_SUMMARY_COLUMNS " FROM jobs INDEXED BY jobs_list "
                           "WHERE (?2 IS NULL OR state = ?2) AND (?3 IS NULL OR kind = ?3) "
                           "AND (?4 = -1 OR visibility <> 'private' OR owner_uid = ?4) "
                           "ORDER BY id DESC LIMIT ?1",
                           -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int(q, 1, f->limit);
        if (f->state >= 0)
            sqlite3_bind_text(q, 2, job_state_name((job_state)f->state), -1, SQLITE_STATIC);
        if (f->kind)
            sqlite3_bind_text(q, 3, f->kind, -1, SQLITE_TRANSIENT);
        sqlite3_bind_int64(q, 4, f->viewer);
        errors = calloc(f->limit > 0 ? (size_t)f->limit : 1, sizeof *errors);
        while (errors && sqlite3_step(q) == SQLITE_ROW) {
            size_t n = json_array_size(a);
            json_array_append_new(a, row_summary(q, &errors[n]));
        }
        sqlite3_finalize(q);
    }
    job_store_reader_release(r);
    for (size_t i = 0; errors && i < json_array_size(a); i++)
        attach_error(json_array_get(a, i), errors[i]);
    free(errors);
    return a;
}

int job_store_counts(job_store *st, long long counts[JOB_STATE_COUNT])
{
    memset(counts, 0, sizeof(long long) * JOB_STATE_COUNT);
    job_store_reader *r = job_store_reader_acquire(st);
    sqlite3_stmt *q;
    int rc = AA_EINVAL;
    if (sqlite3_prepare_v2(r->db, "SELECT state, count(*) FROM jobs GROUP BY state", -1, &q,
                           NULL) == SQLITE_OK) {
        while (sqlite3_step(q) == SQLITE_ROW)
            counts[job_state_from_name((const char *)sqlite3_column_text(q, 0))] +=
                sqlite3_column_int64(q, 1);
        sqlite3_finalize(q);
        rc = AA_OK;
    }
    job_store_reader_release(r);
    return rc;
}

int job_store_counts_visible(job_store *st, long long viewer, long long counts[JOB_STATE_COUNT])
{
    if (viewer == JOB_VIEWER_ALL)
        return job_store_counts(st, counts);
    memset(counts, 0, sizeof(long long) * JOB_STATE_COUNT);
    job_store_reader *r = job_store_reader_acquire(st);
    sqlite3_stmt *q;
    int rc = AA_EINVAL;
    if (sqlite3_prepare_v2(r->db,
                           "SELECT state, count(*) FROM jobs WHERE visibility <> 'private' OR "
                           "owner_uid = ?1 GROUP BY state",
                           -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int64(q, 1, viewer);
        while (sqlite3_step(q) == SQLITE_ROW)
            counts[job_state_from_name((const char *)sqlite3_column_text(q, 0))] +=
                sqlite3_column_int64(q, 1);
        sqlite3_finalize(q);
        rc = AA_OK;
    }
    job_store_reader_release(r);
    return rc;
}

int job_store_usage_of(job_store *st, long long owner, job_store_usage *out)
{
    *out = (job_store_usage){.limit = st->user_quota};
    job_store_reader *r = job_store_reader_acquire(st);
    sqlite3_stmt *q;
    int rc = AA_EINVAL;
    if (sqlite3_prepare_v2(r->db,
                           "SELECT coalesce(sum(max(bytes, reserve)), 0), count(*) FROM jobs "
                           "INDEXED BY jobs_usage WHERE owner_uid = ?",
                           -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int64(q, 1, owner);
        if (sqlite3_step(q) == SQLITE_ROW) {
            out->bytes = sqlite3_column_int64(q, 0);
            out->jobs = sqlite3_column_int64(q, 1);
            rc = AA_OK;
        }
        sqlite3_finalize(q);
    }
    job_store_reader_release(r);
    return rc;
}

json_t *job_store_usage_all(job_store *st)
{
    job_store_reader *r = job_store_reader_acquire(st);
    sqlite3_stmt *q;
    json_t *a = json_array();
    if (sqlite3_prepare_v2(r->db,
                           "SELECT owner_uid, sum(max(bytes, reserve)) AS b, count(*) FROM jobs "
                           "INDEXED BY jobs_usage GROUP BY owner_uid ORDER BY b DESC",
                           -1, &q, NULL) == SQLITE_OK) {
        while (sqlite3_step(q) == SQLITE_ROW)
            json_array_append_new(a, json_pack("{s:o,s:I,s:I}", "owner_uid",
                                               sqlite3_column_type(q, 0) == SQLITE_NULL
                                                   ? json_null()
                                                   : json_integer(sqlite3_column_int64(q, 0)),
                                               "bytes", (json_int_t)sqlite3_column_int64(q, 1),
                                               "jobs", (json_int_t)sqlite3_column_int64(q, 2)));
        sqlite3_finalize(q);
    }
    job_store_reader_release(r);
    return a;
}

int job_store_unfinished(job_store *st, job_store_visit_fn fn, void *user)
{
    /* Collect first, call after releasing: fn may write to the store. */
    job_store_reader *r = job_store_reader_acquire(st);
    sqlite3_stmt *q;
    typedef struct row {
        long long id, owner;
        int priority;
        bool private_job;
        char *kind, *spec, *state;
        double created;
    } row;
    row *rows = NULL;
    size_t n = 0, cap = 0;
    if (sqlite3_prepare_v2(
            r->db,
            "SELECT id, kind, " JOB_SPEC_EXPR
            ", coalesce(owner_uid, -1), state, created, priority, visibility = 'private' "
            "FROM jobs WHERE state IN ('queued','running') ORDER BY id",
            -1, &q, NULL) == SQLITE_OK) {
        while (sqlite3_step(q) == SQLITE_ROW) {
            if (n == cap) {
                size_t c = cap ? 2 * cap : 16;
                row *g = realloc(rows, c * sizeof *g);
                if (!g)
                    break;
                rows = g;
                cap = c;
            }
            rows[n++] = (row){.id = sqlite3_column_int64(q, 0),
                              .kind = column_dup(q, 1),
                              .spec = column_dup(q, 2),
                              .owner = sqlite3_column_int64(q, 3),
                              .state = column_dup(q, 4),
                              .created = sqlite3_column_double(q, 5),
                              .priority = sqlite3_column_int(q, 6),
                              .private_job = sqlite3_column_int(q, 7) != 0};
        }
        sqlite3_finalize(q);
    }
    job_store_reader_release(r);
    for (size_t i = 0; i < n; i++) {
        json_t *spec = parse_owned(rows[i].spec);
        fn(user, rows[i].id, rows[i].kind, spec, rows[i].owner, rows[i].priority,
           rows[i].private_job, job_state_from_name(rows[i].state), rows[i].created);
        json_decref(spec);
        free(rows[i].kind);
        free(rows[i].state);
    }
    free(rows);
    return AA_OK;
}

json_t *job_store_get_cluster(job_store *st, long long id)
{
    job_store_reader *r = job_store_reader_acquire(st);
    sqlite3_stmt *q;
    char *text = NULL;
    if (sqlite3_prepare_v2(r->db, "SELECT cluster FROM jobs WHERE id=?", -1, &q, NULL) ==
        SQLITE_OK) {
        sqlite3_bind_int64(q, 1, id);
        if (sqlite3_step(q) == SQLITE_ROW)
            text = column_dup(q, 0);
        sqlite3_finalize(q);
    }
    job_store_reader_release(r);
    if (!text)
        return NULL;
    json_error_t e;
    json_t *o = json_loads(text, JSON_REJECT_DUPLICATES, &e);
    free(text);
    return o;
}
