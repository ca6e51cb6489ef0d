#include "view_kv.h"

#include <stdarg.h>

#include "../cli.h"
#include "../table.h"

void view_kv_add(view_kv *kv, const char *key, const char *fmt, ...)
{
    if (kv->n >= VIEW_KV_MAX)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(kv->values[kv->n], sizeof kv->values[kv->n], fmt, ap);
    va_end(ap);
    kv->keys[kv->n++] = key;
}

void view_kv_number(view_kv *kv, const char *key, const json_t *v, int decimals)
{
    char buf[64];
    view_kv_add(kv, key, "%s", fmt_number(buf, sizeof buf, v, decimals));
}

void view_kv_print(FILE *out, const view_kv *kv)
{
    const char *values[VIEW_KV_MAX];
    for (size_t i = 0; i < kv->n; i++)
        values[i] = kv->values[i];
    print_key_values(out, kv->keys, values, kv->n);
}

void view_kv_scene(view_kv *kv, const json_t *scene)
{
    const char *name = json_string_value(json_object_get(scene, "name"));
    view_kv_add(kv, "scene", "%s %lldx%lld", name ? name : "-",
                (long long)json_integer_value(json_object_get(scene, "width")),
                (long long)json_integer_value(json_object_get(scene, "height")));
}

void view_kv_execution(view_kv *kv, const json_t *result)
{
    const json_t *executor = json_object_get(result, "executor");
    if (!json_is_string(executor))
        return;
    long long shards = json_integer_value(json_object_get(result, "shards"));
    view_kv_add(kv, "executor", "%s, %lld shard%s, %s", json_string_value(executor), shards,
                shards == 1 ? "" : "s",
                json_is_true(json_object_get(result, "reproducible"))
                    ? "reproducible"
                    : "best effort (time budget)");
    view_kv_acuity(kv, result);
}

const char *view_acuity_text(char *buf, size_t cap, const json_t *obj)
{
    const json_t *acuity = json_object_get(obj, "acuity");
    const json_t *version = json_object_get(acuity, "version");
    const char *name = json_string_value(json_object_get(acuity, "name"));
    if (!name)
        return NULL;
    if (json_is_integer(version))
        snprintf(buf, cap, "%s version %lld", name, (long long)json_integer_value(version));
    else
        snprintf(buf, cap, "%s", name);
    return buf;
}

void view_kv_acuity(view_kv *kv, const json_t *obj)
{
    char buf[96];
    if (view_acuity_text(buf, sizeof buf, obj))
        view_kv_add(kv, "acuity", "%s", buf);
}

const char *view_str(const json_t *v)
{
    return json_is_string(v) ? json_string_value(v) : "-";
}

void view_images_heading(FILE *out)
{
    fputs("\nimages (PNG; GET each URL on the socket, or with a token over TCP)\n", out);
}

void view_images_line(FILE *out, const char *label, const json_t *tiles)
{
    static const char *const IMAGES[] = {"pattern", "reference", "difference"};
    fprintf(out, "  %-18s", label);
    for (size_t i = 0; i < sizeof IMAGES / sizeof IMAGES[0]; i++) {
        const char *url =
            json_string_value(json_object_get(json_object_get(tiles, IMAGES[i]), "url"));
        if (url)
            fprintf(out, "  %s %s", IMAGES[i], url);
    }
    fputc('\n', out);
}
