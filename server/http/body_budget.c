#include "body_budget.h"

#include <pthread.h>
#include <stdlib.h>

typedef struct held {
    uint64_t user;
    size_t bytes;
} held;

struct body_budget {
    pthread_mutex_t lock;
    size_t per_user;
    held *h;
    size_t n, cap;
};

body_budget *body_budget_create(size_t per_user)
{
    body_budget *b = calloc(1, sizeof *b);
    if (!b)
        return NULL;
    pthread_mutex_init(&b->lock, NULL);
    b->per_user = per_user;
    return b;
}

void body_budget_destroy(body_budget *b)
{
    if (!b)
        return;
    pthread_mutex_destroy(&b->lock);
    free(b->h);
    free(b);
}

static held *find(body_budget *b, uint64_t user)
{
    for (size_t i = 0; i < b->n; i++)
        if (b->h[i].user == user)
            return &b->h[i];
    return NULL;
}

bool body_budget_acquire(body_budget *b, uint64_t user, size_t bytes)
{
    if (!bytes)
        return true;
    bool ok = false;
    pthread_mutex_lock(&b->lock);
    held *e = find(b, user);
    if (!e && bytes <= b->per_user) {
        if (b->n == b->cap) {
            size_t cap = b->cap ? 2 * b->cap : 16;
            held *h = realloc(b->h, cap * sizeof *h);
            if (h) {
                b->h = h;
                b->cap = cap;
            }
        }
        if (b->n < b->cap) {
            e = &b->h[b->n++];
            *e = (held){.user = user, .bytes = 0};
        }
    }
    if (e && bytes <= b->per_user - e->bytes) {
        e->bytes += bytes;
        ok = true;
    }
    pthread_mutex_unlock(&b->lock);
    return ok;
}

void body_budget_release(body_budget *b, uint64_t user, size_t bytes)
{
    if (!bytes)
        return;
    pthread_mutex_lock(&b->lock);
    held *e = find(b, user);
    if (e) {
        e->bytes = bytes < e->bytes ? e->bytes - bytes : 0;
        if (!e->bytes) /* forget idle users: the table stays as small as the active set */
            *e = b->h[--b->n];
    }
    pthread_mutex_unlock(&b->lock);
}

size_t body_budget_limit(const body_budget *b)
{
    return b->per_user;
}

size_t body_budget_held(body_budget *b, uint64_t user)
{
    pthread_mutex_lock(&b->lock);
    held *e = find(b, user);
    size_t bytes = e ? e->bytes : 0;
    pthread_mutex_unlock(&b->lock);
    return bytes;
}
