/* Spec of the "family-sweep" job kind: every mirrored P(4,1+,n) placement configuration of one
 * cost, optimised from K seeds each. {"family":"P(4,1+,1.25)" | "cost":1.25,
 * "seeds_per_config":K?, "distributions":[...]?, and the shared optimizer fields}. */
#ifndef AALAB_PROTO_JOB_FAMILY_SWEEP_H
#define AALAB_PROTO_JOB_FAMILY_SWEEP_H

#include "aa_pattern.h"
#include "job_optimizer_spec.h"
#include "job_result_util.h"

typedef struct proto_family_sweep_spec {
    proto_optimizer_spec common; /* max_seconds default 60, split evenly over configurations */
    double cost;
    char family[48];   /* "" when the spec gave a cost */
    size_t per_config; /* default 8 */
    aa_seed_distribution distributions[PROTO_MAX_DISTRIBUTIONS];
    size_t distribution_count;
} proto_family_sweep_spec;

int proto_decode_family_sweep_spec(const json_t *spec, proto_family_sweep_spec *out, aa_error *err);
void proto_family_sweep_spec_free(proto_family_sweep_spec *s);

/* Result of a "family-sweep" job: the configurations ranked by E2 (best first). */
typedef struct proto_sweep_row {
    long rank; /* 1-based */
    aa_mirrored_config config;
    double cost; /* samples per pixel of the configuration */
    double e2;   /* NaN: the configuration did not run */
    bool have_best;
    aa_pattern best;
} proto_sweep_row;

typedef struct proto_family_sweep_result {
    double cost;
    long configurations, seeds_per_config;
    proto_sweep_row *ranked;
    size_t ranked_count;
    proto_run_info run;
} proto_family_sweep_result;

/* {"cost","configurations","seeds_per_config","ranked":[{"rank","config":{"corners","edges",
 * "interior"},"cost","e2","best"}],"best"?,"e2"?,"executor","shards","reproducible"}: the first
 * row's pattern and E2 are also the result's "best" and "e2". NULL when out of memory. */
json_t *proto_encode_family_sweep_result(const proto_family_sweep_result *r);
int proto_decode_family_sweep_result(const json_t *j, proto_family_sweep_result *out,
                                     aa_error *err);
void proto_family_sweep_result_free(proto_family_sweep_result *r);

#endif
