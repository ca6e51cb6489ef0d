/* compare: one scene rendered with several patterns against one reference; a row per pattern
 * with its E2 and its image error (RMSE and largest deviation, 8-bit levels), the edge model's
 * predicted RMSE beside it and their rank correlation. */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"
#include "view_rows.h"

void view_compare(FILE *out, const json_t *result, bool csv)
{
    if (!csv) {
        const json_t *ref = json_object_get(result, "reference");
        view_kv kv = {0};
        view_kv_scene(&kv, json_object_get(result, "scene"));
        view_kv_number(&kv, "reference spp", json_object_get(ref, "spp"), 0);
        view_kv_number(&kv, "reference seed", json_object_get(ref, "seed"), 0);
        view_kv_add(&kv, "reference filter", "%s", view_str(json_object_get(ref, "filter")));
        const json_t *pred = json_object_get(result, "prediction");
        if (pred)
            view_kv_number(&kv, "prediction rho", json_object_get(pred, "spearman"), 3);
        view_kv_acuity(&kv, result);
        view_kv_print(out, &kv);
        fputc('\n', out);
    }
    static const view_column cols[] = {
        {"name", "name", VIEW_STRING, 0},
        {"family", "family", VIEW_STRING, 0},
        {"spp", "samples_per_pixel", VIEW_MEASURE, 2},
        {"e2", "e2", VIEW_MEASURE, 6},
        {"rmse", "rmse", VIEW_MEASURE, 4},
        {"predicted", "predicted_rmse", VIEW_MEASURE, 4},
        {"max_dev", "max_dev", VIEW_MEASURE, 2},
        {"render_seconds", "render_seconds", VIEW_MEASURE, 4},
        {"pixels_sampled", "pixels_sampled", VIEW_FIXED, 0},
    };
    view_rows_write(out, json_object_get(result, "rows"), cols, sizeof cols / sizeof cols[0], csv);
    if (csv)
        return;
    /* The renders themselves: the reference, then each pattern's and its difference. */
    const json_t *rows = json_object_get(result, "rows"), *row;
    const json_t *ref =
        json_array_get(json_object_get(json_object_get(result, "reference"), "renders"), 0);
    size_t i;
    bool any = json_object_get(ref, "tile") != NULL;
    json_array_foreach(rows, i, row) any = any || json_object_get(row, "tiles");
    if (!any)
        return;
    view_images_heading(out);
    if (json_object_get(ref, "tile")) {
        json_t *t = json_pack("{s:O}", "reference", json_object_get(ref, "tile"));
        view_images_line(out, "reference", t);
        json_decref(t);
    }
    json_array_foreach(rows, i, row)
    {
        if (json_object_get(row, "tiles"))
            view_images_line(out, view_str(json_object_get(row, "name")),
                             json_object_get(row, "tiles"));
    }
}
