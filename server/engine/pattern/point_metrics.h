/* The scalar point-set figures (point_set.h) a job can record per pattern, by the names
 * /v1/analyze gives them: one call computes the chosen ones for a pattern's tile points. */
#ifndef AA_POINT_METRICS_H
#define AA_POINT_METRICS_H

#include <stddef.h>

#include "aa_core.h"
#include "pattern.h"

typedef enum aa_point_metric {
    AA_PM_L2_STAR, /* discrepancies: the roots */
    AA_PM_CENTERED,
    AA_PM_WRAP_AROUND,
    AA_PM_MIXTURE,
    AA_PM_STAR_LINF,
    AA_PM_MIN_DISTANCE, /* spacing, raw and divided by the packing distance */
    AA_PM_MEAN_NN_DISTANCE,
    AA_PM_MIN_DISTANCE_NORMALIZED,
    AA_PM_MEAN_NN_DISTANCE_NORMALIZED,
    AA_PM_EFFECTIVE_NYQUIST, /* spectrum at radius AA_PM_SPECTRUM_RADIUS */
    AA_PM_EFFECTIVE_NYQUIST_NORMALIZED,
    AA_PM_OSCILLATION,
    AA_PM_COUNT
} aa_point_metric;

/* The periodogram radius of the spectral figures (the /v1/analyze default). */
#define AA_PM_SPECTRUM_RADIUS 32

/* "l2_star", "centered", ...: the names of /v1/analyze's fields. */
const char *aa_point_metric_name(aa_point_metric m);
/* AA_OK and *out for a known name; AA_EINVAL otherwise (no error filled). */
int aa_point_metric_parse(const char *name, aa_point_metric *out);

/* values[i] = figure which[i] of the pattern's tile points (aa_pattern_unit_points): NaN where
 * the figure is undefined (effective Nyquist or oscillation with no crossing). Errors of
 * aa_pattern_unit_points and aa_point_set_check (e.g. more than AA_POINT_SET_MAX points). */
int aa_point_metrics_of(const aa_pattern *p, const aa_point_metric *which, size_t k, double *values,
                        aa_error *err);

#endif
