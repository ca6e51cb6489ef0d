/* animation: one pattern over the frames of a moving scene; a row per frame with its image
 * error and how many pixels had to be recomputed. */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"
#include "view_rows.h"

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
        view_kv_acuity(&kv, result);
        view_kv_number(&kv, "total rmse", json_object_get(total, "rmse"), 4);
        view_kv_number(&kv, "total max_dev", json_object_get(total, "max_dev"), 2);
        view_kv_number(&kv, "pattern seconds", json_object_get(times, "pattern_seconds"), 4);
        view_kv_number(&kv, "reference seconds", json_object_get(times, "reference_seconds"), 4);
        view_kv_number(&kv, "pixels recomputed", json_object_get(pixels, "recomputed"), 0);
        view_kv_number(&kv, "pixels all frames", json_object_get(pixels, "all_frames"), 0);
        view_kv_print(out, &kv);
        fputc('\n', out);
    }
    static const view_column cols[] = {
        {"frame", "frame", VIEW_FIXED, 0},
        {"rmse", "rmse", VIEW_MEASURE, 4},
        {"max_dev", "max_dev", VIEW_MEASURE, 2},
        {"pixels_recomputed", "pixels_recomputed", VIEW_FIXED, 0},
        {"pattern_sampled", "pattern_sampled", VIEW_FIXED, 0},
        {"reference_supersampled", "reference_supersampled", VIEW_FIXED, 0},
        {"pattern_seconds", "pattern_seconds", VIEW_MEASURE, 6},
        {"reference_seconds", "reference_seconds", VIEW_MEASURE, 6},
    };
    view_rows_write(out, json_object_get(result, "frames"), cols, sizeof cols / sizeof cols[0],
                    csv);
    if (csv)
        return;
    /* Each frame's renders: the pattern's, the reference and their difference. */
    const json_t *frames = json_object_get(result, "frames"), *f;
    size_t i;
    bool heading = false;
    json_array_foreach(frames, i, f)
    {
        if (!json_object_get(f, "tiles"))
            continue;
        if (!heading)
            view_images_heading(out);
        heading = true;
        char label[32];
        snprintf(label, sizeof label, "frame %lld",
                 (long long)json_integer_value(json_object_get(f, "frame")));
        view_images_line(out, label, json_object_get(f, "tiles"));
    }
}
