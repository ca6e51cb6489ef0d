#include "point_metrics.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "point_set.h"

static const char *const names[AA_PM_COUNT] = {"l2_star",
                                               "centered",
                                               "wrap_around",
                                               "mixture",
                                               "star_linf",
                                               "min_distance",
                                               "mean_nn_distance",
                                               "min_distance_normalized",
                                               "mean_nn_distance_normalized",
                                               "effective_nyquist",
                                               "effective_nyquist_normalized",
                                               "oscillation"};

const char *aa_point_metric_name(aa_point_metric m)
{
    return (unsigned)m < AA_PM_COUNT ? names[m] : "?";
}

int aa_point_metric_parse(const char *name, aa_point_metric *out)
{
    for (int m = 0; name && m < AA_PM_COUNT; m++)
        if (!strcmp(name, names[m])) {
            *out = (aa_point_metric)m;
            return AA_OK;
        }
    return AA_EINVAL;
}

int aa_point_metrics_of(const aa_pattern *p, const aa_point_metric *which, size_t k, double *values,
                        aa_error *err)
{
    /* Only the groups asked for are computed: the L-infinity star and the spectrum cost most. */
    bool want[AA_PM_COUNT] = {false};
    for (size_t i = 0; i < k; i++) {
        if ((unsigned)which[i] >= AA_PM_COUNT)
            return aa_error_set(err, AA_EINVAL, "metrics", "unknown point-set figure");
        want[which[i]] = true;
    }
    bool disc = want[AA_PM_L2_STAR] || want[AA_PM_CENTERED] || want[AA_PM_WRAP_AROUND] ||
                want[AA_PM_MIXTURE];
    bool spacing = want[AA_PM_MIN_DISTANCE] || want[AA_PM_MEAN_NN_DISTANCE] ||
                   want[AA_PM_MIN_DISTANCE_NORMALIZED] || want[AA_PM_MEAN_NN_DISTANCE_NORMALIZED];
    bool spectrum = want[AA_PM_EFFECTIVE_NYQUIST] || want[AA_PM_EFFECTIVE_NYQUIST_NORMALIZED] ||
                    want[AA_PM_OSCILLATION];
    aa_point *pts = NULL;
    size_t n = 0;
    int rc = aa_pattern_unit_points(p, &pts, &n, err);
    double v[AA_PM_COUNT];
    for (int m = 0; m < AA_PM_COUNT; m++)
        v[m] = NAN;
    aa_discrepancy d;
    aa_spacing sp;
    aa_spectrum s;
    memset(&s, 0, sizeof s);
    if (!rc && disc)
        rc = aa_point_set_discrepancy(pts, n, &d, err);
    if (!rc && disc) {
        v[AA_PM_L2_STAR] = d.l2_star;
        v[AA_PM_CENTERED] = d.centered;
        v[AA_PM_WRAP_AROUND] = d.wrap_around;
        v[AA_PM_MIXTURE] = d.mixture;
    }
    if (!rc && want[AA_PM_STAR_LINF])
        rc = aa_point_set_star_discrepancy(pts, n, &v[AA_PM_STAR_LINF], err);
    if (!rc && spacing)
        rc = aa_point_set_spacing(pts, n, &sp, err);
    if (!rc && spacing) {
        v[AA_PM_MIN_DISTANCE] = sp.min_distance;
        v[AA_PM_MEAN_NN_DISTANCE] = sp.mean_nn_distance;
        v[AA_PM_MIN_DISTANCE_NORMALIZED] = sp.min_distance_normalized;
        v[AA_PM_MEAN_NN_DISTANCE_NORMALIZED] = sp.mean_nn_distance_normalized;
    }
    if (!rc && spectrum)
        rc = aa_point_set_spectrum(pts, n, AA_PM_SPECTRUM_RADIUS, &s, err);
    if (!rc && spectrum) {
        v[AA_PM_EFFECTIVE_NYQUIST] = s.effective_nyquist;
        v[AA_PM_EFFECTIVE_NYQUIST_NORMALIZED] = s.effective_nyquist / sqrt((double)n);
        v[AA_PM_OSCILLATION] = s.oscillation;
        aa_spectrum_free(&s);
    }
    free(pts);
    for (size_t i = 0; !rc && i < k; i++)
        values[i] = isfinite(v[which[i]]) ? v[which[i]] : NAN;
    return rc;
}
