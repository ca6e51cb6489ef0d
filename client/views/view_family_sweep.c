/* family-sweep: every placement configuration of the cost, ranked by E2, with a label that
 * reads as the configuration ("c0001 e1100 i0": samples on the four corners, the four edges
 * and inside the pixel). */
#include "job_views.h"

#include <string.h>

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"

/* Four counts as "0001", or "0.0.10.1" when one has two digits. */
static void counts(char *buf, size_t cap, const json_t *a)
{
    bool wide = false;
    for (size_t i = 0; i < json_array_size(a); i++)
        wide |= json_integer_value(json_array_get(a, i)) > 9;
    size_t used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < json_array_size(a) && used < cap; i++) {
        int n = snprintf(buf + used, cap - used, "%s%lld", wide && i ? "." : "",
                         (long long)json_integer_value(json_array_get(a, i)));
        if (n < 0)
            break;
        used += (size_t)n;
    }
}

static const char *config_label(char *buf, size_t cap, const json_t *config)
{
    if (!json_is_object(config))
        return NULL;
    char corners[48], edges[48];
    counts(corners, sizeof corners, json_object_get(config, "corners"));
    counts(edges, sizeof edges, json_object_get(config, "edges"));
    snprintf(buf, cap, "c%s e%s i%lld", corners, edges,
             (long long)json_integer_value(json_object_get(config, "interior")));
    return buf;
}

void view_family_sweep(FILE *out, const json_t *result, bool csv)
{
    if (!csv) {
        view_kv kv = {0};
        view_kv_number(&kv, "cost", json_object_get(result, "cost"), 2);
        view_kv_number(&kv, "configurations", json_object_get(result, "configurations"), 0);
        view_kv_number(&kv, "seeds_per_config", json_object_get(result, "seeds_per_config"), 0);
        view_kv_number(&kv, "best E2", json_object_get(result, "e2"), 6);
        view_kv_execution(&kv, result);
        view_kv_print(out, &kv);
        fputs("\nranked configurations\n", out);
    }
    const char *headers[] = {"rank", "configuration", "cost", "e2"};
    table *t = table_new(4, headers);
    if (!t)
        return;
    size_t i;
    json_t *row;
    json_array_foreach(json_object_get(result, "ranked"), i, row)
    {
        char rank[32], label[128], cost[32], e2[32];
        const char *cells[] = {
            fmt_number(rank, sizeof rank, json_object_get(row, "rank"), 0),
            config_label(label, sizeof label, json_object_get(row, "config")),
            fmt_number(cost, sizeof cost, json_object_get(row, "cost"), fmt_decimals(csv, 2)),
            fmt_number(e2, sizeof e2, json_object_get(row, "e2"), fmt_decimals(csv, 6))};
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
}
