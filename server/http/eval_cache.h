/* An LRU cache of deterministic answers: POST /v1/evaluate (key = the exact request body
 * bytes) and POST /v1/families/enumerate (key = "enumerate P(4,1+,n) <cost>"); value = the exact
 * response body. Bounded by entries (--eval-cache) and by 64 MiB of keys and values; answers
 * over 8 MiB are not kept. Thread-safe (one mutex; lookups are a hash and a memcmp). */
#ifndef AALAB_EVAL_CACHE_H
#define AALAB_EVAL_CACHE_H

#include <stdbool.h>
#include <stddef.h>

typedef struct eval_cache eval_cache;

eval_cache *eval_cache_create(size_t capacity); /* NULL when capacity == 0 */
void eval_cache_destroy(eval_cache *c);
/* On a hit, *out is a malloc'd copy of the response body. */
bool eval_cache_get(eval_cache *c, const char *key, size_t key_len, char **out, size_t *out_len);
/* Is key cached? No LRU or statistics effect (the HTTP layer asks before choosing a thread). */
bool eval_cache_contains(eval_cache *c, const char *key, size_t key_len);
void eval_cache_put(eval_cache *c, const char *key, size_t key_len, const char *val,
                    size_t val_len);

/* An evaluate's key: the caller's uid, then the body. Keyed per user, a cached answer tells a
 * caller only about its own earlier requests: a shared key let one user learn from the
 * answer's speed (120 against 183 us) that another had sent the same body. malloc'd; NULL on
 * out of memory. */
char *eval_cache_user_key(long long uid, const char *body, size_t len, size_t *key_len);

typedef struct eval_cache_stats {
    size_t entries, capacity, bytes;
    unsigned long long hits, misses;
} eval_cache_stats;
void eval_cache_stats_get(eval_cache *c, eval_cache_stats *out);

#endif
