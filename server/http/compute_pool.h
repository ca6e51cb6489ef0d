/* The pool that runs POST /v1/evaluate and POST /v1/render, so that no HTTP thread computes.
 * Bounded: --compute-threads threads, a queue of at most queue_cap tasks, and per user at most
 * --user-evaluates evaluates and --user-renders renders admitted (queued or running) at once;
 * beyond a share the caller answers 429. A user's share is given back when the computation
 * ends, before its result is handed back, so a client that waits for each answer never trips
 * over its own share. */
#ifndef AALAB_COMPUTE_POOL_H
#define AALAB_COMPUTE_POOL_H

#include <stdbool.h>
#include <stdint.h>

typedef enum { COMPUTE_EVALUATE, COMPUTE_RENDER } compute_class;

/* Owned by the caller (embedded in its request state) until done() has been called. */
typedef struct compute_task {
    void (*run)(void *arg);  /* the computation, on a pool thread */
    void (*done)(void *arg); /* afterwards, share released: hand the result back */
    void *arg;
    compute_class compute;
    uint64_t user; /* peer uid, or COMPUTE_USER_UNKNOWN (one shared bucket) */
    struct compute_task *next;
} compute_task;

#define COMPUTE_USER_UNKNOWN UINT64_MAX

typedef enum {
    COMPUTE_QUEUED,     /* run() and done() will be called */
    COMPUTE_OVER_SHARE, /* the user already has their share of this class */
    COMPUTE_FULL,       /* the queue is full */
    COMPUTE_STOPPED     /* the pool is shutting down */
} compute_admit;

typedef struct compute_pool compute_pool;

/* NULL if threads < 1 or out of resources. */
compute_pool *compute_pool_create(int threads, int user_evaluates, int user_renders, int queue_cap);
compute_admit compute_pool_submit(compute_pool *cp, compute_task *t);
/* The share of a class (for the 429 message). */
int compute_pool_share(const compute_pool *cp, compute_class compute);
/* Work done by the caller itself (an evaluate small enough to run on the HTTP thread) counts
 * in the same per-user share: true if the user had room, and then the caller must give it back
 * with compute_pool_release_share once the work is done. */
bool compute_pool_acquire_share(compute_pool *cp, compute_class compute, uint64_t user);
void compute_pool_release_share(compute_pool *cp, compute_class compute, uint64_t user);
/* Tasks of the class the user has admitted now. */
int compute_pool_user_load(compute_pool *cp, compute_class compute, uint64_t user);
/* Refuses new tasks, runs every admitted one to the end and joins the threads. */
void compute_pool_stop(compute_pool *cp);
void compute_pool_destroy(compute_pool *cp); /* stops first if needed */

#endif
