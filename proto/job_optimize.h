/* Spec of the "optimize" job kind: multi-start descent for a family or from a given pattern.
 * {"family":"P(4,1+,2)" | "pattern":P, "seeds":N?, "distributions":[...]?, and the shared
 * optimizer fields (job_optimizer_spec.h)}. */
#ifndef AALAB_PROTO_JOB_OPTIMIZE_H
#define AALAB_PROTO_JOB_OPTIMIZE_H

#include "job_optimizer_spec.h"
#include "pattern.h"

typedef struct proto_optimize_spec {
    proto_optimizer_spec common; /* max_seconds default 30 */
    bool have_family;            /* else pattern */
    aa_family family;
    aa_pattern pattern;
    size_t seeds; /* default 64 for a family, 1 (the only value) for a pattern */
    aa_seed_kind kinds[PROTO_MAX_DISTRIBUTIONS];
    size_t kind_count; /* 0: every distribution in turn */
} proto_optimize_spec;

int proto_decode_optimize_spec(const json_t *spec, proto_optimize_spec *out, aa_error *err);
void proto_optimize_spec_free(proto_optimize_spec *s);

#endif
