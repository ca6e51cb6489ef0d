/* eval_cache: hits return the stored bytes, LRU eviction by entry count and by total bytes,
 * oversized answers are not kept. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "eval_cache.h"

static bool has(eval_cache *c, const char *key)
{
    char *v = NULL;
    size_t n = 0;
    bool hit = eval_cache_get(c, key, strlen(key), &v, &n);
    free(v);
    return hit;
}

static void test_hit_returns_stored_bytes(void **state)
{
    (void)state;
    eval_cache *c = eval_cache_create(4);
    assert_non_null(c);
    assert_false(has(c, "a"));
    eval_cache_put(c, "a", 1, "value\0with nul", 14);
    char *v = NULL;
    size_t n = 0;
    assert_true(eval_cache_get(c, "a", 1, &v, &n));
    assert_int_equal(n, 14);
    assert_memory_equal(v, "value\0with nul", 14);
    assert_int_equal(v[14], '\0');
    free(v);
    eval_cache_stats st;
    eval_cache_stats_get(c, &st);
    assert_int_equal(st.entries, 1);
    assert_int_equal(st.bytes, 15);
    assert_int_equal(st.hits, 1);
    assert_int_equal(st.misses, 1);
    eval_cache_destroy(c);
    assert_null(eval_cache_create(0));
}

static void test_lru_by_count(void **state)
{
    (void)state;
    eval_cache *c = eval_cache_create(2);
    eval_cache_put(c, "a", 1, "1", 1);
    eval_cache_put(c, "b", 1, "2", 1);
    assert_true(has(c, "a")); /* a is now the most recent */
    eval_cache_put(c, "c", 1, "3", 1);
    assert_true(has(c, "a"));
    assert_false(has(c, "b"));
    assert_true(has(c, "c"));
    eval_cache_destroy(c);
}

static void test_bounded_by_bytes(void **state)
{
    (void)state;
    size_t five = 5u << 20;
    char *big = calloc(1, 9u << 20);
    eval_cache *c = eval_cache_create(1000);
    char key[16];
    for (int i = 0; i < 20; i++) {
        snprintf(key, sizeof key, "k%d", i);
        eval_cache_put(c, key, strlen(key), big, five);
    }
    eval_cache_stats st;
    eval_cache_stats_get(c, &st);
    assert_true(st.bytes <= (64u << 20));
    assert_int_equal(st.entries, 12); /* 12 x 5 MiB fit in 64 MiB, 13 do not */
    assert_false(has(c, "k0"));
    assert_false(has(c, "k7"));
    assert_true(has(c, "k8"));
    assert_true(has(c, "k19"));
    eval_cache_put(c, "huge", 4, big, 9u << 20); /* over 8 MiB: not kept */
    assert_false(has(c, "huge"));
    assert_true(has(c, "k8"));
    eval_cache_destroy(c);
    free(big);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hit_returns_stored_bytes),
        cmocka_unit_test(test_lru_by_count),
        cmocka_unit_test(test_bounded_by_bytes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
