/* Spec of the "optimize" job kind: multi-start descent for a family or from a given pattern.
 * {"family":"P(4,1+,2)" | "pattern":P, "seeds":N?, "distributions":[...]?, and the shared
 * optimizer fields (job_optimizer_spec.h)}. */
#ifndef AALAB_PROTO_JOB_OPTIMIZE_H
#define AALAB_PROTO_JOB_OPTIMIZE_H

#include "job_optimizer_spec.h"
#include "job_result_util.h"
#include "job_scene_objective.h"
#include "aa_pattern.h"

typedef struct proto_optimize_spec {
    proto_optimizer_spec common; /* max_seconds default 30 */
    bool have_family;            /* else pattern */
    aa_family family;
    aa_pattern pattern;
    size_t seeds; /* default 64 for a family, 1 (the only value) for a pattern */
    aa_seed_distribution distributions[PROTO_MAX_DISTRIBUTIONS];
    size_t distribution_count;       /* 0: every distribution in turn */
    proto_scene_objective objective; /* "objective": optimise for a scene (job_scene_objective.h) */
} proto_optimize_spec;

int proto_decode_optimize_spec(const json_t *spec, proto_optimize_spec *out, aa_error *err);
void proto_optimize_spec_free(proto_optimize_spec *s);

/* Result of an "optimize" job. */
typedef struct proto_seed_summary {
    size_t seed;
    aa_seed_distribution distribution;
    double initial_e2, e2;
    long iterations;
} proto_seed_summary;

typedef struct proto_optimize_result {
    aa_pattern best; /* its family is the result's "family" */
    double e2;
    int argmax_kernel;
    double argmax_angle_deg;
    long seeds_run, iterations, evaluations;
    double seconds;
    aa_optimize_method method;
    proto_seed_summary *per_seed; /* seeds that ran */
    size_t per_seed_count;
    bool have_grid; /* the spec asked for a grid */
    int grid_bits;
    bool d3d12;
    double e2_before_snap;              /* quantisation_cost = e2 - e2_before_snap */
    proto_scene_objective_result scene; /* scene.spec.enabled: the spec had an objective */
    proto_run_info run;
} proto_optimize_result;

/* {"best","e2","argmax":{"kernel","angle_deg"},"seeds_run","iterations","evaluations",
 * "seconds","family","method","per_seed":[{"seed","distribution","initial_e2","e2",
 * "iterations"}],"grid"?:{...},"scene_objective"?:{"bits","d3d12","e2_before_snap","quantisation_cost"},"executor",
 * "shards","reproducible"}; NULL when out of memory. */
json_t *proto_encode_optimize_result(const proto_optimize_result *r);
int proto_decode_optimize_result(const json_t *j, proto_optimize_result *out, aa_error *err);
void proto_optimize_result_free(proto_optimize_result *r);
#endif
