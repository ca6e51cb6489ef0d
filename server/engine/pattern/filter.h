/* Reference reconstruction filters h(x) (1-D, even, unit integral) and their step responses
 * (CDFs) g(a) = integral of h from -inf to a.
 *
 * Every filter is stored as a piecewise polynomial CDF in Chebyshev form over knots, so that the
 * E1 integral can be done exactly piece by piece (metric.c). For the piecewise-cubic filters
 * (Mitchell-Netravali family, box, tent) the representation is exact up to rounding. For the
 * Gaussian and Lanczos filters it is a tabulated interpolant of the exact CDF built at init
 * time; cdf_error_bound states its measured maximum absolute error (about 2e-15).
 * The struct is a plain value: copy it freely, no free() needed. */
#ifndef AA_FILTER_H
#define AA_FILTER_H

#include <stddef.h>

#include "aa_core.h"

#define AA_FILTER_MAX_PIECES 192
#define AA_FILTER_MAX_DEGREE 15
/* Closed-form tables (piecewise-polynomial filters): at most 4 pieces, Gamma of degree <= 5. */
#define AA_FILTER_CLOSED_MAX_PIECES 4
#define AA_FILTER_CLOSED_DEGREE 5

typedef enum aa_filter_formula {
    AA_FILTER_MITCHELL, /* Mitchell-Netravali (B, C), support [-radius, radius], default radius 2 */
    AA_FILTER_BOX,
    AA_FILTER_TENT,
    AA_FILTER_GAUSSIAN, /* truncated at radius, renormalised */
    AA_FILTER_LANCZOS   /* sinc(x) sinc(x/a) on [-a, a], renormalised */
} aa_filter_formula;

typedef struct aa_filter {
    aa_filter_formula formula;
    char name[24]; /* canonical name: "mitchell", "catmull-rom", "bspline", "notch", "box", ... */
    double B, C;   /* Mitchell-Netravali parameters (also set for catmull-rom/bspline/notch) */
    double sigma;  /* Gaussian */
    double lanczos_a;
    double radius;          /* h(x) = 0 for |x| >= radius */
    double cdf_error_bound; /* max |g_table - g_exact| measured at init vs long double */
    double scale;           /* 1 / integral of the unnormalised response */
    int pieces;             /* number of polynomial pieces covering [-radius, radius] */
    int degree;             /* polynomial degree of the CDF on each piece */
    double knot[AA_FILTER_MAX_PIECES + 1];
    /* CDF on piece j in Chebyshev form: t = (2a - knot[j] - knot[j+1]) / (knot[j+1] - knot[j]),
     * g(a) = sum_k cheb[j][k] T_k(t). */
    double cheb[AA_FILTER_MAX_PIECES][AA_FILTER_MAX_DEGREE + 1];
    /* (degree+1)-point Gauss-Legendre rule on [-1, 1]: exact for (c - g)^2 on a piece. */
    double rule_node[AA_FILTER_MAX_DEGREE + 1];
    double rule_weight[AA_FILTER_MAX_DEGREE + 1];
    /* Closed form of E1 (docs/metric.md section 2b), piecewise-polynomial filters only
     * (Mitchell-Netravali family, box, tent); closed_pieces = 0 for the Gaussian and Lanczos.
     * With gamma(a) = g(a) - 1/2 (odd) and Gamma(a) = integral_{-radius}^{a} gamma (even,
     * Gamma(+-radius) = 0), piece j = floor((a + radius) * closed_inv_width) holds
     * Gamma(a) = sum_k closed_gamma[j][k] s^k, s = a - closed_mid[j]; the coefficients are
     * the exact polynomial integrals of h done in long double, rounded once to double.
     * closed_var = integral_{-radius}^{radius} gamma^2 (exact, long double, rounded once). */
    int closed_pieces;
    double closed_inv_width;
    double closed_var;
    double closed_mid[AA_FILTER_CLOSED_MAX_PIECES];
    double closed_gamma[AA_FILTER_CLOSED_MAX_PIECES][AA_FILTER_CLOSED_DEGREE + 1];
} aa_filter;

/* Constructors. Return AA_OK or AA_EINVAL (with err->field naming "B", "C", "sigma", "radius"
 * or "a") for non-finite or degenerate parameters. */
int aa_filter_mitchell(aa_filter *f, double B, double C, double radius, aa_error *err);
int aa_filter_box(aa_filter *f, double radius, aa_error *err);
int aa_filter_tent(aa_filter *f, double radius, aa_error *err);
int aa_filter_gaussian(aa_filter *f, double sigma, double radius, aa_error *err);
int aa_filter_lanczos(aa_filter *f, double a, aa_error *err);

/* Named constructor with defaults: "mitchell" (B=C=1/3, r=2), "catmull-rom" (0, 1/2),
 * "bspline" (1, 0), "notch" (3/2, -1/4), "box" (r=0.5), "tent" (r=1),
 * "gaussian" (sigma=0.5, r=2), "lanczos" (a=2). NaN parameters mean "use the default". */
typedef struct aa_filter_params {
    double B, C, radius, sigma, a;
} aa_filter_params;
aa_filter_params aa_filter_params_default(void); /* all NaN */
int aa_filter_by_name(aa_filter *f, const char *name, const aa_filter_params *p, aa_error *err);

/* The default reference filter of aalab: Mitchell-Netravali B = C = 1/3, radius 2. */
void aa_filter_default(aa_filter *f);

/* Names accepted by aa_filter_by_name, NULL-terminated. */
extern const char *const aa_filter_names[];

double aa_filter_eval(const aa_filter *f, double x); /* impulse response h(x), unit integral */
double aa_filter_cdf(const aa_filter *f, double a);  /* g(a) */
/* Piece index containing a, or -1 if a <= -radius, f->pieces if a >= radius. */
int aa_filter_piece(const aa_filter *f, double a);
/* CDF evaluated inside piece j (no range checks; a should lie in the piece). */
double aa_filter_cdf_in_piece(const aa_filter *f, int j, double a);

#endif
