/* Shard descriptors of contiguous index ranges (split_ranges.h). */
#include "split_ranges.h"

json_t *split_ranges(size_t n, size_t max_shards)
{
    size_t shards = max_shards < 1 ? 1 : max_shards < n ? max_shards : n;
    json_t *a = json_array();
    size_t first = 0;
    for (size_t i = 0; a && i < shards; i++) {
        size_t count = n / shards + (i < n % shards ? 1 : 0);
        if (json_array_append_new(a, json_pack("{s:I,s:I}", "first", (json_int_t)first, "count",
                                               (json_int_t)count))) {
            json_decref(a);
            return NULL;
        }
        first += count;
    }
    return a;
}

int split_range_decode(const json_t *shard, size_t n, size_t *first, size_t *count, aa_error *err)
{
    json_int_t f = -1, c = -1;
    json_error_t je;
    if (json_unpack_ex((json_t *)shard, &je, JSON_STRICT, "{s:I,s:I}", "first", &f, "count", &c))
        return aa_error_set(err, AA_EINVAL, "shard", "expected {\"first\":i,\"count\":n}: %s",
                            je.text);
    if (f < 0 || c < 1 || (size_t)f >= n || (size_t)c > n - (size_t)f)
        return aa_error_set(err, AA_EINVAL, "shard", "range [%lld, %lld) is not inside [0, %zu)",
                            (long long)f, (long long)(f + c), n);
    *first = (size_t)f;
    *count = (size_t)c;
    return AA_OK;
}

int split_array(const json_t *obj, const char *key, size_t length, json_t **out, aa_error *err)
{
    json_t *a = json_object_get(obj, key);
    if (!json_is_array(a) || json_array_size(a) != length)
        return aa_error_set(err, AA_EINVAL, key, "must be an array of %zu entries", length);
    *out = a;
    return AA_OK;
}
