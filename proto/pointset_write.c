/* Point sets -> text (pointset.h), and the export format names. */
#include "pointset.h"

#include <assert.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

bool proto_export_format_parse(const char *name, proto_export_writer *writer,
                               proto_points_format *points)
{
    if (!name)
        return false;
    if (!strcmp(name, "json")) {
        *writer = PROTO_EXPORT_PATTERN;
        return true;
    }
    if (!strcmp(name, "vulkan") || !strcmp(name, "d3d12") || !strcmp(name, "metal")) {
        *writer = name[0] == 'v'   ? PROTO_EXPORT_VULKAN
                  : name[0] == 'd' ? PROTO_EXPORT_D3D12
                                   : PROTO_EXPORT_METAL;
        return true;
    }
    if (!strcmp(name, "points-json")) {
        *writer = PROTO_EXPORT_POINTS;
        *points = PROTO_POINTS_JSON;
        return true;
    }
    if (strcmp(name, "json") && proto_points_format_parse(name, points)) {
        *writer = PROTO_EXPORT_POINTS;
        return true;
    }
    return false;
}

/* A growing text buffer; ok turns false at the first allocation failure. */
typedef struct text_buf {
    char *s;
    size_t len, cap;
    bool ok;
} text_buf;

static void put(text_buf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static void put(text_buf *b, const char *fmt, ...)
{
    if (!b->ok)
        return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int n = vsnprintf(b->s + b->len, b->cap - b->len, fmt, ap);
        va_end(ap);
        if (n < 0) {
            b->ok = false;
            return;
        }
        if ((size_t)n < b->cap - b->len) {
            b->len += (size_t)n;
            return;
        }
        size_t cap = (b->cap + (size_t)n + 1) * 2;
        char *s = realloc(b->s, cap);
        if (!s) {
            b->ok = false;
            return;
        }
        b->s = s;
        b->cap = cap;
    }
}

static char *write_json(const proto_pointset *ps, size_t *len)
{
    json_t *a = json_array();
    for (size_t i = 0; a && i < ps->count; i++) {
        const proto_point *q = &ps->points[i];
        json_array_append_new(a, ps->has_weights ? json_pack("[fff]", q->x, q->y, q->w)
                                                 : json_pack("[ff]", q->x, q->y));
    }
    json_t *o = ps->header ? json_pack("{s:O,s:o}", "aalab", ps->header, "points", a) : a;
    char *s = o ? json_dumps(o, JSON_COMPACT) : NULL;
    json_decref(o);
    if (!s)
        return NULL;
    size_t n = strlen(s);
    char *t = realloc(s, n + 2); /* a text file ends with a newline */
    if (!t) {
        free(s);
        return NULL;
    }
    t[n] = '\n';
    t[n + 1] = 0;
    *len = n + 1;
    return t;
}

char *proto_pointset_write(const proto_pointset *ps, proto_points_format fmt, size_t *len)
{
    assert(ps->points || !ps->count); /* a set from the parser or proto_export_points */
    if (fmt == PROTO_POINTS_JSON)
        return write_json(ps, len);
    if (proto_points_format_is_binary(fmt))
        return proto_pointset_write_binary(ps, fmt, len);
    text_buf b = {malloc(4096), 0, 4096, true};
    b.ok = b.s != NULL;
    if (ps->header) {
        char *h = json_dumps(ps->header, JSON_COMPACT);
        if (h)
            put(&b, "%s%s\n", PROTO_POINTS_HEADER, h);
        else
            b.ok = false;
        free(h);
    }
    bool w = ps->has_weights && fmt != PROTO_POINTS_UTK;
    if (fmt == PROTO_POINTS_CSV)
        put(&b, w ? "x,y,w\n" : "x,y\n");
    const char *sep = fmt == PROTO_POINTS_CSV ? "," : " ";
    for (size_t i = 0; i < ps->count && b.ok; i++) {
        const proto_point *q = &ps->points[i];
        if (w)
            put(&b, "%.17g%s%.17g%s%.17g\n", q->x, sep, q->y, sep, q->w);
        else
            put(&b, "%.17g%s%.17g\n", q->x, sep, q->y);
    }
    if (!b.ok) {
        free(b.s);
        return NULL;
    }
    *len = b.len;
    return b.s;
}

char *proto_export_points(const aa_pattern *p, proto_points_format fmt, size_t *len, aa_error *err)
{
    proto_pointset ps;
    if (proto_pointset_of_pattern(p, &ps, err))
        return NULL;
    char *s = proto_pointset_write(&ps, fmt, len);
    proto_pointset_free(&ps);
    if (!s)
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
    return s;
}
