#define _POSIX_C_SOURCE 200809L
#include "eval_cache.h"

#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lock_held.h"

#define EVAL_CACHE_MAX_KEY (64u << 10)   /* larger requests are not cached */
#define EVAL_CACHE_MAX_BYTES (64u << 20) /* keys + values held at most */
#define EVAL_CACHE_MAX_VALUE (8u << 20)  /* larger answers are not cached */

typedef struct entry {
    uint64_t hash;
    char *key, *val;
    size_t key_len, val_len;
    struct entry *prev, *next; /* LRU list, most recent first */
    struct entry *chain;       /* hash bucket */
} entry;

struct eval_cache {
    pthread_mutex_t lock;
    size_t capacity, count, nbuckets, bytes;
    entry **buckets;
    entry *head, *tail;
    unsigned long long hits, misses;
};

static uint64_t fnv1a(const char *s, size_t n)
{
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; i++) {
        h ^= (unsigned char)s[i];
        h *= 1099511628211ull;
    }
    return h;
}

eval_cache *eval_cache_create(size_t capacity)
{
    if (!capacity)
        return NULL;
    eval_cache *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    c->capacity = capacity;
    c->nbuckets = capacity * 2 + 1;
    c->buckets = calloc(c->nbuckets, sizeof *c->buckets);
    if (!c->buckets) {
        free(c);
        return NULL;
    }
    pthread_mutex_init(&c->lock, NULL);
    return c;
}

void eval_cache_destroy(eval_cache *c)
{
    if (!c)
        return;
    for (entry *e = c->head, *n; e; e = n) {
        n = e->next;
        free(e->key);
        free(e->val);
        free(e);
    }
    free(c->buckets);
    pthread_mutex_destroy(&c->lock);
    free(c);
}

/* The list and the buckets below are guarded by c->lock. */
static void lru_unlink(eval_cache *c, entry *e)
{
    ASSERT_LOCK_HELD(&c->lock);
    if (e->prev)
        e->prev->next = e->next;
    else
        c->head = e->next;
    if (e->next)
        e->next->prev = e->prev;
    else
        c->tail = e->prev;
    e->prev = e->next = NULL;
}

static void lru_push_front(eval_cache *c, entry *e)
{
    ASSERT_LOCK_HELD(&c->lock);
    e->next = c->head;
    e->prev = NULL;
    if (c->head)
        c->head->prev = e;
    c->head = e;
    if (!c->tail)
        c->tail = e;
}

static entry *find(eval_cache *c, uint64_t h, const char *key, size_t n)
{
    ASSERT_LOCK_HELD(&c->lock);
    for (entry *e = c->buckets[h % c->nbuckets]; e; e = e->chain)
        if (e->hash == h && e->key_len == n && !memcmp(e->key, key, n))
            return e;
    return NULL;
}

bool eval_cache_get(eval_cache *c, const char *key, size_t key_len, char **out, size_t *out_len)
{
    if (!c || key_len > EVAL_CACHE_MAX_KEY)
        return false;
    uint64_t h = fnv1a(key, key_len);
    pthread_mutex_lock(&c->lock);
    entry *e = find(c, h, key, key_len);
    bool hit = false;
    if (e) {
        char *copy = malloc(e->val_len + 1);
        if (copy) {
            memcpy(copy, e->val, e->val_len);
            copy[e->val_len] = 0;
            *out = copy;
            *out_len = e->val_len;
            hit = true;
            lru_unlink(c, e);
            lru_push_front(c, e);
        }
    }
    if (hit)
        c->hits++;
    else
        c->misses++;
    pthread_mutex_unlock(&c->lock);
    return hit;
}

bool eval_cache_contains(eval_cache *c, const char *key, size_t key_len)
{
    if (!c || key_len > EVAL_CACHE_MAX_KEY)
        return false;
    uint64_t h = fnv1a(key, key_len);
    pthread_mutex_lock(&c->lock);
    bool found = find(c, h, key, key_len) != NULL;
    pthread_mutex_unlock(&c->lock);
    return found;
}

static void bucket_remove(eval_cache *c, entry *e)
{
    ASSERT_LOCK_HELD(&c->lock);
    for (entry **p = &c->buckets[e->hash % c->nbuckets]; *p; p = &(*p)->chain) {
        if (*p == e) {
            *p = e->chain;
            return;
        }
    }
}

void eval_cache_put(eval_cache *c, const char *key, size_t key_len, const char *val, size_t val_len)
{
    if (!c || key_len > EVAL_CACHE_MAX_KEY || val_len > EVAL_CACHE_MAX_VALUE)
        return;
    uint64_t h = fnv1a(key, key_len);
    entry *e = calloc(1, sizeof *e);
    if (!e)
        return;
    e->key = malloc(key_len ? key_len : 1);
    e->val = malloc(val_len ? val_len : 1);
    if (!e->key || !e->val) {
        free(e->key);
        free(e->val);
        free(e);
        return;
    }
    memcpy(e->key, key, key_len);
    memcpy(e->val, val, val_len);
    e->key_len = key_len;
    e->val_len = val_len;
    e->hash = h;
    pthread_mutex_lock(&c->lock);
    entry *old = find(c, h, key, key_len);
    if (old) { /* another thread computed the same answer first */
        pthread_mutex_unlock(&c->lock);
        free(e->key);
        free(e->val);
        free(e);
        return;
    }
    while (c->tail &&
           (c->count == c->capacity || c->bytes + key_len + val_len > EVAL_CACHE_MAX_BYTES)) {
        entry *victim = c->tail;
        lru_unlink(c, victim);
        bucket_remove(c, victim);
        c->count--;
        c->bytes -= victim->key_len + victim->val_len;
        free(victim->key);
        free(victim->val);
        free(victim);
    }
    e->chain = c->buckets[h % c->nbuckets];
    c->buckets[h % c->nbuckets] = e;
    lru_push_front(c, e);
    c->count++;
    c->bytes += key_len + val_len;
    pthread_mutex_unlock(&c->lock);
}

char *eval_cache_user_key(long long uid, const char *body, size_t len, size_t *key_len)
{
    char head[32];
    int h = snprintf(head, sizeof head, "uid %lld\n", uid);
    char *k = malloc((size_t)h + len + 1);
    if (!k)
        return NULL;
    memcpy(k, head, (size_t)h);
    if (len)
        memcpy(k + h, body, len);
    *key_len = (size_t)h + len;
    return k;
}

void eval_cache_stats_get(eval_cache *c, eval_cache_stats *out)
{
    memset(out, 0, sizeof *out);
    if (!c)
        return;
    pthread_mutex_lock(&c->lock);
    out->entries = c->count;
    out->capacity = c->capacity;
    out->bytes = c->bytes;
    out->hits = c->hits;
    out->misses = c->misses;
    pthread_mutex_unlock(&c->lock);
}
