/* Point-set figures per random pattern in the random-stats and table3 jobs (issue 31): the
 * spec's "metrics" list, the per-pattern columns a shard outputs, and the result's
 * "point_metrics" block with Spearman's rho of each figure with E2 over the patterns. */
#ifndef AALAB_PROTO_JOB_POINT_METRICS_H
#define AALAB_PROTO_JOB_POINT_METRICS_H

#include <stddef.h>

#include <jansson.h>

#include "aa_pattern.h"

/* Random patterns of one job that may carry figures: keeps the result's per-pattern columns
 * under about 3 MB of JSON (13 numbers of about 20 bytes per pattern). */
#define PROTO_POINT_METRICS_MAX_PATTERNS 10000

typedef struct proto_point_metrics_spec {
    aa_point_metric which[AA_PM_COUNT];
    size_t count; /* 0: no "metrics" in the spec */
} proto_point_metrics_spec;

/* The spec's optional "metrics": a non-empty array of distinct names (aa_point_metric_name),
 * for a family whose tile has 2..AA_POINT_SET_MAX points and a job of at most
 * PROTO_POINT_METRICS_MAX_PATTERNS patterns (`patterns`: how many it draws). Errors name
 * "metrics" or "metrics[i]". */
int proto_spec_point_metrics(const json_t *spec, const aa_family *family, size_t patterns,
                             proto_point_metrics_spec *out, aa_error *err);

/* Figures of n patterns and their E2, and rho of each figure with E2. */
typedef struct proto_point_metrics {
    proto_point_metrics_spec spec;
    size_t n, capacity;
    double *e2;     /* [capacity] */
    double *values; /* [spec.count][capacity], figure-major; NaN where undefined */
    aa_spearman_result rho[AA_PM_COUNT];
} proto_point_metrics;

/* Empty columns for up to capacity patterns. */
int proto_point_metrics_init(proto_point_metrics *pm, const proto_point_metrics_spec *spec,
                             size_t capacity, aa_error *err);
void proto_point_metrics_free(proto_point_metrics *pm);
/* {"e2": [n], "<name>": [n], ...} (null for NaN); NULL when out of memory. */
json_t *proto_point_metrics_columns(const proto_point_metrics *pm);
/* Appends the rows of such columns (a shard's output, or a result's "patterns"); errors name
 * field. */
int proto_point_metrics_append(proto_point_metrics *pm, const json_t *columns, const char *field,
                               aa_error *err);
/* An aa_random_visit_fn (user: the proto_point_metrics): pattern i's figures and E2 into row i
 * (rows 0..i filled in order; n becomes i + 1). */
int proto_point_metrics_visit(void *user, size_t i, const aa_pattern *p, double e2, aa_error *err);
/* rho[] of every figure with E2 over the n patterns. */
int proto_point_metrics_rank(proto_point_metrics *pm, aa_error *err);

/* {"metrics": [names], "spectrum_radius", "spearman": [{"metric","rho","n","p_value"}],
 * "patterns": columns}; NULL when out of memory. */
json_t *proto_encode_point_metrics(const proto_point_metrics *pm);
/* The same back (rho as stored); errors name field. */
int proto_decode_point_metrics(const json_t *j, const char *field, proto_point_metrics *pm,
                               aa_error *err);

#endif
