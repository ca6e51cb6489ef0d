/* Bounded content-addressed LRU tile store, optionally mirrored on disk (tile_store.h). */
#define _POSIX_C_SOURCE 200809L
#include "tile_store.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct tile_entry {
    char id[TILE_ID_LEN + 1];
    size_t len;
    void *data;         /* NULL: on disk only (found at start-up, not read yet) */
    bool team;          /* anyone may read it */
    long long *readers; /* else these uids */
    size_t n_readers;
    struct tile_entry *prev, *next; /* LRU list: head = most recent */
} tile_entry;

struct tile_store {
    pthread_mutex_t lock;
    char *dir; /* state_dir/tiles, or NULL */
    size_t max_bytes, bytes, count, evicted;
    tile_entry *head, *tail;
};

bool tile_id_valid(const char *id)
{
    if (!id || strlen(id) != TILE_ID_LEN)
        return false;
    for (size_t i = 0; i < TILE_ID_LEN; i++)
        if (!((id[i] >= '0' && id[i] <= '9') || (id[i] >= 'a' && id[i] <= 'f')))
            return false;
    return true;
}

/* Two independent 64-bit hashes of the content (FNV-1a and a multiply-xorshift mix). */
static void content_id(const void *data, size_t len, char id[TILE_ID_LEN + 1])
{
    const unsigned char *p = data;
    uint64_t a = 0xcbf29ce484222325ull, b = 0x9E3779B97F4A7C15ull ^ len;
    for (size_t i = 0; i < len; i++) {
        a = (a ^ p[i]) * 0x100000001b3ull;
        b = (b ^ p[i]) * 0xff51afd7ed558ccdull;
        b ^= b >> 29;
    }
    b ^= b >> 33;
    b *= 0xc4ceb9fe1a85ec53ull;
    b ^= b >> 33;
    snprintf(id, TILE_ID_LEN + 1, "%016llx%016llx", (unsigned long long)a, (unsigned long long)b);
}

static void unlink_entry(tile_store *ts, tile_entry *e)
{
    if (e->prev)
        e->prev->next = e->next;
    else
        ts->head = e->next;
    if (e->next)
        e->next->prev = e->prev;
    else
        ts->tail = e->prev;
    e->prev = e->next = NULL;
}

static void push_front(tile_store *ts, tile_entry *e)
{
    e->prev = NULL;
    e->next = ts->head;
    if (ts->head)
        ts->head->prev = e;
    ts->head = e;
    if (!ts->tail)
        ts->tail = e;
}

static tile_entry *find(tile_store *ts, const char *id)
{
    for (tile_entry *e = ts->head; e; e = e->next)
        if (strcmp(e->id, id) == 0)
            return e;
    return NULL;
}

static void file_path(const tile_store *ts, const char *id, char *out, size_t cap)
{
    snprintf(out, cap, "%s/%s.png", ts->dir, id);
}

static void readers_path(const tile_store *ts, const char *id, char *out, size_t cap)
{
    snprintf(out, cap, "%s/%s.readers", ts->dir, id);
}

static void entry_free(tile_entry *e)
{
    free(e->data);
    free(e->readers);
    free(e);
}

/* A new file 0600 whatever the umask, never through a symlink: a private tile must not be
 * readable by the daemon's group (under systemd the team's group, UMask=0027). */
static FILE *create_private(const char *path, const char *fmode)
{
    unlink(path); /* a temporary left by a crash */
    int fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd < 0)
        return NULL;
    FILE *f = fchmod(fd, 0600) == 0 ? fdopen(fd, fmode) : NULL;
    if (!f)
        close(fd);
    return f;
}

/* {id}.readers: the private readers, one uid per line, replaced atomically; absent = team. */
static void write_readers(const tile_store *ts, const tile_entry *e)
{
    char path[4200], tmp[4300];
    readers_path(ts, e->id, path, sizeof path);
    if (e->team) {
        unlink(path);
        return;
    }
    snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
    FILE *f = create_private(tmp, "w");
    if (!f)
        return;
    bool ok = true;
    for (size_t i = 0; i < e->n_readers && ok; i++)
        ok = fprintf(f, "%lld\n", e->readers[i]) > 0;
    ok = (fclose(f) == 0) && ok;
    if (!ok || rename(tmp, path) != 0)
        unlink(tmp);
}

/* Reads {id}.readers into e; without the file the tile is team (tiles made before access). */
static void read_readers(const tile_store *ts, tile_entry *e)
{
    char path[4200];
    readers_path(ts, e->id, path, sizeof path);
    FILE *f = fopen(path, "r");
    e->team = f == NULL;
    if (!f)
        return;
    long long uid;
    while (fscanf(f, "%lld", &uid) == 1) {
        long long *grown = realloc(e->readers, (e->n_readers + 1) * sizeof *grown);
        if (!grown)
            break;
        e->readers = grown;
        e->readers[e->n_readers++] = uid;
    }
    fclose(f);
}

/* Adds access to e; true if it changed. */
static bool grant(tile_entry *e, const tile_access *access)
{
    if (e->team)
        return false;
    if (!access || !access->private_tile) {
        e->team = true;
        free(e->readers);
        e->readers = NULL;
        e->n_readers = 0;
        return true;
    }
    for (size_t i = 0; i < e->n_readers; i++)
        if (e->readers[i] == access->owner)
            return false;
    long long *grown = realloc(e->readers, (e->n_readers + 1) * sizeof *grown);
    if (!grown)
        return false;
    e->readers = grown;
    e->readers[e->n_readers++] = access->owner;
    return true;
}

static bool readable(const tile_entry *e, long long uid, bool admin)
{
    if (e->team || admin)
        return true;
    for (size_t i = 0; i < e->n_readers; i++)
        if (uid >= 0 && e->readers[i] == uid)
            return true;
    return false;
}

static void drop(tile_store *ts, tile_entry *e)
{
    unlink_entry(ts, e);
    if (ts->dir) {
        char path[4200];
        file_path(ts, e->id, path, sizeof path);
        unlink(path);
        readers_path(ts, e->id, path, sizeof path);
        unlink(path);
    }
    ts->bytes -= e->len;
    ts->count--;
    ts->evicted++;
    entry_free(e);
}

static void evict_until(tile_store *ts, size_t room)
{
    while (ts->tail && ts->bytes + room > ts->max_bytes)
        drop(ts, ts->tail);
}

/* Start-up: index the tiles already on disk, oldest last in the LRU order. */
typedef struct found_file {
    char id[TILE_ID_LEN + 1];
    size_t len;
    double mtime;
} found_file;

static int by_mtime_desc(const void *pa, const void *pb)
{
    const found_file *a = pa, *b = pb;
    return (a->mtime < b->mtime) - (a->mtime > b->mtime);
}

static void index_disk(tile_store *ts)
{
    DIR *d = opendir(ts->dir);
    if (!d)
        return;
    size_t n = 0, cap = 0;
    found_file *files = NULL;
    struct dirent *de;
    while ((de = readdir(d))) {
        size_t nl = strlen(de->d_name);
        if (nl != TILE_ID_LEN + 4 || strcmp(de->d_name + TILE_ID_LEN, ".png") != 0)
            continue;
        found_file f;
        memcpy(f.id, de->d_name, TILE_ID_LEN);
        f.id[TILE_ID_LEN] = 0;
        if (!tile_id_valid(f.id))
            continue;
        char path[4200];
        struct stat st;
        file_path(ts, f.id, path, sizeof path);
        if (lstat(path, &st) != 0 || !S_ISREG(st.st_mode))
            continue;
        if ((st.st_mode & 07777) != 0600) /* written by an older daemon under its umask */
            chmod(path, 0600);
        f.len = (size_t)st.st_size;
        f.mtime = (double)st.st_mtim.tv_sec + st.st_mtim.tv_nsec * 1e-9;
        if (n == cap) {
            cap = cap ? 2 * cap : 64;
            found_file *grown = realloc(files, cap * sizeof *files);
            if (!grown)
                break;
            files = grown;
        }
        files[n++] = f;
    }
    closedir(d);
    if (n > 1)
        qsort(files, n, sizeof *files, by_mtime_desc);
    for (size_t i = 0; i < n; i++) {
        tile_entry *e = calloc(1, sizeof *e);
        if (!e)
            break;
        memcpy(e->id, files[i].id, sizeof e->id);
        e->len = files[i].len;
        read_readers(ts, e);
        /* Most recent first: append at the tail. */
        e->prev = ts->tail;
        if (ts->tail)
            ts->tail->next = e;
        else
            ts->head = e;
        ts->tail = e;
        ts->bytes += e->len;
        ts->count++;
    }
    free(files);
    evict_until(ts, 0);
    ts->evicted = 0;
}

tile_store *tile_store_create(const char *state_dir, size_t max_bytes, aa_error *err)
{
    if (max_bytes < 1) {
        aa_error_set(err, AA_EINVAL, "max_bytes", "the tile store needs a positive size");
        return NULL;
    }
    tile_store *ts = calloc(1, sizeof *ts);
    if (!ts) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    pthread_mutex_init(&ts->lock, NULL);
    ts->max_bytes = max_bytes;
    if (state_dir) {
        size_t n = strlen(state_dir) + sizeof "/tiles";
        ts->dir = malloc(n);
        if (!ts->dir) {
            tile_store_destroy(ts);
            aa_error_set(err, AA_ENOMEM, "", "out of memory");
            return NULL;
        }
        snprintf(ts->dir, n, "%s/tiles", state_dir);
        /* 0700: tiles are served through the API only, which knows who may read a private
         * one; an existing directory of an older daemon (0750) is narrowed. */
        int dfd = -1;
        struct stat st;
        bool ok = (mkdir(ts->dir, 0700) == 0 || errno == EEXIST) &&
                  (dfd = open(ts->dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC)) >= 0 &&
                  fstat(dfd, &st) == 0;
        bool theirs = ok && st.st_uid != geteuid();
        if (!ok || theirs || ((st.st_mode & 07777) != 0700 && fchmod(dfd, 0700) != 0)) {
            aa_error_set(err, AA_EINVAL, "state_dir", "%s: %s", ts->dir,
                         theirs ? "not owned by the daemon's user; remove it" : strerror(errno));
            if (dfd >= 0)
                close(dfd);
            tile_store_destroy(ts);
            return NULL;
        }
        close(dfd);
        index_disk(ts);
    }
    return ts;
}

void tile_store_destroy(tile_store *ts)
{
    if (!ts)
        return;
    tile_entry *e = ts->head;
    while (e) {
        tile_entry *next = e->next;
        entry_free(e);
        e = next;
    }
    pthread_mutex_destroy(&ts->lock);
    free(ts->dir);
    free(ts);
}

static void write_file(const tile_store *ts, const char *id, const void *data, size_t len)
{
    char path[4200], tmp[4300];
    file_path(ts, id, path, sizeof path);
    snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
    FILE *f = create_private(tmp, "wb");
    if (!f)
        return;
    bool ok = fwrite(data, 1, len, f) == len;
    ok = (fclose(f) == 0) && ok;
    if (!ok || rename(tmp, path) != 0)
        unlink(tmp);
}

int tile_store_put(tile_store *ts, const void *data, size_t len, char id[TILE_ID_LEN + 1],
                   aa_error *err)
{
    return tile_store_put_as(ts, data, len, NULL, id, err);
}

int tile_store_put_as(tile_store *ts, const void *data, size_t len, const tile_access *access,
                      char id[TILE_ID_LEN + 1], aa_error *err)
{
    content_id(data, len, id);
    if (len > ts->max_bytes)
        return aa_error_set(err, AA_ERANGE, "", "tile of %zu bytes exceeds the store (%zu)", len,
                            ts->max_bytes);
    void *copy = malloc(len ? len : 1);
    tile_entry *e = calloc(1, sizeof *e);
    if (!copy || !e) {
        free(copy);
        free(e);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    memcpy(copy, data, len);
    pthread_mutex_lock(&ts->lock);
    tile_entry *old = find(ts, id);
    if (old) {
        unlink_entry(ts, old);
        push_front(ts, old);
        if (!old->data) {
            old->data = copy;
            copy = NULL;
        }
        if (grant(old, access) && ts->dir)
            write_readers(ts, old);
        pthread_mutex_unlock(&ts->lock);
        free(copy);
        free(e);
        return AA_OK;
    }
    evict_until(ts, len);
    memcpy(e->id, id, TILE_ID_LEN + 1);
    e->len = len;
    e->data = copy;
    grant(e, access);
    if (!e->team && !e->n_readers) { /* out of memory recording the owner: keep it unreadable */
        free(e->data);
        free(e);
        pthread_mutex_unlock(&ts->lock);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    push_front(ts, e);
    ts->bytes += len;
    ts->count++;
    if (ts->dir) {
        /* under the lock: eviction never races the write; the readers first, so a private tile
         * is never on disk without them */
        write_readers(ts, e);
        write_file(ts, id, data, len);
    }
    pthread_mutex_unlock(&ts->lock);
    return AA_OK;
}

static void *read_file(const tile_store *ts, const char *id, size_t len)
{
    char path[4200];
    file_path(ts, id, path, sizeof path);
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    void *buf = malloc(len ? len : 1);
    if (buf && fread(buf, 1, len, f) != len) {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    return buf;
}

int tile_store_get(tile_store *ts, const char *id, void **data, size_t *len)
{
    return tile_store_get_as(ts, id, -1, true, data, len);
}

int tile_store_get_as(tile_store *ts, const char *id, long long uid, bool admin, void **data,
                      size_t *len)
{
    *data = NULL;
    *len = 0;
    if (!tile_id_valid(id))
        return AA_EINVAL;
    pthread_mutex_lock(&ts->lock);
    tile_entry *e = find(ts, id);
    if (e && !e->data && ts->dir) {
        e->data = read_file(ts, id, e->len);
        if (!e->data) {
            drop(ts, e);
            e = NULL;
        }
    }
    int rc = TILE_ENOENT;
    if (e && !readable(e, uid, admin))
        e = NULL;
    if (e) {
        unlink_entry(ts, e);
        push_front(ts, e);
        *data = malloc(e->len ? e->len : 1);
        if (*data) {
            memcpy(*data, e->data, e->len);
            *len = e->len;
            rc = AA_OK;
        } else {
            rc = AA_ENOMEM;
        }
    }
    pthread_mutex_unlock(&ts->lock);
    return rc;
}

tile_store_usage tile_store_usage_get(tile_store *ts)
{
    pthread_mutex_lock(&ts->lock);
    tile_store_usage u = {ts->count, ts->bytes, ts->max_bytes, ts->evicted};
    pthread_mutex_unlock(&ts->lock);
    return u;
}
