/* Binary point-set files (pointset.h), little-endian on every host:
 *
 * UTK .bin (utk-team/utk, include/utk/utils/PointsetIO.hpp, write_bin_pointsets and
 * read_bin_pointsets): bytes 0-3 the magic 0x214B5455 ("UTK!"), 4 dtype (0 int32, 1 int64,
 * 2 uint32, 3 uint64, 4 float, 5 double), 5-7 reserved, 8-11 m (sets), 12-15 N (points per set),
 * 16-19 d (dimension), then m sets of N points of d values. aalab reads float and double, d = 2,
 * and writes double with m = 1; its aalab-pattern header follows the data as a trailer line
 * (UTK reads m N d values and stops there).
 *
 * PSA .rps (nodag/psa, src/point.cpp, PointSet::Load/Save): x y pairs of float32, nothing
 * else; the point count is the file's size / 8. */
#include "pointset.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec_internal.h"

#define UTK_MAGIC 0x214B5455u
#define UTK_HEADER_BYTES 20
#define UTK_DTYPE_FLOAT 4
#define UTK_DTYPE_DOUBLE 5

static uint32_t get_u32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static void put_u32(unsigned char *b, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        b[i] = (unsigned char)(v >> (8 * i));
}

static double get_f32(const unsigned char *b)
{
    uint32_t u = get_u32(b);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static double get_f64(const unsigned char *b)
{
    uint64_t u = (uint64_t)get_u32(b) | (uint64_t)get_u32(b + 4) << 32;
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

/* n points of 2 values of `size` bytes from b. */
static int read_points(const unsigned char *b, size_t n, size_t size, proto_pointset *ps,
                       const char *field, aa_error *err)
{
    size_t cap = 0;
    for (size_t i = 0; i < n; i++) {
        const unsigned char *q = b + i * 2 * size;
        double x = size == 4 ? get_f32(q) : get_f64(q);
        double y = size == 4 ? get_f32(q + size) : get_f64(q + size);
        if (!isfinite(x) || !isfinite(y))
            return aa_error_set(err, AA_EINVAL, field, "point %zu: %s is not a finite number (%g)",
                                i, isfinite(x) ? "y" : "x", isfinite(x) ? y : x);
        if (proto_pointset_push(ps, &cap, (proto_point){x, y, 0}, i))
            return aa_error_set(err, AA_ENOMEM, field, "out of memory");
    }
    return AA_OK;
}

/* An aalab-pattern trailer after UTK data: the header line, optionally ending in a newline.
 * 1 when the bytes are not one. */
static int read_trailer(const unsigned char *b, size_t n, proto_pointset *ps, const char *field,
                        aa_error *err)
{
    size_t hn = strlen(PROTO_POINTS_HEADER);
    if (n < hn || memcmp(b, PROTO_POINTS_HEADER, hn))
        return 1;
    if (n && b[n - 1] == '\n')
        n--;
    json_error_t je;
    json_t *h = json_loadb((const char *)b + hn, n - hn, JSON_REJECT_DUPLICATES, &je);
    if (!h || !json_is_object(h)) {
        json_decref(h);
        return aa_error_set(err, AA_EINVAL, field,
                            "the aalab-pattern trailer after the data is not a JSON object");
    }
    ps->header = h;
    return AA_OK;
}

static const char *dtype_name(unsigned t)
{
    static const char *const names[] = {"int32", "int64", "uint32", "uint64", "float", "double"};
    return t < 6 ? names[t] : "unknown";
}

/* count_only: the header (and trailer) checked, *set_count set, no point read. */
static int parse_utk(const unsigned char *b, size_t len, size_t set, bool count_only,
                     proto_pointset *ps, size_t *set_count, const char *field,
                     const char *set_field, aa_error *err)
{
    if (len < UTK_HEADER_BYTES)
        return aa_error_set(err, AA_EINVAL, field,
                            "truncated: %zu bytes, but UTK's header alone is %d (magic, dtype, m, "
                            "N, d)",
                            len, UTK_HEADER_BYTES);
    uint32_t magic = get_u32(b);
    if (magic != UTK_MAGIC)
        return aa_error_set(err, AA_EINVAL, field,
                            "bytes 0-3: magic is 0x%08X, not UTK's 0x%08X (\"UTK!\")", magic,
                            UTK_MAGIC);
    unsigned dtype = b[4];
    if (dtype != UTK_DTYPE_FLOAT && dtype != UTK_DTYPE_DOUBLE)
        return aa_error_set(err, AA_EINVAL, field,
                            "byte 4: dtype is %u (%s); aalab reads float (4) and double (5)", dtype,
                            dtype_name(dtype));
    uint32_t m = get_u32(b + 8), N = get_u32(b + 12), d = get_u32(b + 16);
    if (d != 2)
        return aa_error_set(err, AA_EINVAL, field,
                            "bytes 16-19: dimension d is %u; aalab reads 2-D point sets only", d);
    if (m == 0 || N == 0)
        return aa_error_set(err, AA_EINVAL, field,
                            "no points: the header says m = %u sets of N = %u", m, N);
    if (N > PROTO_POINTS_MAX)
        return aa_error_set(err, AA_ERANGE, field,
                            "bytes 12-15: N is %u points per set, more than %d", N,
                            PROTO_POINTS_MAX);
    size_t size = dtype == UTK_DTYPE_FLOAT ? 4 : 8;
    uint64_t per_set = (uint64_t)N * 2 * size, data = (uint64_t)m * per_set; /* <= 2^48 */
    uint64_t after = len - UTK_HEADER_BYTES;
    if (after < data)
        return aa_error_set(err, AA_EINVAL, field,
                            "truncated: the header says m = %u sets of N = %u points of d = 2 %s "
                            "(%llu bytes of data), but %llu bytes follow it",
                            m, N, dtype_name(dtype), (unsigned long long)data,
                            (unsigned long long)after);
    if (after > data) {
        int rc = read_trailer(b + UTK_HEADER_BYTES + data, (size_t)(after - data), ps, field, err);
        if (rc > 0)
            return aa_error_set(err, AA_EINVAL, field,
                                "count mismatch: the header says m = %u sets of N = %u points of "
                                "d = 2 %s (%llu bytes of data), but %llu bytes follow it",
                                m, N, dtype_name(dtype), (unsigned long long)data,
                                (unsigned long long)after);
        if (rc)
            return rc;
    }
    if (set_count)
        *set_count = m;
    if (count_only)
        return AA_OK;
    if (set == PROTO_POINTS_WHOLE && m != 1)
        return aa_error_set(err, AA_EINVAL, set_field,
                            "the file holds %u sets (UTK's m); choose one with set", m);
    size_t which = set == PROTO_POINTS_WHOLE ? 0 : set;
    if (which >= m)
        return aa_error_set(err, AA_ERANGE, set_field,
                            "is %zu but the file holds %u set%s (sets count from 0)", set, m,
                            m == 1 ? "" : "s");
    return read_points(b + UTK_HEADER_BYTES + which * per_set, N, size, ps, field, err);
}

static int parse_rps(const unsigned char *b, size_t len, size_t set, proto_pointset *ps,
                     size_t *set_count, const char *field, const char *set_field, aa_error *err)
{
    if (set_count)
        *set_count = 1;
    if (set != PROTO_POINTS_WHOLE && set != 0)
        return aa_error_set(err, AA_ERANGE, set_field, "is %zu but an rps file holds one set", set);
    if (len % 8)
        return aa_error_set(err, AA_EINVAL, field,
                            "truncated: %zu bytes is not a whole number of points (8 bytes each: "
                            "x and y as little-endian float32)",
                            len);
    if (len == 0)
        return aa_error_set(err, AA_EINVAL, field, "no points (an empty file)");
    if (len / 8 > PROTO_POINTS_MAX)
        return aa_error_set(err, AA_ERANGE, field, "%zu points, more than %d", len / 8,
                            PROTO_POINTS_MAX);
    return read_points(b, len / 8, 4, ps, field, err);
}

int proto_pointset_parse_binary(const unsigned char *b, size_t len, proto_points_format fmt,
                                size_t set, proto_pointset *out, size_t *set_count,
                                const char *field, const char *set_field, aa_error *err)
{
    memset(out, 0, sizeof *out);
    int rc = fmt == PROTO_POINTS_BIN
                 ? parse_utk(b, len, set, false, out, set_count, field, set_field, err)
                 : parse_rps(b, len, set, out, set_count, field, set_field, err);
    if (rc)
        proto_pointset_free(out);
    return rc;
}

int proto_pointset_binary_set_count(const unsigned char *b, size_t len, proto_points_format fmt,
                                    size_t *count, const char *field, aa_error *err)
{
    *count = 1;
    if (fmt != PROTO_POINTS_BIN)
        return AA_OK;
    proto_pointset ps;
    memset(&ps, 0, sizeof ps);
    int rc = parse_utk(b, len, 0, true, &ps, count, field, field, err);
    proto_pointset_free(&ps);
    return rc;
}

/* bin: UTK header, float64 points, the header trailer; rps: float32 points. */
char *proto_pointset_write_binary(const proto_pointset *ps, proto_points_format fmt, size_t *len)
{
    bool utk = fmt == PROTO_POINTS_BIN;
    char *trailer = NULL;
    size_t tn = 0;
    if (utk && ps->header) {
        char *h = json_dumps(ps->header, JSON_COMPACT);
        if (!h)
            return NULL;
        tn = strlen(PROTO_POINTS_HEADER) + strlen(h) + 1;
        trailer = malloc(tn + 1);
        if (trailer)
            snprintf(trailer, tn + 1, "%s%s\n", PROTO_POINTS_HEADER, h);
        free(h);
        if (!trailer)
            return NULL;
    }
    size_t size = utk ? 8 : 4, head = utk ? UTK_HEADER_BYTES : 0;
    size_t n = head + ps->count * 2 * size + tn;
    unsigned char *b = calloc(n + 1, 1); /* NUL-terminated like the text formats */
    if (!b) {
        free(trailer);
        return NULL;
    }
    if (utk) {
        put_u32(b, UTK_MAGIC);
        b[4] = UTK_DTYPE_DOUBLE;
        put_u32(b + 8, 1);
        put_u32(b + 12, (uint32_t)ps->count);
        put_u32(b + 16, 2);
    }
    unsigned char *q = b + head;
    assert(ps->points || !ps->count);
    for (size_t i = 0; i < ps->count; i++) {
        double v[2] = {ps->points[i].x, ps->points[i].y};
        for (int k = 0; k < 2; k++, q += size) {
            uint64_t u;
            if (utk) {
                memcpy(&u, &v[k], 8);
                put_u32(q, (uint32_t)u);
                put_u32(q + 4, (uint32_t)(u >> 32));
            } else {
                float f = (float)v[k];
                uint32_t w;
                memcpy(&w, &f, 4);
                put_u32(q, w);
            }
        }
    }
    assert((size_t)(q - b) + tn == n); /* the points filled what was sized for them */
    if (tn)
        memcpy(q, trailer, tn);
    free(trailer);
    *len = n;
    return (char *)b;
}
