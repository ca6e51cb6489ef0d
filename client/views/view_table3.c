/* table3: Laine & Aila's Table 3 over K seeds, as the paper prints it: a row per distribution
 * with Min, Avg, Max, Opt W and Opt W+P, each followed by a ± column (the sd over the seeds),
 * and under it the paper's row where the paper has one. CSV: the same table, the paper's rows
 * named "<distribution> (paper)" with empty sd cells, the sd columns named min_sd ... opt_wp_sd.
 * With the spec's metrics: Spearman's rho of each point-set figure with E2 per distribution, a
 * table under the text and spearman_<figure> columns in CSV. */
#include "job_views.h"

#include <stdio.h>
#include <string.h>

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"
#include "view_point_metrics.h"

static const char *const columns[] = {"min", "avg", "max", "opt_w", "opt_wp"};
/* CSV headers are unique ASCII names (pandas renames repeated ones to "±.1", ...). */
static const char *const sd_columns[] = {"min_sd", "avg_sd", "max_sd", "opt_w_sd", "opt_wp_sd"};
enum { COLS = 5 };

void view_table3(FILE *out, const json_t *result, bool csv)
{
    const json_t *rows = json_object_get(result, "rows");
    /* every row has the same figures (the spec's) */
    char names[VIEW_PM_MAX][48];
    size_t figures =
        csv ? view_point_metrics_headers(json_object_get(json_array_get(rows, 0), "point_metrics"),
                                         names, VIEW_PM_MAX)
            : 0;
    const char *headers[1 + 2 * COLS + VIEW_PM_MAX] = {"distribution"};
    for (int c = 0; c < COLS; c++) {
        headers[1 + 2 * c] = columns[c];
        headers[2 + 2 * c] = csv ? sd_columns[c] : "±";
    }
    for (size_t k = 0; k < figures; k++)
        headers[1 + 2 * COLS + k] = names[k];
    table *t = table_new(1 + 2 * COLS + figures, headers);
    if (!t)
        return;
    size_t i;
    const json_t *row;
    json_array_foreach(rows, i, row)
    {
        const json_t *cols = json_object_get(row, "columns");
        char v[2 * COLS][32], paper[COLS][32], name[64], rho[VIEW_PM_MAX][32];
        const char *cells[1 + 2 * COLS + VIEW_PM_MAX] = {
            fmt_string(json_object_get(row, "distribution"))};
        const char *pcells[1 + 2 * COLS + VIEW_PM_MAX] = {name};
        bool have_paper = false;
        snprintf(name, sizeof name, "%s (paper)", cells[0]);
        for (int c = 0; c < COLS; c++) {
            const json_t *st = json_object_get(cols, columns[c]);
            cells[1 + 2 * c] = fmt_number(v[2 * c], sizeof v[2 * c], json_object_get(st, "mean"),
                                          fmt_decimals(csv, 4));
            cells[2 + 2 * c] = fmt_number(v[2 * c + 1], sizeof v[2 * c + 1],
                                          json_object_get(st, "sd"), fmt_decimals(csv, 4));
            const json_t *p = json_object_get(st, "paper");
            have_paper |= json_is_number(p);
            pcells[1 + 2 * c] = fmt_number(paper[c], sizeof paper[c], p, fmt_decimals(csv, 3));
            pcells[2 + 2 * c] = "";
        }
        view_point_metrics_cells(json_object_get(row, "point_metrics"), figures,
                                 cells + 1 + 2 * COLS, rho, csv);
        for (size_t k = 0; k < figures; k++)
            pcells[1 + 2 * COLS + k] = "";
        table_add_row(t, cells);
        if (have_paper)
            table_add_row(t, pcells);
    }
    table_write(t, out, csv);
    table_free(t);
    if (csv)
        return;
    view_kv kv = {0};
    view_kv_add(&kv, "family", "%s", view_str(json_object_get(result, "family")));
    char seeds[256] = "";
    size_t used = 0;
    const json_t *s;
    json_array_foreach(json_object_get(result, "seeds"), i, s)
    {
        int n = snprintf(seeds + used, sizeof seeds - used, "%s%lld", i ? " " : "",
                         (long long)json_integer_value(s));
        if (n < 0 || (size_t)n >= sizeof seeds - used)
            break;
        used += (size_t)n;
    }
    view_kv_add(&kv, "seeds", "%zu (rng_seed %s), %lld random patterns each",
                json_array_size(json_object_get(result, "seeds")), seeds,
                (long long)json_integer_value(json_object_get(result, "count")));
    char gens[512] = "";
    used = 0;
    json_array_foreach(json_object_get(result, "rows"), i, row)
    {
        const json_t *gen = json_object_get(row, "generator");
        const json_t *radius = json_object_get(gen, "radius");
        char r[48] = "";
        if (json_is_number(radius))
            snprintf(r, sizeof r, " (radius %.4g px)", json_number_value(radius));
        int n = snprintf(gens + used, sizeof gens - used, "%s%s: %s%s", i ? "; " : "",
                         view_str(json_object_get(row, "distribution")),
                         view_str(json_object_get(gen, "name")), r);
        if (n < 0 || (size_t)n >= sizeof gens - used)
            break;
        used += (size_t)n;
    }
    view_kv_add(&kv, "generators", "%s", gens);
    view_kv_execution(&kv, result);
    fputs("\n(± = sample standard deviation over the seeds)\n", out);
    view_kv_print(out, &kv);
    const json_t *blocks[8];
    const char *labels[8];
    size_t nb = 0;
    json_array_foreach(rows, i, row)
    {
        if (nb == 8)
            break;
        blocks[nb] = json_object_get(row, "point_metrics");
        labels[nb++] = fmt_string(json_object_get(row, "distribution"));
    }
    view_point_metrics_print(out, blocks, labels, nb);
}
