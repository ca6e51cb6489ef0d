/* Pieces the splittable kinds share: contiguous index ranges as shard descriptors
 * ({"first": i, "count": n}), strict reading of the kinds' own JSON, and the local executor's
 * entry point. */
#ifndef AALAB_SPLIT_RANGES_H
#define AALAB_SPLIT_RANGES_H

#include <stddef.h>

#include <jansson.h>

#include "aa_core.h"

/* [0, n) as at most max_shards (>= 1) contiguous ranges of sizes differing by at most one, the
 * larger first; NULL when out of memory. */
json_t *split_ranges(size_t n, size_t max_shards);
/* A range descriptor, checked to lie inside [0, n). */
int split_range_decode(const json_t *shard, size_t n, size_t *first, size_t *count, aa_error *err);
/* The array at key, of the given length (field names the key). */
int split_array(const json_t *obj, const char *key, size_t length, json_t **out, aa_error *err);

#endif
