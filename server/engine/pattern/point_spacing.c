/* Toroidal nearest-neighbour distances (PSA's "min. distance" and "avg. min. distance"), by
 * all pairs: O(n^2), 8 M distance evaluations at 4,096 points. */
#include "point_set.h"

#include <math.h>
#include <stdlib.h>

int aa_point_set_spacing(const aa_point *pts, size_t n, aa_spacing *out, aa_error *err)
{
    int rc = aa_point_set_check(pts, n, err);
    if (rc)
        return rc;
    double *nearest = malloc(n * sizeof *nearest);
    if (!nearest)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t i = 0; i < n; i++)
        nearest[i] = INFINITY;
    for (size_t i = 0; i < n; i++) {
        for (size_t j = i + 1; j < n; j++) {
            double d = aa_torus_distance_sq(pts[i], pts[j]);
            if (d < nearest[i])
                nearest[i] = d;
            if (d < nearest[j])
                nearest[j] = d;
        }
    }
    double min_sq = INFINITY, sum = 0;
    for (size_t i = 0; i < n; i++) {
        if (nearest[i] < min_sq)
            min_sq = nearest[i];
        sum += sqrt(nearest[i]);
    }
    free(nearest);
    out->min_distance = sqrt(min_sq);
    out->mean_nn_distance = sum / (double)n;
    out->packing_distance = sqrt(2.0 / (sqrt(3.0) * (double)n));
    out->min_distance_normalized = out->min_distance / out->packing_distance;
    out->mean_nn_distance_normalized = out->mean_nn_distance / out->packing_distance;
    return AA_OK;
}
