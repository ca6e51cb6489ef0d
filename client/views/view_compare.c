/* compare: one scene rendered with several patterns against one reference; a row per pattern
 * with its E2 and its image error (RMSE and largest deviation, 8-bit levels). */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"

void view_compare(FILE *out, const json_t *result, bool csv)
{
    if (!csv) {
        const json_t *ref = json_object_get(result, "reference");
        char scene[128];
        view_kv kv = {0};
        view_kv_add(&kv, "scene", "%s",
                    view_scene_label(scene, sizeof scene, json_object_get(result, "scene")));
        view_kv_number(&kv, "reference spp", json_object_get(ref, "spp"), 0);
        view_kv_number(&kv, "reference seed", json_object_get(ref, "seed"), 0);
        view_kv_add(&kv, "reference filter", "%s", view_str(json_object_get(ref, "filter")));
        view_kv_print(out, &kv);
        fputc('\n', out);
    }
    const char *headers[] = {"name",    "family",         "spp",           "e2", "rmse",
                             "max_dev", "render_seconds", "pixels_sampled"};
    table *t = table_new(8, headers);
    if (!t)
        return;
    size_t i;
    json_t *row;
    json_array_foreach(json_object_get(result, "rows"), i, row)
    {
        char spp[32], e2[32], rmse[32], dev[32], sec[32], px[32];
        const char *cells[] = {
            fmt_string(json_object_get(row, "name")),
            fmt_string(json_object_get(row, "family")),
            fmt_number(spp, sizeof spp, json_object_get(row, "samples_per_pixel"),
                       fmt_decimals(csv, 2)),
            fmt_number(e2, sizeof e2, json_object_get(row, "e2"), fmt_decimals(csv, 6)),
            fmt_number(rmse, sizeof rmse, json_object_get(row, "rmse"), fmt_decimals(csv, 4)),
            fmt_number(dev, sizeof dev, json_object_get(row, "max_dev"), fmt_decimals(csv, 2)),
            fmt_number(sec, sizeof sec, json_object_get(row, "render_seconds"),
                       fmt_decimals(csv, 4)),
            fmt_number(px, sizeof px, json_object_get(row, "pixels_sampled"), 0)};
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
}
