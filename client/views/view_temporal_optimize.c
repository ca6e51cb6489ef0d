/* temporal-optimize: the best TAA jitter sequence's figures and how the search got there, then
 * one row per seed (the sequence itself is job_print's, compactly or with --pattern). */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"
#include "view_rows.h"
#include "view_temporal.h"

static void per_seed_table(FILE *out, const json_t *per_seed, bool csv)
{
    static const view_column cols[] = {
        {"seed", "seed", VIEW_FIXED, 0},
        {"start", "start", VIEW_STRING, 0},
        {"initial_score", "initial_score", VIEW_MEASURE, 6},
        {"score", "score", VIEW_MEASURE, 6},
        {"e2", "e2", VIEW_MEASURE, 6},
        {"f2", "f2", VIEW_MEASURE, 6},
    };
    view_rows_write(out, per_seed, cols, sizeof cols / sizeof cols[0], csv);
}

void view_temporal_optimize(FILE *out, const json_t *result, bool csv)
{
    const json_t *per_seed = json_object_get(result, "per_seed");
    if (csv) {
        per_seed_table(out, per_seed, true);
        return;
    }
    const json_t *temporal = json_object_get(json_object_get(result, "best"), "temporal");
    const json_t *grid = json_object_get(result, "grid");
    char blend[96];
    view_kv kv = {0};
    view_kv_add(&kv, "family", "%s", view_str(json_object_get(result, "family")));
    view_kv_add(&kv, "blend", "%s",
                view_blend_text(blend, sizeof blend, json_object_get(temporal, "blend")));
    view_kv_add(&kv, "objective", "%s", view_str(json_object_get(result, "objective")));
    view_kv_number(&kv, "E2 (worst phase)", json_object_get(result, "e2"), 6);
    view_kv_number(&kv, "mean phase E2", json_object_get(result, "mean_phase_e2"), 6);
    view_kv_number(&kv, "F2", json_object_get(result, "f2"), 6);
    view_kv_number(&kv, "score", json_object_get(result, "score"), 6);
    /* null: not within 5 % over the after-cut curve's 4N frames */
    if (json_is_null(json_object_get(result, "frames_to_settle")))
        view_kv_add(&kv, "frames to settle", "not within 4N frames");
    else
        view_kv_number(&kv, "frames to settle", json_object_get(result, "frames_to_settle"), 0);
    view_kv_number(&kv, "start E2", json_object_get(result, "start_e2"), 6);
    view_kv_number(&kv, "seeds_run", json_object_get(result, "seeds_run"), 0);
    view_kv_number(&kv, "evaluations", json_object_get(result, "evaluations"), 0);
    view_kv_number(&kv, "seconds", json_object_get(result, "seconds"), 3);
    view_kv_execution(&kv, result);
    if (json_is_object(grid)) {
        view_kv_number(&kv, "grid bits", json_object_get(grid, "bits"), 0);
        view_kv_number(&kv, "grid step", json_object_get(grid, "step"), 6);
    }
    view_kv_print(out, &kv);
    fputc('\n', out);
    view_number_lines(out, "E2 per phase", json_object_get(result, "phase_e2"), 0, 4);
    if (json_array_size(per_seed) > 0) {
        fputs("\nper seed\n", out);
        per_seed_table(out, per_seed, false);
    }
}
