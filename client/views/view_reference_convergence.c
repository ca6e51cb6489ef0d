/* reference-convergence: how far the reference at each supersampling level is from the
 * baseline render, and what each level costs. */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"

void view_reference_convergence(FILE *out, const json_t *result, bool csv)
{
    if (!csv) {
        const json_t *base = json_object_get(result, "baseline");
        char scene[128];
        view_kv kv = {0};
        view_kv_add(&kv, "scene", "%s",
                    view_scene_label(scene, sizeof scene, json_object_get(result, "scene")));
        view_kv_number(&kv, "output_offset", json_object_get(result, "output_offset"), 2);
        view_kv_number(&kv, "baseline spp", json_object_get(base, "spp"), 0);
        view_kv_number(&kv, "baseline seconds", json_object_get(base, "seconds"), 4);
        view_kv_number(&kv, "baseline samples", json_object_get(base, "samples"), 0);
        view_kv_print(out, &kv);
        fputc('\n', out);
    }
    const char *headers[] = {"spp", "rmse", "max_dev", "seconds", "supersampled", "samples"};
    table *t = table_new(6, headers);
    if (!t)
        return;
    size_t i;
    json_t *row;
    json_array_foreach(json_object_get(result, "rows"), i, row)
    {
        char spp[32], rmse[32], dev[32], sec[32], sup[32], n[32];
        const char *cells[] = {
            fmt_number(spp, sizeof spp, json_object_get(row, "spp"), 0),
            fmt_number(rmse, sizeof rmse, json_object_get(row, "rmse"), fmt_decimals(csv, 4)),
            fmt_number(dev, sizeof dev, json_object_get(row, "max_dev"), fmt_decimals(csv, 2)),
            fmt_number(sec, sizeof sec, json_object_get(row, "seconds"), fmt_decimals(csv, 4)),
            fmt_number(sup, sizeof sup, json_object_get(row, "supersampled"), 0),
            fmt_number(n, sizeof n, json_object_get(row, "samples"), 0)};
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
}
