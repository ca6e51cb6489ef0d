/* Spec of the "random-stats" job kind (L&A Table 3): {"family":"P(1,4,2)", "count":N?,
 * "distribution":"uniform"?, "metrics":[names]? (job_point_metrics.h), and the shared optimizer
 * fields except mode and grid}. */
#ifndef AALAB_PROTO_JOB_RANDOM_STATS_H
#define AALAB_PROTO_JOB_RANDOM_STATS_H

#include "job_optimizer_spec.h"
#include "job_point_metrics.h"
#include "job_result_util.h"
#include "aa_pattern.h"

typedef struct proto_random_stats_spec {
    proto_optimizer_spec common; /* max_seconds default 30: half for Opt W, half for Opt W+P */
    aa_family family;
    size_t count;                      /* default 1000 */
    aa_seed_distribution distribution; /* default uniform */
    double poisson_radius;             /* px; the default for the family's density when not given */
    proto_point_metrics_spec metrics;  /* point-set figures per pattern; count 0: none */
} proto_random_stats_spec;

int proto_decode_random_stats_spec(const json_t *spec, proto_random_stats_spec *out, aa_error *err);
void proto_random_stats_spec_free(proto_random_stats_spec *s);

/* Result of a "random-stats" job: the random patterns' E2 and the two optimised stages. */
typedef struct proto_stats_stage {
    double e2;
    aa_pattern pattern;
    aa_optimize_method method;
} proto_stats_stage;

typedef struct proto_random_stats_result {
    char family[48];
    aa_seed_distribution distribution;
    double radius; /* Poisson disk radius in px ("generator"); NaN: none recorded */
    long count;
    double min, avg, max; /* E2 of the random patterns */
    aa_pattern best_random;
    proto_stats_stage opt_w, opt_wp; /* weights only; weights and positions */
    proto_run_info run;
    proto_point_metrics point_metrics; /* spec.count 0: the spec asked for none */
} proto_random_stats_result;

/* {"family","distribution","count","random":{"min","avg","max"},"best_random","opt_w":{"e2",
 * "pattern","method"},"opt_wp":{...},"best","e2","generator":{"name","radius"?},"executor",
 * "shards","reproducible","point_metrics"? (job_point_metrics.h)}: Opt W+P is
 * also the result's "best" and "e2". NULL when out of memory. */
json_t *proto_encode_random_stats_result(const proto_random_stats_result *r);
int proto_decode_random_stats_result(const json_t *j, proto_random_stats_result *out,
                                     aa_error *err);
void proto_random_stats_result_free(proto_random_stats_result *r);

#endif
