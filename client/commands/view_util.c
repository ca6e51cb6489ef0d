#define _POSIX_C_SOURCE 200809L
#include "view_util.h"

#include <stdbool.h>

#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../cli.h"
#include "../table.h"

const json_t *list_member(const json_t *resp, const char *member)
{
    if (json_is_array(resp))
        return resp;
    const json_t *v = json_object_get(resp, member);
    return json_is_array(v) ? v : NULL;
}

const char *fmt_time(char *buf, size_t cap, const json_t *v)
{
    if (!json_is_number(v))
        return fmt_number(buf, cap, v, 0);
    time_t t = (time_t)json_number_value(v);
    struct tm tm;
    if (!gmtime_r(&t, &tm) || strftime(buf, cap, "%Y-%m-%d %H:%M:%S", &tm) == 0)
        snprintf(buf, cap, "-");
    return buf;
}

/* A short array of scalars reads as "a, b, c"; anything longer or nested as "[n items]". */
static const char *fmt_short_array(char *buf, size_t cap, const json_t *a)
{
    size_t n = json_array_size(a), used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < n && n <= 16; i++) {
        const json_t *v = json_array_get(a, i);
        char item[64];
        if (json_is_string(v))
            snprintf(item, sizeof item, "%s", json_string_value(v));
        else if (json_is_number(v))
            snprintf(item, sizeof item, "%.6g", json_number_value(v));
        else
            break;
        int w = snprintf(buf + used, cap - used, "%s%s", i ? ", " : "", item);
        if (w < 0 || (size_t)w >= cap - used)
            break;
        used += (size_t)w;
        if (i + 1 == n)
            return buf;
    }
    snprintf(buf, cap, "[%zu items]", n);
    return buf;
}

/* Members that hold Unix times in the job schema (proto/schemas/job.json). */
static bool is_time_key(const char *key)
{
    size_t n = strlen(key);
    return !strcmp(key, "created") || !strcmp(key, "started") || !strcmp(key, "finished") ||
           (n > 3 && !strcmp(key + n - 3, "_at"));
}

typedef struct flat_list {
    char **keys, **values;
    size_t n, cap;
} flat_list;

static void flat_add(flat_list *l, const char *key, const char *value)
{
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 16;
        char **k = realloc(l->keys, cap * sizeof *k);
        if (!k)
            return;
        l->keys = k;
        char **v = realloc(l->values, cap * sizeof *v);
        if (!v)
            return;
        l->values = v;
        l->cap = cap;
    }
    l->keys[l->n] = strdup(key);
    l->values[l->n] = strdup(value);
    l->n++;
}

static void flatten(flat_list *l, const char *prefix, const json_t *obj, int depth)
{
    const char *key;
    json_t *v;
    json_object_foreach((json_t *)obj, key, v)
    {
        char name[128], buf[64];
        int n = snprintf(name, sizeof name, "%s%s%s", prefix, *prefix ? "." : "", key);
        if (n < 0 || (size_t)n >= sizeof name)
            continue; /* a key path this long is not for a table; --json has it */
        if (json_is_object(v) && depth < 3) {
            flatten(l, name, v, depth + 1);
        } else if (json_is_array(v)) {
            char list[256];
            flat_add(l, name, fmt_short_array(list, sizeof list, v));
        } else if (json_is_string(v)) {
            flat_add(l, name, json_string_value(v));
        } else if (json_is_boolean(v)) {
            flat_add(l, name, json_is_true(v) ? "true" : "false");
        } else if (json_is_null(v)) {
            flat_add(l, name, "-");
        } else if (json_is_number(v) && is_time_key(key)) {
            flat_add(l, name, fmt_time(buf, sizeof buf, v));
        } else if (json_is_real(v)) {
            snprintf(buf, sizeof buf, "%.6g", json_real_value(v));
            flat_add(l, name, buf);
        } else {
            flat_add(l, name, fmt_number(buf, sizeof buf, v, 0));
        }
    }
}

void print_flat(FILE *out, const json_t *obj)
{
    print_flat_as(out, obj, false);
}

void print_flat_as(FILE *out, const json_t *obj, bool csv)
{
    flat_list l = {0};
    if (json_is_object(obj))
        flatten(&l, "", obj, 0);
    if (csv)
        print_key_values_csv(out, (const char *const *)l.keys, (const char *const *)l.values, l.n);
    else
        print_key_values(out, (const char *const *)l.keys, (const char *const *)l.values, l.n);
    for (size_t i = 0; i < l.n; i++) {
        free(l.keys[i]);
        free(l.values[i]);
    }
    free(l.keys);
    free(l.values);
}

const json_t *job_best_e2(const json_t *job)
{
    const json_t *e2 = json_object_get(job, "best_e2");
    if (json_is_number(e2))
        return e2;
    e2 = json_object_get(json_object_get(job, "best"), "e2");
    return json_is_number(e2) ? e2 : NULL;
}
