/* The step response the renderer's reference really has across a straight edge (docs/predict.md).
 *
 * The reference (reference.h) filters the scene with the separable 2-D filter h(x) h(y). Across
 * a straight edge with unit normal (c, s) at signed distance a from the output point (inside:
 * x c + y s <= a), it computes
 *     g_θ(a) = ∫∫_{x c + y s <= a} h(x) h(y) dx dy = ∫ h(x) g((a - x c) / |s|) dx,
 * the CDF of X c + Y s with X, Y independent with density h: the 1-D step response g(a) of E1
 * (metric.h) only at θ = 0° or 90°. Its density is the convolution of h scaled by |c| and by |s|,
 * so for a piecewise-cubic h (Mitchell-Netravali family, box, tent) g_θ is a polynomial of
 * degree <= 8 between the knots k_i |c| + k_j |s| (k the filter's knots). Depends on |c| and |s|
 * only (h is even), so θ, 180° - θ and 90° - θ share one profile.
 *
 * aa_edge_profile_exact evaluates g_θ(a) by Gauss-Legendre quadrature per polynomial piece of
 * the integrand: exact up to rounding for the piecewise-polynomial filters. aa_edge_profile
 * caches g_θ for one angle as Chebyshev interpolants of degree AA_EDGE_PROFILE_DEGREE on those
 * pieces (exact up to rounding for the piecewise-cubic filters: degree 8 <= 12; for the Gaussian
 * and Lanczos filters on AA_EDGE_PROFILE_MAX_PIECES equal pieces, within the tested 1e-12), and
 * aa_edge_profile_e1 is E1 of a kernel measured against it instead of against g. */
#ifndef AA_EDGE_PROFILE_H
#define AA_EDGE_PROFILE_H

#include <stddef.h>

#include "aa_core.h"
#include "aa_pattern.h"

#define AA_EDGE_PROFILE_DEGREE 12
#define AA_EDGE_PROFILE_MAX_PIECES 64

typedef struct aa_edge_profile {
    double c, s;  /* |cos θ|, |sin θ| */
    double reach; /* (|c| + |s|) · radius: g_θ = 0 below -reach, 1 above */
    int pieces;
    double knot[AA_EDGE_PROFILE_MAX_PIECES + 1];
    /* g_θ on piece j: sum_k cheb[j][k] T_k(t), t = (2a - knot[j] - knot[j+1]) / (knot[j+1] -
     * knot[j]). */
    double cheb[AA_EDGE_PROFILE_MAX_PIECES][AA_EDGE_PROFILE_DEGREE + 1];
    /* Gauss-Legendre rule of the E1 sweep: exact for (c - g_θ)² on a piece. */
    double rule_node[AA_EDGE_PROFILE_DEGREE + 1], rule_weight[AA_EDGE_PROFILE_DEGREE + 1];
} aa_edge_profile;

/* g_θ(a) for the unit normal (c, s), by quadrature (no table). */
double aa_edge_profile_exact(const aa_filter *f, double c, double s, double a);

/* The table for normal angle theta (radians). Never fails for a valid filter. */
void aa_edge_profile_init(aa_edge_profile *p, const aa_filter *f, double theta);

/* g_θ(a) from the table. */
double aa_edge_profile_eval(const aa_edge_profile *p, double a);

/* E1 of the kernel s[0..n) at the direction (ct, st) measured against the profile:
 * sqrt(∫ (ĝ(a) - g_θ(a))² da), ĝ(a) = Σ_{x ct + y st <= a} w. Infinite when the weights do not
 * sum to 1 (within 1e-9). Errors: AA_EINVAL (n = 0), AA_ENOMEM. */
int aa_edge_profile_e1(const aa_edge_profile *p, const aa_sample *s, size_t n, double ct, double st,
                       double *e1);

#endif
