/* random-stats: the columns of Laine & Aila's Table 3 for one family: min, avg and max E2 of
 * the random patterns, then Opt W (the best random one with its weights optimised) and
 * Opt W+P (weights and positions). With the spec's metrics, Spearman's rho of each point-set
 * figure with E2: a table under the text, spearman_<figure> columns in CSV. */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"
#include "view_point_metrics.h"

void view_random_stats(FILE *out, const json_t *result, bool csv)
{
    const json_t *random = json_object_get(result, "random");
    const json_t *opt_w = json_object_get(result, "opt_w");
    const json_t *opt_wp = json_object_get(result, "opt_wp");
    const json_t *pm = json_object_get(result, "point_metrics");
    char names[VIEW_PM_MAX][48];
    size_t figures = csv ? view_point_metrics_headers(pm, names, VIEW_PM_MAX) : 0;
    const char *headers[8 + VIEW_PM_MAX] = {"family", "distribution", "count", "min",
                                            "avg",    "max",          "opt_w", "opt_wp"};
    for (size_t k = 0; k < figures; k++)
        headers[8 + k] = names[k];
    table *t = table_new(8 + figures, headers);
    if (!t)
        return;
    char count[32], mn[32], avg[32], mx[32], w[32], wp[32];
    const char *cells[8 + VIEW_PM_MAX] = {
        fmt_string(json_object_get(result, "family")),
        fmt_string(json_object_get(result, "distribution")),
        fmt_number(count, sizeof count, json_object_get(result, "count"), 0),
        fmt_number(mn, sizeof mn, json_object_get(random, "min"), fmt_decimals(csv, 4)),
        fmt_number(avg, sizeof avg, json_object_get(random, "avg"), fmt_decimals(csv, 4)),
        fmt_number(mx, sizeof mx, json_object_get(random, "max"), fmt_decimals(csv, 4)),
        fmt_number(w, sizeof w, json_object_get(opt_w, "e2"), fmt_decimals(csv, 4)),
        fmt_number(wp, sizeof wp, json_object_get(opt_wp, "e2"), fmt_decimals(csv, 4))};
    char rho[VIEW_PM_MAX][32];
    view_point_metrics_cells(pm, figures, cells + 8, rho, csv);
    table_add_row(t, cells);
    table_write(t, out, csv);
    table_free(t);
    if (csv)
        return;
    view_point_metrics_print(out, &pm, NULL, 1);
    view_kv kv = {0};
    view_kv_add(&kv, "Opt W method", "%s", view_str(json_object_get(opt_w, "method")));
    view_kv_add(&kv, "Opt W+P method", "%s", view_str(json_object_get(opt_wp, "method")));
    view_kv_execution(&kv, result);
    fputc('\n', out);
    view_kv_print(out, &kv);
}
