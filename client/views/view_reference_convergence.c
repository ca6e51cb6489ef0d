/* reference-convergence: how far the reference at each supersampling level is from the
 * baseline render, and what each level costs. */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"
#include "view_rows.h"

void view_reference_convergence(FILE *out, const json_t *result, bool csv)
{
    if (!csv) {
        const json_t *base = json_object_get(result, "baseline");
        view_kv kv = {0};
        view_kv_scene(&kv, json_object_get(result, "scene"));
        view_kv_number(&kv, "output_offset", json_object_get(result, "output_offset"), 2);
        view_kv_number(&kv, "baseline spp", json_object_get(base, "spp"), 0);
        view_kv_number(&kv, "baseline seconds", json_object_get(base, "seconds"), 4);
        view_kv_number(&kv, "baseline samples", json_object_get(base, "samples"), 0);
        view_kv_print(out, &kv);
        fputc('\n', out);
    }
    static const view_column cols[] = {
        {"spp", "spp", VIEW_FIXED, 0},
        {"rmse", "rmse", VIEW_MEASURE, 4},
        {"max_dev", "max_dev", VIEW_MEASURE, 2},
        {"seconds", "seconds", VIEW_MEASURE, 4},
        {"supersampled", "supersampled", VIEW_FIXED, 0},
        {"samples", "samples", VIEW_FIXED, 0},
    };
    view_rows_write(out, json_object_get(result, "rows"), cols, sizeof cols / sizeof cols[0], csv);
}
