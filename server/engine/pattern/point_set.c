/* A pattern's tile as a point set on the unit torus, and the checks every analysis shares. */
#include "point_set.h"

#include <math.h>
#include <stdlib.h>

int aa_point_set_check(const aa_point *pts, size_t n, aa_error *err)
{
    if (n < 2 || n > AA_POINT_SET_MAX)
        return aa_error_set(err, AA_EINVAL, "points", "%zu points: the analysis takes 2 to %d", n,
                            AA_POINT_SET_MAX);
    for (size_t i = 0; i < n; i++)
        if (!(pts[i].x >= 0 && pts[i].x < 1 && pts[i].y >= 0 && pts[i].y < 1))
            return aa_error_set(err, AA_EINVAL, "points", "point %zu (%g, %g) is not in [0,1)^2", i,
                                pts[i].x, pts[i].y);
    return AA_OK;
}

int aa_pattern_unit_points(const aa_pattern *p, aa_point **out, size_t *n, aa_error *err)
{
    *out = NULL;
    *n = 0;
    if (p->tile <= 0 || !p->tile_count)
        return aa_error_set(err, AA_EINVAL, "pattern",
                            "the pattern has no tile (explicit kernels whose count is not a "
                            "square): its samples are not one point set");
    aa_point *q = malloc(p->tile_count * sizeof *q);
    if (!q)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    double inv = 1.0 / p->tile;
    for (size_t i = 0; i < p->tile_count; i++) {
        /* Tile coordinates are in [0, T); the scaled value can round up to 1. */
        double x = p->tile_samples[i].x * inv, y = p->tile_samples[i].y * inv;
        q[i].x = x >= 1.0 ? 0.0 : x;
        q[i].y = y >= 1.0 ? 0.0 : y;
    }
    *out = q;
    *n = p->tile_count;
    return AA_OK;
}
