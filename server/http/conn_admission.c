#define _GNU_SOURCE
#include "conn_admission.h"
#include "aa_core.h"

#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <time.h>

#include "key_counts.h"
#include "lock_held.h"
#include "peer_identity.h"

typedef struct slot {
    bool used, token_counted;
    conn_peer peer;
    uint64_t token_key;
    double accepted_at;
} slot;

struct conn_admission {
    pthread_mutex_t lock;
    bool is_unix;
    int total_limit, user_limit, token_limit;
    int open;
    slot *by_fd; /* indexed by fd: fds are small and dense */
    size_t cap;
    key_counts *users, *tokens;
};

conn_admission *conn_admission_create(bool is_unix, int total_limit, int user_limit,
                                      int token_limit)
{
    conn_admission *ca = calloc(1, sizeof *ca);
    if (!ca)
        return NULL;
    pthread_mutex_init(&ca->lock, NULL);
    ca->is_unix = is_unix;
    ca->total_limit = total_limit;
    ca->user_limit = user_limit;
    ca->token_limit = token_limit;
    ca->users = key_counts_create();
    ca->tokens = key_counts_create();
    if (!ca->users || !ca->tokens) {
        conn_admission_destroy(ca);
        return NULL;
    }
    return ca;
}

void conn_admission_destroy(conn_admission *ca)
{
    if (!ca)
        return;
    key_counts_destroy(ca->users);
    key_counts_destroy(ca->tokens);
    pthread_mutex_destroy(&ca->lock);
    free(ca->by_fd);
    free(ca);
}

static uint64_t user_key(const conn_peer *p)
{
    return p->uid_known ? (uint64_t)p->uid : UINT64_MAX;
}

conn_admit_result conn_admission_admit(conn_admission *ca, int fd, const struct sockaddr *sa,
                                       socklen_t len, conn_peer *peer)
{
    peer->uid_known = false;
    peer->uid = (uid_t)-1;
    if (!ca->is_unix && !peer_addr_is_loopback(sa, len))
        return ADMIT_NOT_LOOPBACK;
    uid_t uid;
    if ((ca->is_unix ? peer_unix_uid(fd, &uid) : peer_tcp_uid(fd, &uid)) == 0) {
        peer->uid_known = true;
        peer->uid = uid;
    }
    if (fd < 0)
        return ADMIT_NO_MEMORY;
    pthread_mutex_lock(&ca->lock);
    conn_admit_result r = ADMIT_OK;
    if ((size_t)fd >= ca->cap) {
        size_t cap = ca->cap ? ca->cap : 256;
        while (cap <= (size_t)fd)
            cap *= 2;
        slot *grown = realloc(ca->by_fd, cap * sizeof *grown);
        if (grown) {
            for (size_t i = ca->cap; i < cap; i++)
                grown[i] = (slot){0};
            ca->by_fd = grown;
            ca->cap = cap;
        } else {
            r = ADMIT_NO_MEMORY;
        }
    }
    if (r == ADMIT_OK && ca->by_fd[fd].used) {
        /* A slot whose connection libmicrohttpd dropped without a CLOSED notification: the fd
         * was closed and reused, so give back what it held. */
        slot *s = &ca->by_fd[fd];
        key_counts_release(ca->users, user_key(&s->peer));
        if (s->token_counted)
            key_counts_release(ca->tokens, s->token_key);
        *s = (slot){0};
        ca->open--;
    }
    if (r == ADMIT_OK && ca->open >= ca->total_limit)
        r = ADMIT_TOTAL_LIMIT;
    /* Unknown uids (a failed lookup) share one bucket: they cannot escape the limit. */
    if (r == ADMIT_OK && !key_counts_acquire(ca->users, user_key(peer), ca->user_limit))
        r = ADMIT_USER_LIMIT;
    if (r == ADMIT_OK) {
        ca->by_fd[fd] = (slot){.used = true, .peer = *peer, .accepted_at = aa_monotonic_seconds()};
        ca->open++;
    }
    pthread_mutex_unlock(&ca->lock);
    return r;
}

/* The admitted connection on fd, or NULL. Lock held. */
static const slot *slot_of_locked(const conn_admission *ca, int fd)
{
    ASSERT_LOCK_HELD(&ca->lock);
    return fd >= 0 && (size_t)fd < ca->cap && ca->by_fd[fd].used ? &ca->by_fd[fd] : NULL;
}

bool conn_admission_peer(conn_admission *ca, int fd, conn_peer *peer)
{
    pthread_mutex_lock(&ca->lock);
    const slot *s = slot_of_locked(ca, fd);
    if (s)
        *peer = s->peer;
    pthread_mutex_unlock(&ca->lock);
    return s != NULL;
}

bool conn_admission_accepted_at(conn_admission *ca, int fd, double *when)
{
    pthread_mutex_lock(&ca->lock);
    const slot *s = slot_of_locked(ca, fd);
    if (s)
        *when = s->accepted_at;
    pthread_mutex_unlock(&ca->lock);
    return s != NULL;
}

bool conn_admission_token(conn_admission *ca, int fd, long long token_id)
{
    if (token_id <= 0)
        return true;
    bool ok = true;
    pthread_mutex_lock(&ca->lock);
    if (fd >= 0 && (size_t)fd < ca->cap && ca->by_fd[fd].used && !ca->by_fd[fd].token_counted) {
        uint64_t key = (uint64_t)token_id;
        ok = key_counts_acquire(ca->tokens, key, ca->token_limit);
        if (ok) {
            ca->by_fd[fd].token_counted = true;
            ca->by_fd[fd].token_key = key;
        }
    }
    pthread_mutex_unlock(&ca->lock);
    return ok;
}

void conn_admission_release(conn_admission *ca, int fd)
{
    pthread_mutex_lock(&ca->lock);
    if (fd >= 0 && (size_t)fd < ca->cap && ca->by_fd[fd].used) {
        slot *s = &ca->by_fd[fd];
        key_counts_release(ca->users, user_key(&s->peer));
        if (s->token_counted)
            key_counts_release(ca->tokens, s->token_key);
        *s = (slot){0};
        ca->open--;
    }
    pthread_mutex_unlock(&ca->lock);
}

int conn_admission_open(conn_admission *ca)
{
    pthread_mutex_lock(&ca->lock);
    int n = ca->open;
    pthread_mutex_unlock(&ca->lock);
    return n;
}

int conn_admission_user_limit(const conn_admission *ca)
{
    return ca->user_limit;
}

int conn_admission_token_limit(const conn_admission *ca)
{
    return ca->token_limit;
}

int conn_admission_total_limit(const conn_admission *ca)
{
    return ca->total_limit;
}
