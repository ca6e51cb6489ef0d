/* aa_fork_join: every item runs exactly once, item 0 on the calling thread, the others on
 * threads of their own, and all have finished when it returns. */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <time.h>

#include <cmocka.h>

#include "aa_core.h"

typedef struct item {
    int runs;
    pthread_t ran_on;
    double padding[3]; /* a stride that is not a pointer's */
} item;

static void mark(void *arg)
{
    item *it = arg;
    struct timespec nap = {0, 2000000}; /* 2 ms: joins must really wait */
    nanosleep(&nap, NULL);
    it->ran_on = pthread_self();
    it->runs++;
}

static void test_every_item_once(void **state)
{
    (void)state;
    for (int count = 1; count <= 9; count++) {
        item items[9] = {0};
        aa_fork_join(items, sizeof items[0], count, mark);
        for (int k = 0; k < 9; k++)
            assert_int_equal(items[k].runs, k < count ? 1 : 0);
        assert_true(pthread_equal(items[0].ran_on, pthread_self()));
        for (int k = 1; k < count; k++)
            assert_false(pthread_equal(items[k].ran_on, pthread_self()));
    }
}

static void test_nothing_to_run(void **state)
{
    (void)state;
    item it = {0};
    aa_fork_join(&it, sizeof it, 0, mark);
    assert_int_equal(it.runs, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_item_once),
        cmocka_unit_test(test_nothing_to_run),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
