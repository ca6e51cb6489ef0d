/* Spec and result of the "temporal-optimize" job kind (docs/temporal.md section 7): the N offsets
 * of a TAA jitter sequence optimised for the worst-phase E2 (optionally + lambda F2), the weights
 * fixed by the blend.
 * Spec: {"family": "T(N)" with "blend"?, "resolve"?, "frame_pattern"?, "jitter_range"? (the
 * temporal pattern's keys) | "pattern": {"temporal": {...}} (the first seed is its sequence),
 * "seeds"?, "flicker_weight"?, "flicker_cap"?, "grid"? {"bits"}, "order"? ("auto" | "none"),
 * "filter"?, "acuity"?, "angles"?, "max_seconds"?, "max_iterations"?, "rng_seed"?}. */
#ifndef AALAB_PROTO_JOB_TEMPORAL_OPTIMIZE_H
#define AALAB_PROTO_JOB_TEMPORAL_OPTIMIZE_H

#include <stdbool.h>
#include <stdint.h>

#include <jansson.h>

#include "aa_metric.h"
#include "codec_temporal.h"
#include "job_result_util.h"

#define PROTO_TEMPORAL_OPT_MAX_PHASES 256

typedef struct proto_temporal_optimize_spec {
    bool have_family;        /* else a given sequence */
    char family[16];         /* "T(N)" */
    proto_temporal temporal; /* the setting; its jitter is the given sequence (or N zeros) */
    long seeds;              /* starts: default 16 */
    double flicker_weight, flicker_cap;
    int grid_bits; /* 0: none; offsets on multiples of 2^-bits px */
    bool order_search;
    aa_filter filter;
    aa_acuity acuity;
    double *angles;
    size_t angle_count;
    double max_seconds;  /* 0: none (reproducible) */
    long max_iterations; /* descent steps per q level of a seed; 0: the engine's 60 */
    bool reproducible;
    uint64_t rng_seed;
} proto_temporal_optimize_spec;

int proto_decode_temporal_optimize_spec(const json_t *spec, proto_temporal_optimize_spec *out,
                                        aa_error *err);
void proto_temporal_optimize_spec_free(proto_temporal_optimize_spec *s);
aa_metric_params proto_temporal_optimize_metric(const proto_temporal_optimize_spec *s);

typedef struct proto_temporal_seed {
    long seed;
    int start; /* 0 given, 1 random, 2 hop */
    double initial_score, score, e2, f2;
} proto_temporal_seed;

typedef struct proto_temporal_optimize_result {
    char family[16];
    proto_temporal best;
    double e2, mean_phase_e2, f2, score; /* e2, mean, f2: POST /v1/evaluate's of best */
    double *phase_e2;                    /* [N] */
    long frames_to_settle;               /* -1: none */
    double flicker_weight, flicker_cap;
    int grid_bits;
    double start_e2; /* the given sequence's E2 (NaN for a family) */
    long seeds_run, evaluations;
    double seconds;
    proto_temporal_seed *per_seed;
    size_t per_seed_count;
    proto_run_info run;
} proto_temporal_optimize_result;

/* {"best": {"temporal": ...}, "e2", "mean_phase_e2", "phase_e2", "f2", "frames_to_settle",
 * "score", "objective", "family", "start_e2"?, "grid"?, "seeds_run", "evaluations", "seconds",
 * "per_seed": [...], run info}; NULL when out of memory. */
json_t *proto_encode_temporal_optimize_result(const proto_temporal_optimize_result *r);
/* What the job list needs back: the best pattern (decoded) and its E2. */
int proto_decode_temporal_optimize_result(const json_t *j, proto_temporal *best, double *e2,
                                          aa_error *err);
void proto_temporal_optimize_result_free(proto_temporal_optimize_result *r);

#endif
