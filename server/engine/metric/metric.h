/* The E1 / E2 error metric of Laine & Aila (2005), section 4, computed exactly.
 *
 * For a kernel of samples (x_i, y_i, w_i) and an edge-normal angle theta, the projections are
 * p_i = x_i cos(theta) + y_i sin(theta), the pattern's step response is
 * ghat(a) = sum_{p_i <= a} w_i and the reference's is the filter CDF g(a). Then
 *   E1(theta) = sqrt( integral (ghat(a) - g(a))^2 da ),
 *   E2 = max over kernels and angles of W(theta) E1(theta).
 * Two methods (docs/metric.md section 2):
 *  - closed form (piecewise-polynomial filters): with gamma = g - 1/2, Gamma its antiderivative
 *    from -r and V = integral gamma^2, E1^2 = (exterior terms) + sum over the constant pieces
 *    of (c_k - 1/2)^2 len_k + 2 sum_i w_i Gamma(p_i) + V: one polynomial per sample, no
 *    quadrature. Its terms cancel when E1^2 is small beside them (many samples, nearly perfect
 *    kernels); it carries an error estimate and falls back to the quadrature when the estimate
 *    exceeds AA_E1_CLOSED_REL_ERROR (measured in tests/engine: <= 1e-12 either way).
 *  - quadrature: between consecutive breakpoints (sorted projections and filter knots) ghat is
 *    constant and g a polynomial of degree d, so each piece is integrated with (d+1)-point
 *    Gauss-Legendre, exact for the degree-2d integrand; every term is >= 0, so the sum has
 *    relative error of a few ulp times the number of pieces, plus the filter table's stated
 *    CDF error for tabulated filters (Gaussian, Lanczos: always this method).
 *
 * Gradients (derived in docs/metric.md; L&A eq. 6 writes sqrt(E1) for E1):
 *   dE1/dp_i = w_i (2 g(p_i) - 2 S_i - w_i) / (2 E1),  S_i = sum of w_j sorted before i,
 *   dx_i = cos(theta) dE1/dp_i, dy_i = sin(theta) dE1/dp_i,
 *   dE1/dw_i (raw) = (1/E1) integral_{p_i}^{inf} (ghat - g) da, and the returned dw is the raw
 *   gradient projected onto sum(w) = 1 (minus its mean), the direction that keeps E1 finite.
 * At coincident projections the position derivative is one-sided (ties keep input order). */
#ifndef AA_METRIC_H
#define AA_METRIC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "acuity.h"
#include "aa_core.h"
#include "aa_pattern.h"

/* How the sorted order is carried from one angle of a kernel to the next (order.h). Every pass
 * gives the same order; AUTO takes the fastest this CPU runs. */
typedef enum aa_order_pass {
    AA_ORDER_AUTO = 0,
    AA_ORDER_INSERTION,   /* an insertion pass */
    AA_ORDER_RANK_AVX2,   /* ranks counted in a window, four lanes (x86-64 with AVX2) */
    AA_ORDER_RANK_AVX512, /* the same in eight lanes (x86-64 with AVX-512F) */
} aa_order_pass;

/* Scratch memory for the per-angle computation; reuse it across calls to avoid allocation.
 * One workspace per thread. The projections are kept sorted as a structure of arrays (p, w,
 * index). The kernel-block functions also keep the kernel's samples as arrays in input order
 * (in_x, in_y, in_w), so that projecting on a direction is one contiguous loop the compiler
 * vectorises, and the sort then moves keys and indices only. The workspace remembers the sorted
 * order of the last kernel it saw (identified by its sample pointer and count): the next angle
 * of the same kernel is re-sorted from that order (order.h: a rank pass or an insertion pass,
 * nearly linear for neighbouring angles). The result never depends on it (ties are ordered by
 * input index either way). */
typedef struct aa_metric_workspace {
    size_t capacity;
    double *p, *w;                     /* [capacity] each, in sorted order */
    uint32_t *index;                   /* input position of each sorted entry */
    double *in_x, *in_y, *in_w, *in_p; /* the block's kernel and projection, input order */
    double *tail;                      /* prefix integrals for the weight gradient */
    double *cdf;          /* g(p_k) of the sorted projections, from the closed form's prefix pass */
    double *u, *len;      /* the closed form's c_k - 1/2 and interval lengths, sorted order */
    bool cdf_valid;       /* cdf holds the current projections' values */
    const void *order_of; /* samples whose sorted order the arrays hold (NULL: none) */
    size_t order_n;
    double *padded; /* [capacity + 2 AA_ORDER_WINDOW]: the rank pass's keys between pads */
    aa_order_pass order_pass;           /* the caller's choice (AUTO after init) */
    aa_order_pass kernel_pass;          /* the pass for the current kernel's next angle */
    long rank_passes, insertion_passes; /* how each angle after a kernel's first was sorted */
    long closed_calls, fallback_calls;  /* how often the closed form was conditioned enough */
    double closed_condition; /* of the last closed form: sqrt(sum of its squared terms) / E1^2 */
} aa_metric_workspace;

void aa_metric_workspace_init(aa_metric_workspace *ws);
void aa_metric_workspace_free(aa_metric_workspace *ws);

/* How E1 is computed. AUTO: the closed form where the filter has one (piecewise polynomial)
 * and its estimated rounding error is below AA_E1_CLOSED_REL_ERROR relative, else the
 * quadrature. QUADRATURE: always the piecewise Gauss-Legendre sweep (the previous method, kept
 * as the independent check). CLOSED: the closed form without the fallback (benchmarks and the
 * tests that measure its error; filters without tables still use the quadrature). */
typedef enum aa_e1_method { AA_E1_AUTO, AA_E1_QUADRATURE, AA_E1_CLOSED } aa_e1_method;
/* The closed form is used when its estimated relative error of E1, 4 eps sqrt(sum of its squared
 * terms) / E1^2, is at most this: a quarter of the tests' tolerance (metric.c). */
#define AA_E1_CLOSED_REL_ERROR 2.5e-13

/* cos and sin of theta with the axis and diagonal directions exact (samples that tie at 0, 45,
 * 90 ... degrees tie in floating point too). Precompute once per angle. */
void aa_metric_direction(double theta, double *c, double *s);

/* E1 at one angle (radians). Returns AA_OK, AA_EINVAL (no samples, non-finite angle) or
 * AA_ENOMEM. Precondition: the weights sum to 1 (otherwise E1 is infinite; not checked). */
int aa_e1_at_angle(const aa_filter *f, const aa_sample *s, size_t n, double theta,
                   aa_metric_workspace *ws, double *e1);
/* The same for a direction from aa_metric_direction, with a method. */
int aa_e1_at_direction(const aa_filter *f, const aa_sample *s, size_t n, double ct, double st,
                       aa_e1_method method, aa_metric_workspace *ws, double *e1);
/* aa_e1_at_direction that also leaves the sorted projection in ws (p, w and index, sorted by
 * (p, index)) for a caller that reads it next (e1_smoothed.c's kink pairs). aa_e1_at_direction
 * itself sorts kernels of up to 16 samples on the stack and leaves ws's arrays unspecified. */
int aa_e1_sorted_at_direction(const aa_filter *f, const aa_sample *s, size_t n, double ct,
                              double st, aa_e1_method method, aa_metric_workspace *ws, double *e1);
/* E1 and its gradient. dx, dy, dw may each be NULL; arrays of n. */
int aa_e1_gradient_at_angle(const aa_filter *f, const aa_sample *s, size_t n, double theta,
                            aa_metric_workspace *ws, double *e1, double *dx, double *dy,
                            double *dw);
int aa_e1_gradient_at_direction(const aa_filter *f, const aa_sample *s, size_t n, double ct,
                                double st, aa_e1_method method, aa_metric_workspace *ws, double *e1,
                                double *dx, double *dy, double *dw);

/* E1 with its crossing kinks smoothed (e1_smoothed.c, docs/metric.md section 7), for the
 * optimizer's descent: E1^2 = S - sum_{i<j} w_i w_j |p_i - p_j| with S smooth, and each |d|
 * below kink_width (h, pixels) is replaced by the Huber function d^2/(2h) + h/2, which makes E1
 * continuously differentiable in the positions. e1 gets the exact E1 (AUTO), e1_smoothed the
 * smoothed one (the same when no two projections are closer than h; h = 0: exact; a negative
 * E1_h^2, possible for wide h, is taken as 0 and has no gradient). The gradient
 * (dx, dy, dw as aa_e1_gradient_at_direction, each may be NULL) is the smoothed one's. Errors as
 * aa_e1_at_direction, and AA_EINVAL for a negative or non-finite kink_width. */
int aa_e1_smoothed_at_direction(const aa_filter *f, const aa_sample *s, size_t n, double ct,
                                double st, double kink_width, aa_metric_workspace *ws, double *e1,
                                double *e1_smoothed);
int aa_e1_smoothed_gradient_at_direction(const aa_filter *f, const aa_sample *s, size_t n,
                                         double ct, double st, double kink_width,
                                         aa_metric_workspace *ws, double *e1, double *e1_smoothed,
                                         double *dx, double *dy, double *dw);

/* One kernel at na directions (dir_c/dir_s from aa_metric_direction, neighbouring directions
 * next to each other for the sort reuse): the kernel × angle block of whole-pattern E2. The
 * samples are copied once into the workspace's arrays, each direction is projected by one
 * vectorised loop and re-sorted from the previous direction's order (order.h). e1[na]
 * gets the same numbers as aa_e1_at_direction per direction (bit for bit: same sums, same
 * order). Errors as aa_e1_at_direction. */
int aa_e1_kernel_block(const aa_filter *f, const aa_sample *s, size_t n, const double *dir_c,
                       const double *dir_s, size_t na, aa_e1_method method, aa_metric_workspace *ws,
                       double *e1);
/* The same block with the gradient of sum_a factor[a] E1_a: e1[na] as above, and gx, gy, gw
 * (n each, each may be NULL) get += factor[a] * (dx, dy, dw of aa_e1_gradient_at_direction) for
 * every direction with factor[a] != 0 and E1_a > 0 (at E1 = 0 the gradient is not defined).
 * Directions with factor 0 cost what aa_e1_kernel_block costs. */
int aa_e1_gradient_kernel_block(const aa_filter *f, const aa_sample *s, size_t n,
                                const double *dir_c, const double *dir_s, size_t na,
                                const double *factor, aa_e1_method method, aa_metric_workspace *ws,
                                double *e1, double *gx, double *gy, double *gw);

typedef struct aa_metric_params {
    const aa_filter *filter;
    const aa_acuity *acuity;
    const double *angles_deg; /* NULL: the acuity table's default angle set */
    size_t angle_count;
    double lp; /* 0: no Lp norm; otherwise p >= 1 (L&A sec. 7 suggests 2 < p < inf) */
} aa_metric_params;

typedef struct aa_evaluation {
    double e2;
    size_t argmax_kernel;
    double argmax_angle_deg;
    double mean;    /* mean of W E1 over kernels x angles */
    double lp_norm; /* (mean of (W E1)^p)^(1/p), NaN if lp == 0 */
    size_t kernel_count;
    size_t angle_count;
    double *angles_deg; /* [angle_count] */
    double *weight;     /* [angle_count]: W(theta) */
    double *e1;         /* [kernel_count * angle_count], unweighted, kernel-major */
} aa_evaluation;

/* Validates params (angles finite, count <= AA_MAX_ANGLES, lp), evaluates every kernel at every
 * angle. Errors name "angles[i]" or "lp". */
int aa_evaluate(const aa_pattern *p, const aa_metric_params *params, aa_evaluation *out,
                aa_error *err);
void aa_evaluation_free(aa_evaluation *e);

/* Dense angle check: W(theta) E1(theta) on a grid of step_deg over [0, 180), W interpolated as
 * the table says. between_table_angles is true if the dense maximum exceeds the maximum over
 * the table angles by more than 1e-9 relative. */
typedef struct aa_dense_check {
    double step_deg;
    double max_weighted;
    size_t argmax_kernel;
    double argmax_angle_deg;
    double table_max; /* E2 over params' angle set */
    bool between_table_angles;
} aa_dense_check;
int aa_evaluate_dense(const aa_pattern *p, const aa_metric_params *params, double step_deg,
                      aa_dense_check *out, aa_error *err);

#endif
