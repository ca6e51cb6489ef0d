/* Bearer tokens in SQLite, hashed with SHA-256 (token_store.h). */
#define _GNU_SOURCE
#include "token_store.h"

#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <time.h>
#include <unistd.h>

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <sqlite3.h>

#include "lock_held.h"
#include "owned_path.h"

#define SECRET_BYTES 32
#define HASH_BYTES 32
#define PREFIX "aalab_"

/* Every TCP request checks a token, so the checks are answered from memory: the live tokens'
 * (id, uid, hash), loaded at open and kept in step by issue and revoke (one daemon per state
 * directory, so nobody else writes the file). SQLite is the durable copy. A check costs the
 * SHA-256 and a scan of a few entries (15 us with a prepared query per call). */
typedef struct token_entry {
    long long id, uid;
    unsigned char hash[HASH_BYTES];
} token_entry;

struct token_store {
    pthread_mutex_t lock;
    sqlite3 *db;
    EVP_MD *sha256;
    token_entry *live;
    size_t n_live, cap_live;
};

static int remember(token_store *ts, long long id, long long uid, const unsigned char *hash)
{
    ASSERT_LOCK_HELD(&ts->lock);
    if (ts->n_live == ts->cap_live) {
        size_t cap = ts->cap_live ? 2 * ts->cap_live : 16;
        token_entry *grown = realloc(ts->live, cap * sizeof *grown);
        if (!grown)
            return AA_ENOMEM;
        ts->live = grown;
        ts->cap_live = cap;
    }
    token_entry *e = &ts->live[ts->n_live++];
    e->id = id;
    e->uid = uid;
    memcpy(e->hash, hash, HASH_BYTES);
    return AA_OK;
}

/* At open, before the store is shared: the lock is only remember's precondition. */
static int load_live(token_store *ts)
{
    sqlite3_stmt *q;
    if (sqlite3_prepare_v2(ts->db, "SELECT id, uid, hash FROM tokens", -1, &q, NULL) != SQLITE_OK)
        return TOKEN_ESTORE;
    int rc = AA_OK;
    pthread_mutex_lock(&ts->lock);
    while (rc == AA_OK && sqlite3_step(q) == SQLITE_ROW)
        if (sqlite3_column_bytes(q, 2) == HASH_BYTES)
            rc = remember(ts, sqlite3_column_int64(q, 0), sqlite3_column_int64(q, 1),
                          sqlite3_column_blob(q, 2));
    pthread_mutex_unlock(&ts->lock);
    sqlite3_finalize(q);
    return rc;
}

static int hash_secret(const token_store *ts, const char *secret, size_t len,
                       unsigned char out[HASH_BYTES])
{
    unsigned int n = 0;
    return EVP_Digest(secret, len, out, &n, ts->sha256, NULL) == 1 && n == HASH_BYTES ? 0 : -1;
}

token_store *token_store_open(const char *state_dir, aa_error *err)
{
    char path[4200];
    if (snprintf(path, sizeof path, "%s/tokens.db", state_dir) >= (int)sizeof path) {
        aa_error_set(err, AA_EINVAL, "state_dir", "state directory path too long");
        return NULL;
    }
    /* Create the file 0600 ourselves (SQLite would honour the umask); an existing one must be
     * ours, not a planted file or link (owned_path.h). */
    char msg[600];
    mode_t old_mode;
    int fd = owned_file_open(path, &old_mode, msg, sizeof msg);
    if (fd < 0 || owned_db_companions_check(path, msg, sizeof msg)) {
        if (fd >= 0)
            close(fd);
        aa_error_set(err, AA_EINVAL, "state_dir", "%s", msg);
        return NULL;
    }
    close(fd);
    if (old_mode)
        fprintf(stderr, "aalabd: %s had mode %04o; set to 0600\n", path, (unsigned)old_mode);
    token_store *ts = calloc(1, sizeof *ts);
    if (!ts) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    pthread_mutex_init(&ts->lock, NULL);
    ts->sha256 = EVP_MD_fetch(NULL, "SHA256", NULL);
    if (!ts->sha256) {
        aa_error_set(err, AA_EINVAL, "", "SHA-256 is not available from libcrypto");
        token_store_close(ts);
        return NULL;
    }
    if (sqlite3_open_v2(path, &ts->db,
                        SQLITE_OPEN_READWRITE | SQLITE_OPEN_FULLMUTEX | SQLITE_OPEN_NOFOLLOW,
                        NULL) != SQLITE_OK ||
        sqlite3_busy_timeout(ts->db, 5000) != SQLITE_OK ||
        sqlite3_exec(ts->db,
                     "PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL;"
                     "CREATE TABLE IF NOT EXISTS tokens("
                     " id INTEGER PRIMARY KEY AUTOINCREMENT,"
                     " uid INTEGER NOT NULL,"
                     " label TEXT NOT NULL DEFAULT '',"
                     " created INTEGER NOT NULL,"
                     " hash BLOB NOT NULL);",
                     NULL, NULL, NULL) != SQLITE_OK ||
        load_live(ts) != AA_OK) {
        aa_error_set(err, AA_EINVAL, "state_dir", "token store %s: %s", path,
                     ts->db ? sqlite3_errmsg(ts->db) : "cannot open");
        token_store_close(ts);
        return NULL;
    }
    return ts;
}

void token_store_close(token_store *ts)
{
    if (!ts)
        return;
    sqlite3_close(ts->db);
    free(ts->live);
    EVP_MD_free(ts->sha256);
    pthread_mutex_destroy(&ts->lock);
    free(ts);
}

static json_t *row_json(sqlite3_stmt *q)
{
    return json_pack("{s:I,s:I,s:s,s:I}", "id", (json_int_t)sqlite3_column_int64(q, 0), "uid",
                     (json_int_t)sqlite3_column_int64(q, 1), "label",
                     (const char *)sqlite3_column_text(q, 2), "created",
                     (json_int_t)sqlite3_column_int64(q, 3));
}

int token_store_issue(token_store *ts, long long uid, const char *label, int max_per_user,
                      json_t **out, aa_error *err)
{
    unsigned char raw[SECRET_BYTES], hash[HASH_BYTES];
    char secret[2 * SECRET_BYTES + 1];
    if (getrandom(raw, sizeof raw, 0) != (ssize_t)sizeof raw)
        return aa_error_set(err, TOKEN_ESTORE, "", "getrandom failed: %s", strerror(errno));
    for (size_t i = 0; i < sizeof raw; i++)
        snprintf(secret + 2 * i, 3, "%02x", raw[i]);
    if (hash_secret(ts, secret, strlen(secret), hash))
        return aa_error_set(err, TOKEN_ESTORE, "", "SHA-256 failed");
    long long created = (long long)time(NULL), id = 0;
    int rc = TOKEN_ESTORE;
    pthread_mutex_lock(&ts->lock);
    int held = 0;
    for (size_t i = 0; i < ts->n_live; i++)
        held += ts->live[i].uid == uid;
    if (held >= max_per_user) {
        pthread_mutex_unlock(&ts->lock);
        return aa_error_set(err, TOKEN_EQUOTA, "",
                            "you already hold %d tokens (--user-tokens); revoke one first "
                            "(aalab token list, aalab token revoke ID)",
                            held);
    }
    sqlite3_stmt *q;
    if (sqlite3_prepare_v2(ts->db, "INSERT INTO tokens(uid, label, created, hash) VALUES(?,?,?,?)",
                           -1, &q, NULL) == SQLITE_OK) {
        sqlite3_bind_int64(q, 1, uid);
        sqlite3_bind_text(q, 2, label ? label : "", -1, SQLITE_TRANSIENT);
        sqlite3_bind_int64(q, 3, created);
        sqlite3_bind_blob(q, 4, hash, sizeof hash, SQLITE_TRANSIENT);
        if (sqlite3_step(q) == SQLITE_DONE) {
            id = sqlite3_last_insert_rowid(ts->db);
            rc = AA_OK;
        }
        sqlite3_finalize(q);
    }
    if (rc == AA_OK && remember(ts, id, uid, hash) != AA_OK) {
        /* Not usable without its entry: take the row back. */
        char del[64];
        snprintf(del, sizeof del, "DELETE FROM tokens WHERE id=%lld", id);
        sqlite3_exec(ts->db, del, NULL, NULL, NULL);
        rc = AA_ENOMEM;
    }
    if (rc == AA_ENOMEM)
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
    else if (rc)
        aa_error_set(err, TOKEN_ESTORE, "", "token store: %s", sqlite3_errmsg(ts->db));
    pthread_mutex_unlock(&ts->lock);
    if (rc)
        return rc;
    char token[sizeof PREFIX + 24 + sizeof secret];
    snprintf(token, sizeof token, PREFIX "%lld_%s", id, secret);
    *out = json_pack("{s:I,s:s,s:I,s:s,s:I}", "id", (json_int_t)id, "token", token, "uid",
                     (json_int_t)uid, "label", label ? label : "", "created", (json_int_t)created);
    OPENSSL_cleanse(secret, sizeof secret);
    OPENSSL_cleanse(token, sizeof token);
    return *out ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
}

/* "aalab_<id>_<64 lowercase hex>" -> id and the secret's offset; -1 if malformed or the id is
 * not canonical (a leading zero). */
static long long parse_token(const char *token, const char **secret)
{
    size_t plen = strlen(PREFIX);
    if (!token || strncmp(token, PREFIX, plen))
        return -1;
    const char *p = token + plen;
    if (*p == '0') /* canonical ids only: "aalab_01_..." is not token 1 */
        return -1;
    long long id = 0;
    int digits = 0;
    for (; *p >= '0' && *p <= '9' && digits < 18; p++, digits++)
        id = id * 10 + (*p - '0');
    if (!digits || *p != '_' || id <= 0)
        return -1;
    p++;
    if (strlen(p) != 2 * SECRET_BYTES || strspn(p, "0123456789abcdef") != 2 * SECRET_BYTES)
        return -1;
    *secret = p;
    return id;
}

int token_store_check(token_store *ts, const char *token, long long *uid, long long *id)
{
    const char *secret = NULL;
    long long tid = parse_token(token, &secret);
    unsigned char hash[HASH_BYTES];
    if (tid < 0 || hash_secret(ts, secret, strlen(secret), hash))
        return TOKEN_ENOENT;
    int rc = TOKEN_ENOENT;
    pthread_mutex_lock(&ts->lock);
    for (size_t i = 0; i < ts->n_live; i++) {
        const token_entry *e = &ts->live[i];
        if (e->id == tid) {
            if (CRYPTO_memcmp(e->hash, hash, HASH_BYTES) == 0) {
                *uid = e->uid;
                *id = tid;
                rc = AA_OK;
            }
            break;
        }
    }
    pthread_mutex_unlock(&ts->lock);
    return rc;
}

int token_store_count(token_store *ts, long long uid)
{
    int held = 0;
    pthread_mutex_lock(&ts->lock);
    for (size_t i = 0; i < ts->n_live; i++)
        held += ts->live[i].uid == uid;
    pthread_mutex_unlock(&ts->lock);
    return held;
}

json_t *token_store_list(token_store *ts, long long uid)
{
    json_t *a = json_array();
    pthread_mutex_lock(&ts->lock);
    sqlite3_stmt *q;
    if (sqlite3_prepare_v2(ts->db,
                           uid < 0 ? "SELECT id, uid, label, created FROM tokens ORDER BY id"
                                   : "SELECT id, uid, label, created FROM tokens WHERE uid=? "
                                     "ORDER BY id",
                           -1, &q, NULL) == SQLITE_OK) {
        if (uid >= 0)
            sqlite3_bind_int64(q, 1, uid);
        while (sqlite3_step(q) == SQLITE_ROW)
            json_array_append_new(a, row_json(q));
        sqlite3_finalize(q);
    }
    pthread_mutex_unlock(&ts->lock);
    return a;
}

int token_store_revoke(token_store *ts, long long id, long long caller, bool admin)
{
    int rc = TOKEN_ENOENT;
    pthread_mutex_lock(&ts->lock);
    sqlite3_stmt *q;
    if (sqlite3_prepare_v2(ts->db, "SELECT uid FROM tokens WHERE id=?", -1, &q, NULL) ==
        SQLITE_OK) {
        sqlite3_bind_int64(q, 1, id);
        if (sqlite3_step(q) == SQLITE_ROW)
            rc = admin || sqlite3_column_int64(q, 0) == caller ? AA_OK : TOKEN_EFORBIDDEN;
        sqlite3_finalize(q);
    }
    if (rc == AA_OK) {
        rc = TOKEN_ESTORE;
        if (sqlite3_prepare_v2(ts->db, "DELETE FROM tokens WHERE id=?", -1, &q, NULL) ==
            SQLITE_OK) {
            sqlite3_bind_int64(q, 1, id);
            if (sqlite3_step(q) == SQLITE_DONE)
                rc = AA_OK;
            sqlite3_finalize(q);
        }
    }
    for (size_t i = 0; rc == AA_OK && i < ts->n_live; i++) {
        if (ts->live[i].id == id) { /* refused from now on */
            ts->live[i] = ts->live[--ts->n_live];
            break;
        }
    }
    pthread_mutex_unlock(&ts->lock);
    return rc;
}
