/* Spec of the "random-stats" job kind (L&A Table 3): {"family":"P(1,4,2)", "count":N?,
 * "distribution":"uniform"?, and the shared optimizer fields except mode and grid}. */
#ifndef AALAB_PROTO_JOB_RANDOM_STATS_H
#define AALAB_PROTO_JOB_RANDOM_STATS_H

#include "job_optimizer_spec.h"

typedef struct proto_random_stats_spec {
    proto_optimizer_spec common; /* max_seconds default 30: half for Opt W, half for Opt W+P */
    aa_family family;
    size_t count;      /* default 1000 */
    aa_seed_kind kind; /* default uniform */
} proto_random_stats_spec;

int proto_decode_random_stats_spec(const json_t *spec, proto_random_stats_spec *out, aa_error *err);
void proto_random_stats_spec_free(proto_random_stats_spec *s);

#endif
