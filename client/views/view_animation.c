/* animation: one pattern over the frames of a moving scene; a row per frame with its image
 * error and how many pixels had to be recomputed. */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"

void view_animation(FILE *out, const json_t *result, bool csv)
{
    if (!csv) {
        const json_t *pattern = json_object_get(result, "pattern");
        const json_t *total = json_object_get(result, "total");
        const json_t *times = json_object_get(result, "times");
        const json_t *pixels = json_object_get(result, "pixels");
        char spp[32];
        view_kv kv = {0};
        view_kv_scene(&kv, json_object_get(result, "scene"));
        view_kv_add(&kv, "pattern", "%s, %s spp", view_str(json_object_get(pattern, "family")),
                    fmt_number(spp, sizeof spp, json_object_get(pattern, "samples_per_pixel"),
                               fmt_decimals(csv, 2)));
        view_kv_number(&kv, "E2", json_object_get(result, "e2"), 6);
        view_kv_number(&kv, "total rmse", json_object_get(total, "rmse"), 4);
        view_kv_number(&kv, "total max_dev", json_object_get(total, "max_dev"), 2);
        view_kv_number(&kv, "pattern seconds", json_object_get(times, "pattern_seconds"), 4);
        view_kv_number(&kv, "reference seconds", json_object_get(times, "reference_seconds"), 4);
        view_kv_number(&kv, "pixels recomputed", json_object_get(pixels, "recomputed"), 0);
        view_kv_number(&kv, "pixels all frames", json_object_get(pixels, "all_frames"), 0);
        view_kv_print(out, &kv);
        fputc('\n', out);
    }
    const char *headers[] = {"frame",           "rmse",
                             "max_dev",         "pixels_recomputed",
                             "pattern_sampled", "reference_supersampled",
                             "pattern_seconds", "reference_seconds"};
    table *t = table_new(8, headers);
    if (!t)
        return;
    size_t i;
    json_t *f;
    json_array_foreach(json_object_get(result, "frames"), i, f)
    {
        char frame[32], rmse[32], dev[32], rec[32], ps[32], rs[32], psec[32], rsec[32];
        const char *cells[] = {
            fmt_number(frame, sizeof frame, json_object_get(f, "frame"), 0),
            fmt_number(rmse, sizeof rmse, json_object_get(f, "rmse"), fmt_decimals(csv, 4)),
            fmt_number(dev, sizeof dev, json_object_get(f, "max_dev"), fmt_decimals(csv, 2)),
            fmt_number(rec, sizeof rec, json_object_get(f, "pixels_recomputed"), 0),
            fmt_number(ps, sizeof ps, json_object_get(f, "pattern_sampled"), 0),
            fmt_number(rs, sizeof rs, json_object_get(f, "reference_supersampled"), 0),
            fmt_number(psec, sizeof psec, json_object_get(f, "pattern_seconds"),
                       fmt_decimals(csv, 6)),
            fmt_number(rsec, sizeof rsec, json_object_get(f, "reference_seconds"),
                       fmt_decimals(csv, 6))};
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
}
