/* The job store's connections: one writer behind the store mutex, a few WAL readers each
 * behind its own lock. Writes are in job_store_write.c, reads in job_store_read.c. */
#define _POSIX_C_SOURCE 200809L
#include "job_store_impl.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "lock_held.h"
#include "owned_path.h"

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

bool job_state_edge_legal(job_state from, job_state to)
{
    if ((unsigned)to >= JOB_STATE_COUNT)
        return false;
    return from == JOB_QUEUED || from == JOB_RUNNING;
}

job_state job_state_from_name(const char *n)
{
    for (int i = 0; i < JOB_STATE_COUNT; i++)
        if (n && !strcmp(n, state_names[i]))
            return (job_state)i;
    return JOB_INTERRUPTED;
}

job_store_reader *job_store_reader_acquire(job_store *st)
{
    /* A free connection if there is one, else wait for the next in turn. */
    for (int i = 0; i < JOB_STORE_READERS; i++)
        if (pthread_mutex_trylock(&st->readers[i].lock) == 0)
            return &st->readers[i];
    job_store_reader *r = &st->readers[atomic_fetch_add(&st->next_reader, 1) % JOB_STORE_READERS];
    pthread_mutex_lock(&r->lock);
    return r;
}

void job_store_reader_release(job_store_reader *r)
{
    pthread_mutex_unlock(&r->lock);
}

void job_store_sync(job_store *st, bool full)
{
    ASSERT_LOCK_HELD(&st->lock);
    if (st->sync_full == full)
        return;
    if (sqlite3_exec(st->db, full ? "PRAGMA synchronous=FULL" : "PRAGMA synchronous=NORMAL", NULL,
                     NULL, NULL) == SQLITE_OK)
        st->sync_full = full;
}

void job_store_set_user_quota(job_store *st, long long bytes)
{
    st->user_quota = bytes > 0 ? bytes : 0;
}

bool job_store_integrity_ok(job_store *st)
{
    job_store_reader *r = job_store_reader_acquire(st);
    sqlite3_stmt *q;
    bool ok = false;
    if (sqlite3_prepare_v2(r->db, "PRAGMA integrity_check", -1, &q, NULL) == SQLITE_OK) {
        if (sqlite3_step(q) == SQLITE_ROW) {
            const unsigned char *t = sqlite3_column_text(q, 0);
            ok = t && !strcmp((const char *)t, "ok");
        }
        sqlite3_finalize(q);
    }
    job_store_reader_release(r);
    return ok;
}

static int open_connection(const char *path, sqlite3 **db, aa_error *err)
{
    int rc = sqlite3_open_v2(
        path, db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_FULLMUTEX | SQLITE_OPEN_NOFOLLOW, NULL);
    if (rc != SQLITE_OK)
        return aa_error_set(err, AA_EINVAL, "state_dir", "cannot open %s: %s", path,
                            *db ? sqlite3_errmsg(*db) : sqlite3_errstr(rc));
    sqlite3_busy_timeout(*db, 5000);
    return AA_OK;
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
    for (int i = 0; i < JOB_STORE_READERS; i++)
        pthread_mutex_init(&st->readers[i].lock, NULL);
    /* Created 0600 here, never followed through a symlink, and an existing file must be ours
     * (owned_path.h): SQLite alone would honour the umask and follow a planted link. */
    char why[600];
    mode_t old_mode;
    int fd = owned_file_open(path, &old_mode, why, sizeof why);
    if (fd < 0 || owned_db_companions_check(path, why, sizeof why)) {
        if (fd >= 0)
            close(fd);
        aa_error_set(err, AA_EINVAL, "state_dir", "%s", why);
        goto fail;
    }
    close(fd);
    if (old_mode)
        fprintf(stderr, "aalabd: %s had mode %04o; set to 0600\n", path, (unsigned)old_mode);
    if (open_connection(path, &st->db, err))
        goto fail;
    char *msg = NULL;
    /* A new database gives freed pages back to the file system (job_store_write.c trim);
     * this must come before anything is written and is a no-op on an existing database. */
    sqlite3_exec(st->db, "PRAGMA auto_vacuum=INCREMENTAL", NULL, NULL, NULL);
    /* WAL: readers never block the writer. synchronous=FULL so a state change survives a
     * power cut; progress writes switch to NORMAL (job_store_sync). The WAL is cut back to
     * 4 MiB after a checkpoint so a big job's write does not leave a big file behind. */
    if (sqlite3_exec(st->db,
                     "PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL; PRAGMA foreign_keys=ON; "
                     "PRAGMA journal_size_limit=4194304;",
                     NULL, NULL, &msg) != SQLITE_OK) {
        aa_error_set(err, AA_EINVAL, "state_dir", "cannot initialise %s: %s", path,
                     msg ? msg : sqlite3_errmsg(st->db));
        sqlite3_free(msg);
        goto fail;
    }
    st->sync_full = true;
    if (job_store_schema_init(st->db, err))
        goto fail;
    for (int i = 0; i < JOB_STORE_READERS; i++) {
        if (open_connection(path, &st->readers[i].db, err))
            goto fail;
        sqlite3_exec(st->readers[i].db, "PRAGMA query_only=1", NULL, NULL, NULL);
    }
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
    for (int i = 0; i < JOB_STORE_READERS; i++) {
        sqlite3_close(st->readers[i].db);
        pthread_mutex_destroy(&st->readers[i].lock);
    }
    if (st->db) {
        sqlite3_exec(st->db, "PRAGMA wal_checkpoint(TRUNCATE);", NULL, NULL, NULL);
        sqlite3_close(st->db);
    }
    pthread_mutex_destroy(&st->lock);
    free(st);
}
