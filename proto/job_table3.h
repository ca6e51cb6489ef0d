/* The "table3" job kind: Laine & Aila's Table 3 protocol over K rng_seeds (aa_table3_cell_run per
 * seed and distribution), reported as mean +- sd of each column beside the paper's value.
 * Spec: {"family":"P(16,16,4)"?, "seeds":K? (8; rng_seed, rng_seed+1, ...), "count":N? (1000),
 * "distributions":[...]? (poisson, jittered), "poisson_radius":px?, "metrics":[names]?
 * (job_point_metrics.h: at most 10,000 patterns over seeds and distributions), and the shared
 * optimizer fields filter, acuity, angles, rng_seed, method (Opt W+P's rule), max_seconds (Opt
 * W+P's budget per seed and distribution, default 60), max_iterations (Opt W+P's steps:
 * clock-free)}. */
#ifndef AALAB_PROTO_JOB_TABLE3_H
#define AALAB_PROTO_JOB_TABLE3_H

#include "job_optimizer_spec.h"
#include "job_point_metrics.h"
#include "job_result_util.h"
#include "aa_pattern.h"

#define PROTO_TABLE3_MAX_SEEDS 64

typedef struct proto_table3_spec {
    proto_optimizer_spec common;
    aa_family family;
    size_t seeds; /* K */
    size_t count;
    aa_seed_distribution distributions[PROTO_MAX_DISTRIBUTIONS];
    size_t distribution_count;
    double poisson_radius; /* px; the default radius for the family's density when not given */
    proto_point_metrics_spec metrics; /* point-set figures per random pattern; count 0: none */
} proto_table3_spec;

int proto_decode_table3_spec(const json_t *spec, proto_table3_spec *out, aa_error *err);
void proto_table3_spec_free(proto_table3_spec *s);
/* The spec's time budget: every cell's Opt W+P budget plus Opt W's cap. */
double proto_table3_spec_seconds(const proto_table3_spec *s);

enum { PROTO_T3_MIN, PROTO_T3_AVG, PROTO_T3_MAX, PROTO_T3_OPT_W, PROTO_T3_OPT_WP, PROTO_T3_COLS };
/* Wire names of the columns: min, avg, max, opt_w, opt_wp. */
extern const char *const proto_table3_columns[PROTO_T3_COLS];

typedef struct proto_table3_row {
    aa_seed_distribution distribution;
    double radius; /* the Poisson radius in px; NaN for other distributions */
    double mean[PROTO_T3_COLS], sd[PROTO_T3_COLS];
    double paper[PROTO_T3_COLS]; /* NaN: the paper has no value (not P(16,16,4), or the row) */
    double values[PROTO_T3_COLS][PROTO_TABLE3_MAX_SEEDS]; /* per seed, in seed order */
    /* The random patterns of every seed (seed order, then pattern order) with their figures and
     * rho with E2, when the spec asked for "metrics" (spec.count 0: not). */
    proto_point_metrics point_metrics;
} proto_table3_row;

typedef struct proto_table3_result {
    char family[48];
    long count;
    size_t seed_count;
    uint64_t seeds[PROTO_TABLE3_MAX_SEEDS];
    proto_table3_row rows[PROTO_MAX_DISTRIBUTIONS];
    size_t row_count;
    aa_pattern best; /* the lowest Opt W+P of all seeds and distributions */
    double e2;
    proto_run_info run;
} proto_table3_result;

/* {"family","count","seeds":[..],"rows":[{"distribution","generator":{"name","radius"?},
 * "columns":{"min":{"mean","sd","paper"},...},"per_seed":[{"rng_seed","min",...,"opt_wp"}],"point_metrics"?}],
 * "best","e2", run info}. NULL when out of memory. */
json_t *proto_encode_table3_result(const proto_table3_result *r);
int proto_decode_table3_result(const json_t *j, proto_table3_result *out, aa_error *err);
void proto_table3_result_free(proto_table3_result *r);

#endif
