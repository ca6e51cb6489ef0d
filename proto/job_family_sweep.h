/* Spec of the "family-sweep" job kind: every mirrored P(4,1+,n) placement configuration of one
 * cost, optimised from K seeds each. {"family":"P(4,1+,1.25)" | "cost":1.25,
 * "seeds_per_config":K?, "distributions":[...]?, and the shared optimizer fields}. */
#ifndef AALAB_PROTO_JOB_FAMILY_SWEEP_H
#define AALAB_PROTO_JOB_FAMILY_SWEEP_H

#include "job_optimizer_spec.h"

typedef struct proto_family_sweep_spec {
    proto_optimizer_spec common; /* max_seconds default 60, split evenly over configurations */
    double cost;
    char family[48];   /* "" when the spec gave a cost */
    size_t per_config; /* default 8 */
    aa_seed_kind kinds[PROTO_MAX_DISTRIBUTIONS];
    size_t kind_count;
} proto_family_sweep_spec;

int proto_decode_family_sweep_spec(const json_t *spec, proto_family_sweep_spec *out, aa_error *err);
void proto_family_sweep_spec_free(proto_family_sweep_spec *s);

#endif
