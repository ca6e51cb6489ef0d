/* Point-set analysis beside E2: the figures sampling research judges a point set by, for a
 * pattern's sample positions taken as a set on the unit torus (its tile scaled to [0,1)^2).
 * Definitions, sources and precision: docs/analysis.md. Every function takes n >= 2 points in
 * [0,1)^2 (AA_EINVAL otherwise, naming "points") and at most AA_POINT_SET_MAX points; the pair
 * sums are O(n^2). */
#ifndef AA_POINT_SET_H
#define AA_POINT_SET_H

#include <stddef.h>

#include "aa_core.h"
#include "pattern.h"

#define AA_POINT_SET_MAX 4096

/* AA_OK if 2 <= n <= AA_POINT_SET_MAX and every point is finite and in [0,1)^2. */
int aa_point_set_check(const aa_point *pts, size_t n, aa_error *err);
/* The squared distance of a and b on the unit torus. */
static inline double aa_torus_distance_sq(aa_point a, aa_point b)
{
    double dx = a.x > b.x ? a.x - b.x : b.x - a.x, dy = a.y > b.y ? a.y - b.y : b.y - a.y;
    dx = dx > 0.5 ? 1.0 - dx : dx;
    dy = dy > 0.5 ? 1.0 - dy : dy;
    return dx * dx + dy * dy;
}

/* The positions of a pattern's tile samples scaled to [0,1)^2 (malloc'd into *out). AA_EINVAL
 * naming "pattern" when the tile is unknown (explicit kernels whose count is not a square). */
int aa_pattern_unit_points(const aa_pattern *p, aa_point **out, size_t *n, aa_error *err);

/* Hickernell's L2 discrepancies in closed form, as scipy.stats.qmc.discrepancy defines them
 * (which returns the squares of CD, WD and MD, and the root of L2-star): each as the root and
 * its square. Pair sums are compensated (Neumaier) and the square combined in long double, so
 * each square is within a few eps of its exact value for the rounded pair terms (measured:
 * 1e-12 relative or better against long-double sums at 4 to 1,024 points, e2e_analysis). */
typedef struct aa_discrepancy {
    double l2_star, l2_star_sq;         /* L2-star */
    double centered, centered_sq;       /* CD */
    double wrap_around, wrap_around_sq; /* WD */
    double mixture, mixture_sq;         /* MD */
} aa_discrepancy;
int aa_point_set_discrepancy(const aa_point *pts, size_t n, aa_discrepancy *out, aa_error *err);

/* The exact L-infinity star discrepancy sup over boxes [0,a) x [0,b) of |#points inside / n -
 * ab|, closed boxes included (a point on the box's far edge counts for the upper deviation).
 * O(n^2) over the candidate corners (the points' coordinates and 1). Exact up to the rounding
 * of a product ab (relative 1e-16). */
int aa_point_set_star_discrepancy(const aa_point *pts, size_t n, double *out, aa_error *err);

/* Toroidal nearest-neighbour distances, raw and divided by PSA's hexagonal packing distance
 * sqrt(2 / (sqrt(3) n)) (the spacing of the densest packing of n points in the unit torus). */
typedef struct aa_spacing {
    double min_distance, mean_nn_distance;
    double packing_distance;
    double min_distance_normalized, mean_nn_distance_normalized;
} aa_spacing;
int aa_point_set_spacing(const aa_point *pts, size_t n, aa_spacing *out, aa_error *err);

/* The periodogram P(k) = |sum_j exp(-2 pi i k.x_j)|^2 / n over the integer frequencies k of the
 * torus with |kx|, |ky| <= radius (1..256), row-major from (-radius, -radius); P(0) = n. Its
 * radial average over annuli of width 1 centred on |k| = 0, 1, ..., radius, and its anisotropy
 * 10 log10(variance / mean^2) per annulus (PSA; NaN for an annulus of fewer than 2 frequencies
 * or of zero mean, i.e. below 64 n eps, the periodogram's rounding). effective_nyquist: the largest
 * radius below which the mean power over the disc stays under 0.1 (after PSA's EffectiveNyquist);
 * oscillation: PSA's oscillation figure 10 sqrt(mean of (P - 1)^2 over the ring from where the
 * radial power first reaches 0.98 of its running maximum out to 10 sqrt(n)/2 beyond it or the
 * radius). Both also divided by sqrt(n), PSA's frequency unit. P(k) is computed from cos/sin tables
 * per point, each entry within 16 eps (exact values every 8 frequencies, the angle-addition
 * recurrence between): absolute error about 32 n eps. */
typedef struct aa_spectrum {
    int radius;
    size_t side;           /* 2 radius + 1 */
    double *power;         /* [side * side] */
    double *radial;        /* [radius + 1] */
    double *anisotropy_db; /* [radius + 1] */
    size_t *annulus_count; /* [radius + 1]: frequencies per annulus */
    double effective_nyquist, oscillation;
} aa_spectrum;
#define AA_SPECTRUM_MAX_RADIUS 256
int aa_point_set_spectrum(const aa_point *pts, size_t n, int radius, aa_spectrum *out,
                          aa_error *err);
void aa_spectrum_free(aa_spectrum *s);
/* The mean of m >= 1 spectra of one radius, each of a set of n points: the periodograms
 * averaged, then the radial average, anisotropy and the two figures of that mean (pbrt-v4's
 * pspec and PSA's --avg average several sets so). AA_EINVAL naming "sets" if the radii differ. */
int aa_spectrum_mean(const aa_spectrum *s, size_t m, size_t n, aa_spectrum *out, aa_error *err);

/* The pair correlation function on the torus, g(r) = sum_{i != j} k(r - d_ij) /
 * (n (n - 1) 2 pi r) at the bin centres r_b = (b + 1/2) r_max / bins, with the Gaussian kernel
 * k(t) = exp(-t^2 / (2 sigma^2)) / (sqrt(2 pi) sigma): 1 for a Poisson process at r << 1/2.
 * r_max in (0, 0.5], bins 1..4096, sigma > 0; g gets bins values. */
int aa_point_set_pcf(const aa_point *pts, size_t n, double r_max, size_t bins, double sigma,
                     double *g, aa_error *err);

#endif
