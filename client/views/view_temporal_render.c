/* temporal-render: a still scene through the TAA loop; a row per phase with the edge model's
 * prediction beside the rendered RMSE, the RMSE after a cut, the flicker and the images. */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"
#include "view_rows.h"
#include "view_temporal.h"

/* "6.6405 (predicted 6.1994, ratio 0.934)" */
static void kv_predicted(view_kv *kv, const char *key, const json_t *v, const json_t *pred,
                         const json_t *ratio)
{
    char a[32], b[32], c[32];
    view_kv_add(kv, key, "%s (predicted %s, ratio %s)", fmt_number(a, sizeof a, v, 4),
                fmt_number(b, sizeof b, pred, 4), fmt_number(c, sizeof c, ratio, 3));
}

void view_temporal_render(FILE *out, const json_t *result, bool csv)
{
    static const view_column cols[] = {
        {"phase", "phase", VIEW_FIXED, 0},
        {"e2", "e2", VIEW_MEASURE, 6},
        {"rmse", "rmse", VIEW_MEASURE, 4},
        {"max_dev", "max_dev", VIEW_MEASURE, 2},
        {"predicted_rmse", "predicted_rmse", VIEW_MEASURE, 4},
        {"ratio", "ratio", VIEW_MEASURE, 4},
    };
    const json_t *phases = json_object_get(result, "phases");
    if (csv) {
        view_rows_write(out, phases, cols, sizeof cols / sizeof cols[0], true);
        return;
    }
    const json_t *pattern = json_object_get(result, "pattern");
    const json_t *ref = json_object_get(result, "reference");
    const json_t *steady = json_object_get(result, "steady");
    const json_t *flicker = json_object_get(result, "flicker");
    const json_t *times = json_object_get(result, "times");
    const json_t *pixels = json_object_get(result, "pixels");
    const json_t *preset = json_object_get(pattern, "preset");
    char blend[96], spp[32], off[32];
    view_kv kv = {0};
    view_kv_scene(&kv, json_object_get(result, "scene"));
    view_kv_add(&kv, "pattern", "%s%s%s, %s spp a frame, blend %s",
                view_str(json_object_get(pattern, "family")), preset ? " " : "",
                preset ? view_str(preset) : "",
                fmt_number(spp, sizeof spp, json_object_get(pattern, "samples_per_pixel"), 2),
                view_blend_text(blend, sizeof blend, json_object_get(pattern, "blend")));
    view_kv_add(&kv, "reference", "%lld spp, %s filter, output offset %s",
                (long long)json_integer_value(json_object_get(ref, "spp")),
                view_str(json_object_get(ref, "filter")),
                fmt_number(off, sizeof off, json_object_get(ref, "output_offset"), 2));
    view_kv_number(&kv, "E2 (worst phase)", json_object_get(result, "e2"), 6);
    view_kv_number(&kv, "mean phase E2", json_object_get(result, "mean_phase_e2"), 6);
    view_kv_number(&kv, "F2", json_object_get(result, "f2"), 6);
    view_kv_acuity(&kv, result);
    view_kv_number(&kv, "worst phase", json_object_get(steady, "worst_phase"), 0);
    view_kv_number(&kv, "steady rmse", json_object_get(steady, "rmse"), 4);
    kv_predicted(&kv, "steady mean rmse", json_object_get(steady, "mean_rmse"),
                 json_object_get(steady, "predicted_rmse"), json_object_get(steady, "ratio"));
    if (json_is_null(json_object_get(result, "frames_to_5pct")))
        view_kv_add(&kv, "frames to 5%", "not within the after-cut curve");
    else
        view_kv_number(&kv, "frames to 5%", json_object_get(result, "frames_to_5pct"), 0);
    kv_predicted(&kv, "flicker step rmse", json_object_get(flicker, "step_rmse"),
                 json_object_get(flicker, "predicted_step_rmse"),
                 json_object_get(flicker, "step_ratio"));
    kv_predicted(&kv, "flicker mean rmse", json_object_get(flicker, "mean_rmse"),
                 json_object_get(flicker, "predicted_mean_rmse"),
                 json_object_get(flicker, "ratio"));
    char t1[32], t2[32], t3[32];
    view_kv_add(&kv, "seconds", "reference %s, taa %s, predict %s",
                fmt_number(t1, sizeof t1, json_object_get(times, "reference_seconds"), 4),
                fmt_number(t2, sizeof t2, json_object_get(times, "taa_seconds"), 4),
                fmt_number(t3, sizeof t3, json_object_get(times, "predict_seconds"), 4));
    view_kv_add(&kv, "pixels sampled", "%s, %s samples evaluated",
                fmt_number(t1, sizeof t1, json_object_get(pixels, "sampled"), 0),
                fmt_number(t2, sizeof t2, json_object_get(pixels, "samples_evaluated"), 0));
    view_kv_print(out, &kv);
    fputc('\n', out);
    /* At most 8 phase rows (issue 34: the view fits 60 lines): every s-th phase of a longer
     * sequence, the worst one among them; --csv has them all. */
    size_t n = json_array_size(phases), stride = (n + 7) / 8;
    if (stride <= 1) {
        view_rows_write(out, phases, cols, sizeof cols / sizeof cols[0], false);
    } else {
        size_t worst = (size_t)json_integer_value(json_object_get(steady, "worst_phase"));
        json_t *some = json_array();
        for (size_t i = 0; i < n; i++)
            if (i % stride == 0 || i == worst)
                json_array_append(some, json_array_get(phases, i));
        fprintf(out, "one phase every %zu of %zu and the worst ('--csv' lists all)\n", stride, n);
        view_rows_write(out, some, cols, sizeof cols / sizeof cols[0], false);
        json_decref(some);
    }
    fputc('\n', out);
    view_number_lines(out, "rmse k frames after a cut", json_object_get(result, "after_cut"), 1, 2);
    const json_t *tiles = json_object_get(result, "tiles");
    if (json_is_object(tiles)) {
        char label[48];
        snprintf(label, sizeof label, "worst phase %lld",
                 (long long)json_integer_value(json_object_get(steady, "worst_phase")));
        view_images_heading(out);
        view_images_line(out, label, tiles);
    }
}
