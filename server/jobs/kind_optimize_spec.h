/* Shared by the optimizer job kinds (optimize, family-sweep, random-stats): strict spec
 * parsing of the common fields and the bridge from the engine's progress callback to job_ctx
 * (progress, best-so-far, error-against-run-time trace, cancellation). */
#ifndef AALAB_KIND_OPTIMIZE_SPEC_H
#define AALAB_KIND_OPTIMIZE_SPEC_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_metric.h"
#include "aa_pattern.h"
#include "job_kind.h"
#include "aa_optimizer.h"

typedef struct opt_common_spec {
    aa_filter filter;
    aa_acuity acuity;
    double *angles; /* NULL: the acuity's default set */
    size_t angle_count;
    double max_seconds;
    uint64_t rng_seed;
    aa_optimize_mode mode;
    bool method_auto; /* "method" absent or "auto": the engine's choice (aa_auto_method) */
    aa_optimize_method method;
    int grid_bits;
    bool d3d12;
} opt_common_spec;

/* Rejects keys of spec not in allowed (NULL-terminated), naming the first unknown one. */
int opt_spec_check_keys(const json_t *spec, const char *const *allowed, aa_error *err);
/* Optional number / integer fields: absent leaves *out unchanged; bad type or range names key. */
int opt_spec_number(const json_t *spec, const char *key, double lo, double hi, double *out,
                    aa_error *err);
int opt_spec_integer(const json_t *spec, const char *key, json_int_t lo, json_int_t hi,
                     json_int_t *out, aa_error *err);
int opt_spec_string(const json_t *spec, const char *key, const char **out, aa_error *err);
/* filter, acuity, angles, max_seconds (default def_seconds), rng_seed, mode, method, grid. */
int opt_common_parse(const json_t *spec, double def_seconds, opt_common_spec *out, aa_error *err);
void opt_common_free(opt_common_spec *c);
aa_metric_params opt_common_metric(const opt_common_spec *c);
/* The step rule for a run of the spec's mode on patterns that are (or not) tiled without border
 * samples: the spec's "method", or the engine's choice for "auto". */
aa_optimize_method opt_common_method(const opt_common_spec *c, bool tiled_without_border,
                                     aa_optimize_mode mode);

/* Engine progress -> job_ctx. base/span map the run's 0..1 onto the job's progress. */
typedef struct opt_job_bridge {
    job_ctx *ctx;
    double base, span;
    long iterations_before, evaluations_before;
    double seconds_before;
    double best_e2; /* over the whole job */
    double last_best_post;
} opt_job_bridge;
int opt_job_progress(void *user, const aa_optimize_progress *p);

/* "distributions": [names] -> kinds (count 0 when absent). */
int opt_parse_distributions(const json_t *spec, aa_seed_kind *kinds, size_t *count, aa_error *err);
/* per-seed summary of a multi-start run. */
json_t *opt_per_seed_json(const aa_multistart_result *r);

#endif
