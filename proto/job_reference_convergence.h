/* Spec and result of the "reference-convergence" job kind: RMSE and max deviation of the
 * reference at several sample counts against one at a high count (an independent seed).
 * Spec: {"scene", "size", "reference": {"seed", "filter"}, "levels": [16, 64, 256, 1024]
 * (1..8 square spp values), "baseline_spp": 4096 (a square), "kernel_size": 1 (selects the
 * output grid: 0.5 for odd, 1 for even)}. */
#ifndef AALAB_PROTO_JOB_REFERENCE_CONVERGENCE_H
#define AALAB_PROTO_JOB_REFERENCE_CONVERGENCE_H

#include "job_render_spec.h"

#define PROTO_CONVERGENCE_MAX_LEVELS 8

typedef struct proto_reference_convergence_spec {
    proto_render_spec common;
    int levels[PROTO_CONVERGENCE_MAX_LEVELS];
    size_t level_count;
    int baseline_spp;
    int kernel_size;
} proto_reference_convergence_spec;

int proto_decode_reference_convergence_spec(const json_t *spec,
                                            proto_reference_convergence_spec *out, aa_error *err);
void proto_reference_convergence_spec_free(proto_reference_convergence_spec *s);

/* One reference render: its spp, error against the baseline (not for the baseline itself),
 * wall time and work. */
typedef struct proto_convergence_level {
    long long spp;
    double rmse, max_dev, seconds;
    long long supersampled, samples;
} proto_convergence_level;

typedef struct proto_reference_convergence_result {
    aa_scene_params scene;
    double output_offset;
    proto_convergence_level baseline; /* rmse and max_dev unused */
    proto_convergence_level rows[PROTO_CONVERGENCE_MAX_LEVELS];
    size_t row_count;
} proto_reference_convergence_result;

/* {"scene", "output_offset", "baseline": {"spp", "seconds", "supersampled", "samples"},
 * "rows": [{"spp", "rmse", "max_dev", "seconds", "supersampled", "samples"}]}; NULL when out
 * of memory. */
json_t *proto_encode_reference_convergence_result(const proto_reference_convergence_result *r);
int proto_decode_reference_convergence_result(const json_t *j,
                                              proto_reference_convergence_result *out,
                                              aa_error *err);
void proto_reference_convergence_result_free(proto_reference_convergence_result *r);

#endif
