#include "view_point_metrics.h"

#include <stdio.h>

#include "../cli.h"
#include "../table.h"

size_t view_point_metrics_headers(const json_t *pm, char (*names)[48], size_t max)
{
    size_t n = 0, i;
    const json_t *m;
    json_array_foreach(json_object_get(pm, "metrics"), i, m)
    {
        if (n == max)
            break;
        snprintf(names[n++], 48, "spearman_%s", fmt_string(m));
    }
    return n;
}

void view_point_metrics_cells(const json_t *pm, size_t count, const char **cells, char (*bufs)[32],
                              bool csv)
{
    const json_t *rho = json_object_get(pm, "spearman");
    for (size_t k = 0; k < count; k++)
        cells[k] = fmt_number(bufs[k], sizeof bufs[k],
                              json_object_get(json_array_get(rho, k), "rho"), fmt_decimals(csv, 3));
}

void view_point_metrics_print(FILE *out, const json_t *const *blocks, const char *const *labels,
                              size_t count)
{
    bool any = false, labelled = labels != NULL;
    for (size_t b = 0; b < count; b++)
        any |= json_array_size(json_object_get(blocks[b], "spearman")) > 0;
    if (!any)
        return;
    const char *headers[] = {"distribution", "figure", "rho", "n", "p_value"};
    table *t = table_new(labelled ? 5 : 4, labelled ? headers : headers + 1);
    if (!t)
        return;
    for (size_t b = 0; b < count; b++) {
        size_t i;
        const json_t *e;
        json_array_foreach(json_object_get(blocks[b], "spearman"), i, e)
        {
            char rho[32], n[32], p[32];
            const char *cells[] = {labelled ? labels[b] : NULL,
                                   fmt_string(json_object_get(e, "metric")),
                                   fmt_number(rho, sizeof rho, json_object_get(e, "rho"), 3),
                                   fmt_number(n, sizeof n, json_object_get(e, "n"), 0), NULL};
            const json_t *pv = json_object_get(e, "p_value");
            if (json_is_number(pv))
                snprintf(p, sizeof p, "%.2g", json_number_value(pv));
            cells[4] = json_is_number(pv) ? p : NULL;
            table_add_row(t, labelled ? cells : cells + 1);
        }
    }
    fputs("\nSpearman's rho of each point-set figure with E2 over the random patterns:\n", out);
    table_print(t, out);
    table_free(t);
}
