/* The jobs table and its migration. user_version 0 is the first schema (no list columns):
 * opening such a database adds the columns with ALTER TABLE and backfills them once, in one
 * transaction, from the JSON already stored. Version 2 lacks the label column: it is added and
 * filled from the specs that carried a label. Version 3 lacks the cluster column (added, NULL). */
#include <stdio.h>

#include "job_store_impl.h"

#define SCHEMA_VERSION 4              /* 4: the cluster column (Slurm executor state) */
#define SCHEMA_VERSION_LIST_COLUMNS 2 /* the first with best_e2, family, bytes, job_specs */

static const char create_sql[] = "CREATE TABLE IF NOT EXISTS jobs ("
                                 " id INTEGER PRIMARY KEY AUTOINCREMENT,"
                                 " kind TEXT NOT NULL,"
                                 " owner_uid INTEGER,"
                                 " state TEXT NOT NULL,"
                                 " progress REAL NOT NULL DEFAULT 0,"
                                 " spec TEXT NOT NULL,"
                                 " best TEXT, trace TEXT, result TEXT, error TEXT, reason TEXT,"
                                 " created REAL NOT NULL, started REAL, finished REAL);"
                                 "CREATE INDEX IF NOT EXISTS jobs_state ON jobs(state);";

/* Added after the first schema; a column that exists already is skipped. */
static const char *const added_columns[] = {
    "crashes INTEGER NOT NULL DEFAULT 0",
    "best_e2 REAL",
    "family TEXT",
    "visibility TEXT NOT NULL DEFAULT 'team'",
    "pinned INTEGER NOT NULL DEFAULT 0",
    "bytes INTEGER NOT NULL DEFAULT 0",
    "reserve INTEGER NOT NULL DEFAULT 0", /* bytes held for an unfinished job's output */
    "priority INTEGER NOT NULL DEFAULT 0",
    "label TEXT",
    /* The Slurm executor's state of a job (JSON: array ids per stage, retries): NULL for a job
     * run by the local workers. Read at restart to re-attach to the arrays. */
    "cluster TEXT",
};

/* job_specs keeps new jobs' specs out of the jobs row: a row is rewritten whole on update, and
 * a progress write should not copy a megabyte spec each time.
 * The list reads only jobs_list (a covering index in id order): the row itself, whose big
 * JSON columns precede the new ones and spill into overflow pages, is never touched.
 * jobs_usage makes a user's usage one index-only SUM; jobs_retention serves the sweep. */
static const char index_sql[] =
    "CREATE TABLE IF NOT EXISTS job_specs (job_id INTEGER PRIMARY KEY REFERENCES jobs(id) "
    " ON DELETE CASCADE, spec TEXT NOT NULL);"
    "DROP INDEX IF EXISTS jobs_list;"
    "CREATE INDEX jobs_list ON jobs(id, state, kind, owner_uid, visibility, "
    " pinned, progress, created, started, finished, best_e2, family, bytes, reason, error, label);"
    "CREATE INDEX IF NOT EXISTS jobs_usage ON jobs(owner_uid, bytes, reserve);"
    "CREATE INDEX IF NOT EXISTS jobs_retention ON jobs(pinned, finished);";

/* One-time backfill of rows written by the first schema (version 0 or 1) (SQLite's JSON1 does the
 * parsing, once, at migration). */
static const char backfill_sql[] =
    "UPDATE jobs SET"
    " bytes = length(CAST(spec AS BLOB)) + coalesce(length(CAST(best AS BLOB)), 0)"
    "  + coalesce(length(CAST(trace AS BLOB)), 0) + coalesce(length(CAST(result AS BLOB)), 0)"
    "  + coalesce(length(CAST(error AS BLOB)), 0),"
    " best_e2 = CASE WHEN json_valid(best) AND json_type(best, '$.e2') IN ('real', 'integer')"
    "  THEN json_extract(best, '$.e2') END,"
    " family = CASE WHEN json_valid(best) THEN coalesce(json_extract(best, '$.pattern.family'),"
    "  json_extract(best, '$.family')) END;"
    "UPDATE jobs SET family = json_extract(spec, '$.family')"
    " WHERE family IS NULL AND json_valid(spec) AND json_type(spec, '$.family') = 'text';"
    "UPDATE jobs SET reserve = 2 * length(CAST(spec AS BLOB)) + 262144"
    " WHERE state IN ('queued', 'running');";

/* Specs stored before the envelope took "label" out of them still carry it. */
static const char label_backfill_sql[] =
    "UPDATE jobs SET label = (SELECT CASE WHEN json_valid(t.s) AND"
    "  json_type(t.s, '$.label') = 'text' THEN substr(json_extract(t.s, '$.label'), 1, 200) END"
    "  FROM (SELECT " JOB_SPEC_EXPR " AS s) t) WHERE label IS NULL;";

static int user_version(sqlite3 *db)
{
    sqlite3_stmt *q;
    int v = -1;
    if (sqlite3_prepare_v2(db, "PRAGMA user_version", -1, &q, NULL) == SQLITE_OK) {
        if (sqlite3_step(q) == SQLITE_ROW)
            v = sqlite3_column_int(q, 0);
        sqlite3_finalize(q);
    }
    return v;
}

static bool has_column(sqlite3 *db, const char *decl)
{
    char name[64];
    if (sscanf(decl, "%63s", name) != 1)
        return false;
    sqlite3_stmt *q;
    bool found = false;
    if (sqlite3_prepare_v2(db, "SELECT 1 FROM pragma_table_info('jobs') WHERE name = ?", -1, &q,
                           NULL) == SQLITE_OK) {
        sqlite3_bind_text(q, 1, name, -1, SQLITE_TRANSIENT);
        found = sqlite3_step(q) == SQLITE_ROW;
        sqlite3_finalize(q);
    }
    return found;
}

int job_store_schema_init(sqlite3 *db, aa_error *err)
{
    char *msg = NULL;
    int version = user_version(db);
    if (version >= SCHEMA_VERSION)
        return AA_OK;
    if (sqlite3_exec(db, "BEGIN IMMEDIATE", NULL, NULL, &msg) != SQLITE_OK)
        goto fail;
    if (sqlite3_exec(db, create_sql, NULL, NULL, &msg) != SQLITE_OK)
        goto rollback;
    for (size_t i = 0; i < sizeof added_columns / sizeof added_columns[0]; i++) {
        if (has_column(db, added_columns[i]))
            continue;
        char sql[160];
        snprintf(sql, sizeof sql, "ALTER TABLE jobs ADD COLUMN %s", added_columns[i]);
        if (sqlite3_exec(db, sql, NULL, NULL, &msg) != SQLITE_OK)
            goto rollback;
    }
    char pragma[64];
    snprintf(pragma, sizeof pragma, "PRAGMA user_version = %d", SCHEMA_VERSION);
    /* Rows of a later schema keep their spec in job_specs: the backfill would misread them. */
    if ((version < SCHEMA_VERSION_LIST_COLUMNS &&
         sqlite3_exec(db, backfill_sql, NULL, NULL, &msg) != SQLITE_OK) ||
        sqlite3_exec(db, index_sql, NULL, NULL, &msg) != SQLITE_OK ||
        sqlite3_exec(db, label_backfill_sql, NULL, NULL, &msg) != SQLITE_OK ||
        sqlite3_exec(db, pragma, NULL, NULL, &msg) != SQLITE_OK ||
        sqlite3_exec(db, "COMMIT", NULL, NULL, &msg) != SQLITE_OK)
        goto rollback;
    return AA_OK;
rollback:
    sqlite3_exec(db, "ROLLBACK", NULL, NULL, NULL);
fail:
    aa_error_set(err, AA_EINVAL, "state_dir", "cannot create or migrate the job table: %s",
                 msg ? msg : sqlite3_errmsg(db));
    sqlite3_free(msg);
    return AA_EINVAL;
}
