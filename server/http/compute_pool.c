#include "compute_pool.h"

#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>

#include "key_counts.h"

struct compute_pool {
    pthread_mutex_t lock;
    pthread_cond_t work;
    compute_task *head, *tail;
    int queued, queue_cap;
    bool stopping, joined;
    int nthreads;
    pthread_t *threads;
    key_counts *load[2]; /* per class: admitted tasks per user */
    int share[2];
};

static void *worker(void *arg)
{
    compute_pool *cp = arg;
    for (;;) {
        pthread_mutex_lock(&cp->lock);
        while (!cp->head && !cp->stopping)
            pthread_cond_wait(&cp->work, &cp->lock);
        compute_task *t = cp->head;
        if (!t) { /* stopping and drained */
            pthread_mutex_unlock(&cp->lock);
            return NULL;
        }
        cp->head = t->next;
        if (!cp->head)
            cp->tail = NULL;
        cp->queued--;
        pthread_mutex_unlock(&cp->lock);
        /* Copy what we need: done() may free the task. */
        key_counts *kc = cp->load[t->compute];
        uint64_t user = t->user;
        void (*done)(void *) = t->done;
        void *targ = t->arg;
        t->run(targ);
        key_counts_release(kc, user);
        done(targ);
    }
}

compute_pool *compute_pool_create(int threads, int user_evaluates, int user_renders, int queue_cap)
{
    if (threads < 1)
        return NULL;
    compute_pool *cp = calloc(1, sizeof *cp);
    if (!cp)
        return NULL;
    pthread_mutex_init(&cp->lock, NULL);
    pthread_cond_init(&cp->work, NULL);
    cp->queue_cap = queue_cap;
    cp->share[COMPUTE_EVALUATE] = user_evaluates;
    cp->share[COMPUTE_RENDER] = user_renders;
    cp->load[0] = key_counts_create();
    cp->load[1] = key_counts_create();
    cp->threads = calloc((size_t)threads, sizeof *cp->threads);
    if (!cp->load[0] || !cp->load[1] || !cp->threads) {
        cp->joined = true;
        compute_pool_destroy(cp);
        return NULL;
    }
    for (; cp->nthreads < threads; cp->nthreads++) {
        if (pthread_create(&cp->threads[cp->nthreads], NULL, worker, cp)) {
            compute_pool_destroy(cp);
            return NULL;
        }
    }
    return cp;
}

compute_admit compute_pool_submit(compute_pool *cp, compute_task *t)
{
    if (!key_counts_acquire(cp->load[t->compute], t->user, cp->share[t->compute]))
        return COMPUTE_OVER_SHARE;
    compute_admit a = COMPUTE_QUEUED;
    pthread_mutex_lock(&cp->lock);
    if (cp->stopping) {
        a = COMPUTE_STOPPED;
    } else if (cp->queued >= cp->queue_cap) {
        a = COMPUTE_FULL;
    } else {
        t->next = NULL;
        if (cp->tail)
            cp->tail->next = t;
        else
            cp->head = t;
        cp->tail = t;
        cp->queued++;
    }
    pthread_mutex_unlock(&cp->lock);
    /* Signalled after unlocking: the woken thread does not wait for the lock we hold. */
    if (a == COMPUTE_QUEUED)
        pthread_cond_signal(&cp->work);
    if (a != COMPUTE_QUEUED)
        key_counts_release(cp->load[t->compute], t->user);
    return a;
}

bool compute_pool_acquire_share(compute_pool *cp, compute_class compute, uint64_t user)
{
    return key_counts_acquire(cp->load[compute], user, cp->share[compute]);
}

void compute_pool_release_share(compute_pool *cp, compute_class compute, uint64_t user)
{
    key_counts_release(cp->load[compute], user);
}

int compute_pool_share(const compute_pool *cp, compute_class compute)
{
    return cp->share[compute];
}

int compute_pool_user_load(compute_pool *cp, compute_class compute, uint64_t user)
{
    return key_counts_get(cp->load[compute], user);
}

void compute_pool_stop(compute_pool *cp)
{
    if (!cp)
        return;
    pthread_mutex_lock(&cp->lock);
    cp->stopping = true;
    bool join = !cp->joined;
    cp->joined = true;
    pthread_cond_broadcast(&cp->work);
    pthread_mutex_unlock(&cp->lock);
    if (join)
        for (int i = 0; i < cp->nthreads; i++)
            pthread_join(cp->threads[i], NULL);
}

void compute_pool_destroy(compute_pool *cp)
{
    if (!cp)
        return;
    compute_pool_stop(cp);
    pthread_cond_destroy(&cp->work);
    pthread_mutex_destroy(&cp->lock);
    key_counts_destroy(cp->load[0]);
    key_counts_destroy(cp->load[1]);
    free(cp->threads);
    free(cp);
}
