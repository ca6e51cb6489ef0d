/* The table of job kinds: what each is, how its spec is decoded, how it runs and where its
 * result keeps the best pattern. The order is the one GET /v1/kinds and error messages list. */
#include <string.h>

#include "kinds.h"

static const job_kind table[] = {
    {.name = "optimize",
     .summary = "Multi-start optimisation of a sample pattern (a family, or a given pattern) "
                "for the smallest worst-case error E2.",
     .decode = kind_optimize_decode,
     .free_params = kind_optimize_free,
     .spec_family = kind_optimize_family,
     .max_seconds = kind_optimize_max_seconds,
     .run = kind_optimize_run,
     .encode_result = kind_optimize_encode_result,
     .free_result = kind_optimize_free_result,
     .best_of = kind_optimize_best_of,
     .split = &kind_optimize_split},
    {.name = "family-sweep",
     .summary = "Optimises every mirrored P(4,1+,n) placement configuration of one cost and "
                "ranks them by E2.",
     .decode = kind_family_sweep_decode,
     .free_params = kind_family_sweep_free,
     .spec_family = kind_family_sweep_family,
     .max_seconds = kind_family_sweep_max_seconds,
     .run = kind_family_sweep_run,
     .encode_result = kind_family_sweep_encode_result,
     .free_result = kind_family_sweep_free_result,
     .best_of = kind_family_sweep_best_of,
     .split = &kind_family_sweep_split},
    {.name = "random-stats",
     .summary = "Min, average and max E2 of random patterns of a family, and the best of them "
                "optimised for weights (Opt W) and for weights and positions (Opt W+P).",
     .decode = kind_random_stats_decode,
     .free_params = kind_random_stats_free,
     .spec_family = kind_random_stats_family,
     .max_seconds = kind_random_stats_max_seconds,
     .run = kind_random_stats_run,
     .encode_result = kind_random_stats_encode_result,
     .free_result = kind_random_stats_free_result,
     .best_of = kind_random_stats_best_of,
     .split = &kind_random_stats_split},
    {.name = "table3",
     .summary = "Laine & Aila's Table 3 over K rng_seeds: per distribution, Min, Avg and Max E2 "
                "of random patterns, exact Opt W and Opt W+P of the best, as mean +- sd beside "
                "the paper's values.",
     .decode = kind_table3_decode,
     .free_params = kind_table3_free,
     .spec_family = kind_table3_family,
     .max_seconds = kind_table3_max_seconds,
     .run = kind_table3_run,
     .encode_result = kind_table3_encode_result,
     .free_result = kind_table3_free_result,
     .best_of = kind_table3_best_of,
     .split = &kind_table3_split},
    {.name = "temporal-optimize",
     .summary = "Multi-start optimisation of a TAA jitter sequence (a family T(N), or a given "
                "temporal pattern) for the smallest worst-phase E2, optionally plus lambda F2.",
     .decode = kind_temporal_optimize_decode,
     .free_params = kind_temporal_optimize_free,
     .spec_family = kind_temporal_optimize_family,
     .max_seconds = kind_temporal_optimize_max_seconds,
     .run = kind_temporal_optimize_run,
     .encode_result = kind_temporal_optimize_encode_result,
     .free_result = kind_temporal_optimize_free_result,
     .best_of = kind_temporal_optimize_best_of},
    {.name = "compare",
     .summary = "Renders one scene with several patterns and tabulates samples per pixel, E2, "
                "RMSE and max deviation against a supersampled reference.",
     .decode = kind_compare_decode,
     .free_params = kind_compare_free,
     .run = kind_compare_run,
     .encode_result = kind_compare_encode_result,
     .free_result = kind_compare_free_result},
    {.name = "animation",
     .summary = "Renders a moving scene frame by frame with a pattern beside the reference and "
                "reports the error of each frame and of the whole animation.",
     .decode = kind_animation_decode,
     .free_params = kind_animation_free,
     .run = kind_animation_run,
     .encode_result = kind_animation_encode_result,
     .free_result = kind_animation_free_result},
    {.name = "reference-convergence",
     .summary = "Measures how the reference render's error falls with its samples per pixel, "
                "against a high-sample baseline.",
     .decode = kind_reference_convergence_decode,
     .free_params = kind_reference_convergence_free,
     .run = kind_reference_convergence_run,
     .encode_result = kind_reference_convergence_encode_result,
     .free_result = kind_reference_convergence_free_result},
    {.name = "temporal-render",
     .summary = "Renders a still scene through the TAA loop of a temporal pattern and reports "
                "the steady-state RMSE per phase, the RMSE per frame after a cut and the flicker, "
                "with the edge model's prediction per phase.",
     .decode = kind_temporal_render_decode,
     .free_params = kind_temporal_render_free,
     .run = kind_temporal_render_run,
     .encode_result = kind_temporal_render_encode_result,
     .free_result = kind_temporal_render_free_result},
    {.name = "sleep",
     .summary = "Test kind: waits a given time, reporting progress, and returns an optional "
                "pattern.",
     .test_only = true,
     .decode = kind_sleep_decode,
     .free_params = kind_sleep_free,
     .run = kind_sleep_run,
     .encode_result = kind_sleep_encode_result,
     .free_result = kind_sleep_free_result,
     .best_of = kind_sleep_best_of,
     .split = &kind_sleep_split},
};

#define KIND_COUNT (sizeof table / sizeof table[0])

const job_kind *job_kinds_table(size_t *count)
{
    *count = KIND_COUNT;
    return table;
}

const job_kind *job_kind_find(const char *name)
{
    /* NULL: a stored row or a spec without a kind string is no kind, not a crash. */
    for (size_t i = 0; name && i < KIND_COUNT; i++)
        if (!strcmp(table[i].name, name))
            return &table[i];
    return NULL;
}
