#include "key_counts.h"

#include <pthread.h>
#include <stdlib.h>

/* A plain array: the keys in use are the users (or tokens) with open connections or running
 * requests, a few dozen at most, and each operation is one short scan under the lock. */
typedef struct entry {
    uint64_t key;
    int count;
} entry;

struct key_counts {
    pthread_mutex_t lock;
    entry *e;
    size_t n, cap;
};

key_counts *key_counts_create(void)
{
    key_counts *kc = calloc(1, sizeof *kc);
    if (kc)
        pthread_mutex_init(&kc->lock, NULL);
    return kc;
}

void key_counts_destroy(key_counts *kc)
{
    if (!kc)
        return;
    pthread_mutex_destroy(&kc->lock);
    free(kc->e);
    free(kc);
}

static entry *find(key_counts *kc, uint64_t key)
{
    for (size_t i = 0; i < kc->n; i++)
        if (kc->e[i].key == key)
            return &kc->e[i];
    return NULL;
}

bool key_counts_acquire(key_counts *kc, uint64_t key, int limit)
{
    bool ok = false;
    pthread_mutex_lock(&kc->lock);
    entry *e = find(kc, key);
    if (e) {
        if (e->count < limit) {
            e->count++;
            ok = true;
        }
    } else if (limit > 0) {
        if (kc->n == kc->cap) {
            size_t cap = kc->cap ? kc->cap * 2 : 16;
            entry *grown = realloc(kc->e, cap * sizeof *grown);
            if (grown) {
                kc->e = grown;
                kc->cap = cap;
            }
        }
        if (kc->n < kc->cap) {
            kc->e[kc->n++] = (entry){key, 1};
            ok = true;
        }
    }
    pthread_mutex_unlock(&kc->lock);
    return ok;
}

void key_counts_release(key_counts *kc, uint64_t key)
{
    pthread_mutex_lock(&kc->lock);
    entry *e = find(kc, key);
    if (e && --e->count <= 0)
        *e = kc->e[--kc->n];
    pthread_mutex_unlock(&kc->lock);
}

int key_counts_get(key_counts *kc, uint64_t key)
{
    pthread_mutex_lock(&kc->lock);
    entry *e = find(kc, key);
    int c = e ? e->count : 0;
    pthread_mutex_unlock(&kc->lock);
    return c;
}

size_t key_counts_keys(key_counts *kc)
{
    pthread_mutex_lock(&kc->lock);
    size_t n = kc->n;
    pthread_mutex_unlock(&kc->lock);
    return n;
}

uint64_t key_counts_hash(const char *s)
{
    uint64_t h = 1469598103934665603ull;
    for (; *s; s++) {
        h ^= (unsigned char)*s;
        h *= 1099511628211ull;
    }
    return h;
}
