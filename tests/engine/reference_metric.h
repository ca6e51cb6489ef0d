/* Independent slow reference for the engine tests: reference filters (impulse response and
 * CDF written from their definitions in long double, no engine code) and E1 by adaptive
 * Gauss-Legendre quadrature in long double over the intervals between sorted projections and
 * the filter's knots. Slow relative to the engine on purpose: it shares no representation
 * (no Chebyshev tables, no fixed rule) with it, so agreement means something. */
#ifndef AALAB_TESTS_REFERENCE_METRIC_H
#define AALAB_TESTS_REFERENCE_METRIC_H

#include <stddef.h>

#define REF_PI 3.141592653589793238462643383279502884L
#define REF_LANCZOS_STEP 0.25L
#define REF_LANCZOS_MAX_CELLS 64

typedef enum ref_formula { REF_MITCHELL, REF_BOX, REF_TENT, REF_GAUSSIAN, REF_LANCZOS } ref_formula;

typedef struct ref_filter {
    ref_formula formula;
    long double B, C;  /* Mitchell-Netravali */
    long double sigma; /* Gaussian */
    long double a;     /* Lanczos */
    long double radius;
    long double norm; /* 1 / integral of the unnormalised response (Gaussian, Lanczos) */
    /* Lanczos: CDF at -radius + k * REF_LANCZOS_STEP, by quadrature of h. */
    long double cell_cdf[REF_LANCZOS_MAX_CELLS + 1];
} ref_filter;

/* Mitchell-Netravali (B, C) of support [-radius, radius]: the standard radius-2 cubic
 * stretched by radius / 2 (and divided by it, keeping unit integral). */
void ref_filter_mitchell(ref_filter *f, long double B, long double C, long double radius);
void ref_filter_box(ref_filter *f, long double radius);
void ref_filter_tent(ref_filter *f, long double radius);
void ref_filter_gaussian(ref_filter *f, long double sigma, long double radius);
void ref_filter_lanczos(ref_filter *f, long double a);

long double ref_filter_h(const ref_filter *f, long double x);
/* CDF: closed form (Mitchell: antiderivative of the cubics; box, tent; Gaussian: erf),
 * Lanczos: composite 20-point Gauss-Legendre of h from the nearest table cell. */
long double ref_filter_cdf(const ref_filter *f, long double a);
/* CDF by composite 20-point Gauss-Legendre of h over [-radius, a] split at the knots and into
 * cells of at most `cell` length: the cross-check of the closed forms. */
long double ref_filter_cdf_by_quadrature(const ref_filter *f, long double a, long double cell);
/* Points where h or a derivative is not smooth, ascending; returns how many (<= 8). */
size_t ref_filter_knots(const ref_filter *f, long double *out);

/* m-point Gauss-Legendre rule on [-1, 1] (m = 10 or 20 cached, any m <= 64 computed). */
void ref_gauss_legendre(int m, long double *node, long double *weight);

/* Squared E1 of the 1-D pattern (p_i, w_i): integral of (ghat - g)^2 over the span
 * [min(p, -r), max(p, r)] (outside it the integrand is 0 when sum w = 1), by adaptive
 * G10/G20 Gauss-Legendre in long double on every interval between breakpoints. */
long double ref_e1_squared(const ref_filter *f, const long double *p, const long double *w,
                           size_t n);
/* Projections p_i = x_i cos(theta) + y_i sin(theta) in long double of the double inputs. */
void ref_project(const double *x, const double *y, size_t n, double theta, long double *p);
/* E1 at angle theta (radians) for samples given as separate arrays. */
long double ref_e1_at_angle(const ref_filter *f, const double *x, const double *y, const double *w,
                            size_t n, double theta);
/* Position derivative dE1/dp_i = w_i (2 g(p_i) - 2 S_i - w_i) / (2 E1) and raw weight
 * derivative (1/E1) integral_{p_i}^{inf} (ghat - g) da, with the reference g and quadrature.
 * Samples must have distinct projections. */
void ref_e1_gradient_1d(const ref_filter *f, const long double *p, const long double *w, size_t n,
                        long double *e1, long double *dp, long double *dw_raw);

#endif
