/* optimize: E2 and how it was reached, then one row per starting pattern (per_seed). */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"
#include "view_rows.h"

static void per_seed_table(FILE *out, const json_t *per_seed, bool csv)
{
    static const view_column cols[] = {
        {"seed", "seed", VIEW_FIXED, 0},
        {"distribution", "distribution", VIEW_STRING, 0},
        {"initial_e2", "initial_e2", VIEW_MEASURE, 6},
        {"e2", "e2", VIEW_MEASURE, 6},
        {"iterations", "iterations", VIEW_FIXED, 0},
    };
    view_rows_write(out, per_seed, cols, sizeof cols / sizeof cols[0], csv);
}

void view_optimize(FILE *out, const json_t *result, bool csv)
{
    const json_t *per_seed = json_object_get(result, "per_seed");
    if (csv) {
        per_seed_table(out, per_seed, true);
        return;
    }
    view_kv kv = {0};
    const json_t *argmax = json_object_get(result, "argmax");
    const json_t *grid = json_object_get(result, "grid");
    view_kv_add(&kv, "family", "%s", view_str(json_object_get(result, "family")));
    view_kv_number(&kv, "E2", json_object_get(result, "e2"), 6);
    view_kv_number(&kv, "argmax kernel", json_object_get(argmax, "kernel"), 0);
    view_kv_number(&kv, "argmax angle_deg", json_object_get(argmax, "angle_deg"), 1);
    view_kv_add(&kv, "method", "%s", view_str(json_object_get(result, "method")));
    view_kv_number(&kv, "seeds_run", json_object_get(result, "seeds_run"), 0);
    view_kv_number(&kv, "iterations", json_object_get(result, "iterations"), 0);
    view_kv_number(&kv, "evaluations", json_object_get(result, "evaluations"), 0);
    view_kv_number(&kv, "seconds", json_object_get(result, "seconds"), 3);
    view_kv_execution(&kv, result);
    if (json_is_object(grid)) {
        view_kv_number(&kv, "grid bits", json_object_get(grid, "bits"), 0);
        view_kv_add(&kv, "grid d3d12", "%s",
                    json_is_true(json_object_get(grid, "d3d12")) ? "true" : "false");
        view_kv_number(&kv, "E2 before snap", json_object_get(grid, "e2_before_snap"), 6);
        view_kv_number(&kv, "quantisation cost", json_object_get(grid, "quantisation_cost"), 6);
    }
    const json_t *so = json_object_get(result, "scene_objective");
    if (json_is_object(so)) {
        /* Both figures of the scene-optimised pattern beside the global-E2 optimum's. */
        const json_t *opt = json_object_get(so, "e2_optimum");
        view_kv_add(&kv, "scene", "%s",
                    view_str(json_object_get(json_object_get(so, "scene"), "name")));
        view_kv_number(&kv, "blend", json_object_get(so, "blend"), 3);
        view_kv_number(&kv, "objective", json_object_get(so, "objective"), 6);
        view_kv_number(&kv, "predicted RMSE", json_object_get(so, "predicted_rmse"), 4);
        view_kv_number(&kv, "E2-optimum E2", json_object_get(opt, "e2"), 6);
        view_kv_number(&kv, "E2-optimum predicted RMSE", json_object_get(opt, "predicted_rmse"), 4);
    }
    view_kv_print(out, &kv);
    if (json_array_size(per_seed) > 0) {
        fputs("\nper seed\n", out);
        per_seed_table(out, per_seed, false);
    }
}
