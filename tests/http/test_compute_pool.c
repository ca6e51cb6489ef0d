/* compute_pool and key_counts: a user's evaluates and renders are admitted up to their shares
 * (429 territory beyond), shares are per user and per class, a finished task gives its share
 * back before done() runs, the queue bound holds, and stop runs every admitted task. */
#define _GNU_SOURCE
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "compute_pool.h"
#include "key_counts.h"

/* Tasks that block on a gate until the test opens it. */
typedef struct gate {
    pthread_mutex_t lock;
    pthread_cond_t cond;
    bool open;
    int started, ran, done;
    int load_seen_in_done; /* the user's load of the class when done() ran */
    compute_pool *pool;
} gate;

typedef struct item {
    gate *g;
    compute_task task;
} item;

static void run_blocked(void *arg)
{
    item *it = arg;
    pthread_mutex_lock(&it->g->lock);
    it->g->started++;
    pthread_cond_broadcast(&it->g->cond);
    while (!it->g->open)
        pthread_cond_wait(&it->g->cond, &it->g->lock);
    it->g->ran++;
    pthread_mutex_unlock(&it->g->lock);
}

static void note_done(void *arg)
{
    item *it = arg;
    int load = compute_pool_user_load(it->g->pool, it->task.compute, it->task.user);
    pthread_mutex_lock(&it->g->lock);
    it->g->done++;
    if (load > it->g->load_seen_in_done)
        it->g->load_seen_in_done = load;
    pthread_cond_broadcast(&it->g->cond);
    pthread_mutex_unlock(&it->g->lock);
}

static void gate_init(gate *g, compute_pool *cp)
{
    memset(g, 0, sizeof *g);
    pthread_mutex_init(&g->lock, NULL);
    pthread_cond_init(&g->cond, NULL);
    g->pool = cp;
}

static void gate_open(gate *g)
{
    pthread_mutex_lock(&g->lock);
    g->open = true;
    pthread_cond_broadcast(&g->cond);
    pthread_mutex_unlock(&g->lock);
}

static void gate_wait_done(gate *g, int n)
{
    pthread_mutex_lock(&g->lock);
    while (g->done < n)
        pthread_cond_wait(&g->cond, &g->lock);
    pthread_mutex_unlock(&g->lock);
}

static compute_admit submit(compute_pool *cp, item *it, gate *g, compute_class compute,
                            uint64_t user)
{
    it->g = g;
    it->task = (compute_task){
        .run = run_blocked, .done = note_done, .arg = it, .compute = compute, .user = user};
    return compute_pool_submit(cp, &it->task);
}

static void test_key_counts_limit_and_release(void **state)
{
    (void)state;
    key_counts *kc = key_counts_create();
    assert_non_null(kc);
    assert_true(key_counts_acquire(kc, 7, 2));
    assert_true(key_counts_acquire(kc, 7, 2));
    assert_false(key_counts_acquire(kc, 7, 2));
    assert_true(key_counts_acquire(kc, 8, 2));
    assert_int_equal(key_counts_get(kc, 7), 2);
    assert_int_equal(key_counts_keys(kc), 2);
    key_counts_release(kc, 7);
    assert_true(key_counts_acquire(kc, 7, 2));
    key_counts_release(kc, 7);
    key_counts_release(kc, 7);
    key_counts_release(kc, 8);
    assert_int_equal(key_counts_keys(kc), 0);
    assert_false(key_counts_acquire(kc, 9, 0));
    /* Many keys: the table grows. */
    for (uint64_t k = 0; k < 100; k++)
        assert_true(key_counts_acquire(kc, 1000 + k, 1));
    assert_int_equal(key_counts_keys(kc), 100);
    assert_int_not_equal(key_counts_hash("Bearer a"), key_counts_hash("Bearer b"));
    assert_int_equal(key_counts_hash("Bearer a"), key_counts_hash("Bearer a"));
    key_counts_destroy(kc);
}

static void test_shares_per_user_and_kind(void **state)
{
    (void)state;
    compute_pool *cp = compute_pool_create(2, 2, 1, 64);
    assert_non_null(cp);
    gate g;
    gate_init(&g, cp);
    item it[8];
    /* alice (1000): two evaluates, the third is over her share; one render, the second over. */
    assert_int_equal(submit(cp, &it[0], &g, COMPUTE_EVALUATE, 1000), COMPUTE_QUEUED);
    assert_int_equal(submit(cp, &it[1], &g, COMPUTE_EVALUATE, 1000), COMPUTE_QUEUED);
    assert_int_equal(submit(cp, &it[2], &g, COMPUTE_EVALUATE, 1000), COMPUTE_OVER_SHARE);
    assert_int_equal(submit(cp, &it[2], &g, COMPUTE_RENDER, 1000), COMPUTE_QUEUED);
    assert_int_equal(submit(cp, &it[3], &g, COMPUTE_RENDER, 1000), COMPUTE_OVER_SHARE);
    /* bob (1001) is not affected by alice's load, though both threads are busy. */
    assert_int_equal(submit(cp, &it[3], &g, COMPUTE_EVALUATE, 1001), COMPUTE_QUEUED);
    assert_int_equal(submit(cp, &it[4], &g, COMPUTE_RENDER, 1001), COMPUTE_QUEUED);
    assert_int_equal(compute_pool_user_load(cp, COMPUTE_EVALUATE, 1000), 2);
    assert_int_equal(compute_pool_user_load(cp, COMPUTE_RENDER, 1000), 1);
    assert_int_equal(compute_pool_user_load(cp, COMPUTE_EVALUATE, 1001), 1);
    assert_int_equal(compute_pool_share(cp, COMPUTE_EVALUATE), 2);
    assert_int_equal(compute_pool_share(cp, COMPUTE_RENDER), 1);
    gate_open(&g);
    gate_wait_done(&g, 5);
    assert_int_equal(g.ran, 5);
    /* Shares are back, each before its task's done() (alice's two evaluates: at most 1 left
     * when the first finished). */
    assert_true(g.load_seen_in_done <= 1);
    assert_int_equal(compute_pool_user_load(cp, COMPUTE_EVALUATE, 1000), 0);
    assert_int_equal(compute_pool_user_load(cp, COMPUTE_RENDER, 1000), 0);
    assert_int_equal(submit(cp, &it[5], &g, COMPUTE_RENDER, 1000), COMPUTE_QUEUED);
    gate_wait_done(&g, 6);
    compute_pool_destroy(cp);
}

static void test_queue_bound_and_stop_drains(void **state)
{
    (void)state;
    compute_pool *cp = compute_pool_create(1, 100, 100, 3);
    assert_non_null(cp);
    gate g;
    gate_init(&g, cp);
    item it[8];
    /* One task is taken by the thread, three wait; the fifth finds the queue full. */
    assert_int_equal(submit(cp, &it[0], &g, COMPUTE_EVALUATE, 1), COMPUTE_QUEUED);
    pthread_mutex_lock(&g.lock);
    while (g.started < 1)
        pthread_cond_wait(&g.cond, &g.lock);
    pthread_mutex_unlock(&g.lock);
    assert_int_equal(submit(cp, &it[1], &g, COMPUTE_EVALUATE, 2), COMPUTE_QUEUED);
    assert_int_equal(submit(cp, &it[2], &g, COMPUTE_EVALUATE, 3), COMPUTE_QUEUED);
    assert_int_equal(submit(cp, &it[3], &g, COMPUTE_EVALUATE, 4), COMPUTE_QUEUED);
    assert_int_equal(submit(cp, &it[4], &g, COMPUTE_EVALUATE, 5), COMPUTE_FULL);
    /* A refused task leaves no share behind. */
    assert_int_equal(compute_pool_user_load(cp, COMPUTE_EVALUATE, 5), 0);
    gate_open(&g);
    compute_pool_stop(cp); /* runs all four admitted tasks */
    assert_int_equal(g.ran, 4);
    assert_int_equal(g.done, 4);
    assert_int_equal(submit(cp, &it[5], &g, COMPUTE_EVALUATE, 1), COMPUTE_STOPPED);
    assert_int_equal(compute_pool_user_load(cp, COMPUTE_EVALUATE, 1), 0);
    compute_pool_destroy(cp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_key_counts_limit_and_release),
        cmocka_unit_test(test_shares_per_user_and_kind),
        cmocka_unit_test(test_queue_bound_and_stop_drains),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
