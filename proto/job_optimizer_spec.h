/* The spec fields the optimizer job kinds (optimize, family-sweep, random-stats) share, decoded
 * in one place: filter, acuity, angles, max_seconds, max_iterations, rng_seed, mode, method,
 * grid. Each kind's
 * decoder (proto/job_<kind>.c) names its own keys; proto_optimizer_spec_decode checks the spec
 * against the shared keys plus those (one unknown-key check) and decodes the shared ones. */
#ifndef AALAB_PROTO_JOB_OPTIMIZER_SPEC_H
#define AALAB_PROTO_JOB_OPTIMIZER_SPEC_H

#include <stdbool.h>
#include <stdint.h>

#include <jansson.h>

#include "aa_metric.h"
#include "aa_core.h"
#include "aa_pattern.h"
#include "aa_optimizer.h"

#define PROTO_MAX_DISTRIBUTIONS 5

/* Which shared fields a kind accepts (random-stats has no mode and no grid). */
enum {
    PROTO_OPT_MODE = 1u << 0,
    PROTO_OPT_GRID = 1u << 1,
};

typedef struct proto_optimizer_spec {
    aa_filter filter;
    aa_acuity acuity;
    double *angles; /* NULL: the acuity's default set */
    size_t angle_count;
    /* The budget. "max_iterations" without "max_seconds": no time budget (max_seconds 0) and a
     * reproducible result (the same for any number of shards or workers); any max_seconds
     * (given, or the kind's default when neither is given) makes the result best effort. */
    double max_seconds;
    long max_iterations; /* per seed (per optimised stage for random-stats); 0: kind default */
    bool reproducible;
    uint64_t rng_seed; /* default 1 */
    aa_optimize_mode mode;
    bool method_auto; /* "method" absent or "auto": the engine's choice (aa_auto_method) */
    aa_optimize_method method;
    int grid_bits; /* 0: no grid */
    bool d3d12;
} proto_optimizer_spec;

/* Checks spec's keys against the shared ones (those `fields` selects) plus kind_keys
 * (NULL-terminated), then decodes the shared fields; max_seconds defaults to def_seconds. On
 * error out holds nothing to free. */
int proto_optimizer_spec_decode(const json_t *spec, const char *const *kind_keys, unsigned fields,
                                double def_seconds, proto_optimizer_spec *out, aa_error *err);
void proto_optimizer_spec_free(proto_optimizer_spec *s);
aa_metric_params proto_optimizer_spec_metric(const proto_optimizer_spec *s);
/* The spec's max_iterations, or def when it gave none. */
long proto_optimizer_spec_iterations(const proto_optimizer_spec *s, long def);
/* The step rule for a run of mode on patterns that are (or not) tiled without border samples:
 * the spec's "method", or the engine's choice for "auto". */
aa_optimize_method proto_optimizer_spec_method(const proto_optimizer_spec *s,
                                               bool tiled_without_border, aa_optimize_mode mode);

/* Optional fields of a spec object: absent leaves *out unchanged; a bad type or range is
 * AA_EINVAL naming key. */
int proto_spec_number(const json_t *spec, const char *key, double lo, double hi, double *out,
                      aa_error *err);
int proto_spec_integer(const json_t *spec, const char *key, json_int_t lo, json_int_t hi,
                       json_int_t *out, aa_error *err);
int proto_spec_string(const json_t *spec, const char *key, const char **out, aa_error *err);
/* "filter", "acuity" and "angles", in that order: what the metric of every optimizer kind takes. */
int proto_spec_metric(const json_t *spec, aa_filter *filter, aa_acuity *acuity, double **angles,
                      size_t *angle_count, aa_error *err);
/* "max_seconds" (*max_seconds holds the default) and "max_iterations" (1..iterations_max, 0 when
 * absent). An iteration budget alone does not depend on the clock: *reproducible, no time budget
 * at all (*max_seconds 0). Any time budget stops seeds at clock-dependent points. */
int proto_spec_budget(const json_t *spec, json_int_t iterations_max, double *max_seconds,
                      long *max_iterations, bool *reproducible, aa_error *err);
/* "poisson_radius" in pixels for patterns of spp samples per pixel: the engine's default
 * (aa_poisson_default_radius) when absent; at most 0.8/sqrt(spp), since above ~0.83/sqrt(spp)
 * dart throwing jams before it places every sample. */
int proto_spec_poisson_radius(const json_t *spec, double spp, double *out, aa_error *err);
/* "family": required (or optional when !required: *out untouched if absent); an invalid family
 * string is AA_EINVAL naming "family". */
int proto_spec_family(const json_t *spec, bool required, bool *present, aa_family *out,
                      aa_error *err);
/* "distributions": [names] -> distributions (count 0 when absent). */
int proto_spec_distributions(const json_t *spec,
                             aa_seed_distribution distributions[PROTO_MAX_DISTRIBUTIONS],
                             size_t *count, aa_error *err);

#endif
