/* The pair correlation function on the unit torus with a Gaussian kernel (the estimator of
 * Illian et al., "Statistical Analysis and Modelling of Spatial Point Patterns", 2008, 4.3.3,
 * without edge correction: the torus has no edge). Each pair adds to the bins within 5 sigma of
 * its distance only. */
#include "point_set.h"

#include <math.h>
#include <string.h>

#define PI_D 3.14159265358979323846

int aa_point_set_pcf(const aa_point *pts, size_t n, double r_max, size_t bins, double sigma,
                     double *g, aa_error *err)
{
    int rc = aa_point_set_check(pts, n, err);
    if (rc)
        return rc;
    if (!(r_max > 0 && r_max <= 0.5))
        return aa_error_set(err, AA_EINVAL, "r_max", "must be in (0, 0.5]");
    if (bins < 1 || bins > 4096)
        return aa_error_set(err, AA_EINVAL, "bins", "must be 1 to 4096");
    if (!(sigma > 0 && isfinite(sigma)))
        return aa_error_set(err, AA_EINVAL, "sigma", "must be a positive number");
    memset(g, 0, bins * sizeof *g);
    double dr = r_max / (double)bins, reach = 5 * sigma, inv2s2 = 1 / (2 * sigma * sigma);
    for (size_t i = 0; i < n; i++) {
        for (size_t j = i + 1; j < n; j++) {
            double d = sqrt(aa_torus_distance_sq(pts[i], pts[j]));
            if (d - reach > r_max)
                continue;
            long lo = (long)floor((d - reach) / dr - 0.5), hi = (long)ceil((d + reach) / dr - 0.5);
            if (lo < 0)
                lo = 0;
            if (hi > (long)bins - 1)
                hi = (long)bins - 1;
            for (long b = lo; b <= hi; b++) {
                double t = ((double)b + 0.5) * dr - d;
                g[b] += 2 * exp(-t * t * inv2s2); /* the pair (i, j) and (j, i) */
            }
        }
    }
    double norm = 1 / (sqrt(2 * PI_D) * sigma * (double)n * (double)(n - 1) * 2 * PI_D);
    for (size_t b = 0; b < bins; b++)
        g[b] *= norm / (((double)b + 0.5) * dr);
    return AA_OK;
}
