/* A first optimizer of temporal jitter sequences (docs/temporal.md section 7): moves the N
 * offsets with the frame weights fixed by the blend, toward the smallest worst-phase E2.
 *
 * Each start descends a smooth stand-in for the maximum, the power mean
 *   M_q = ( mean over phases, groups, angles of (W E1)^q )^(1/q),
 * q raised from 8 to 2048, by gradient steps with backtracking (the metric's exact E1 gradient,
 * aa_e1_gradient_kernel_block, summed over the samples each offset moves) and the offsets
 * clamped to the jitter square; then, for N <= 8 under an exponential blend, every cyclic order
 * of the offsets (offset 0 kept first: (N-1)! orders) is evaluated and the best kept, and the
 * descent runs again. The true objective decides which start wins. Starts are random (uniform
 * in the square) except the first, which is the given sequence when there is one, and, with
 * hop > 0, every other start, which moves each offset of the best so far by up to hop * range.
 *  - With a resolve the frame weights h(dx) h(dy) / sum move with the offsets too: their
 *    derivative (h' by central differences, step 1e-6) enters through the metric's weight
 *    gradient.
 *  - With a flicker weight lambda the objective is E2 + lambda F2, or E2 + lambda max(0, F2 -
 *    cap) with a cap (F1's gradient: temporal_flicker.h; without a resolve only).
 *  - With a grid step (hardware and engines store offsets at finite precision) each start ends
 *    by snapping the offsets to the nearest multiples inside the square and moving single
 *    coordinates by one step while the true objective drops.
 * Reproducible when bounded by max_starts and max_seconds is 0. */
#ifndef AA_TEMPORAL_OPTIMIZE_H
#define AA_TEMPORAL_OPTIMIZE_H

#include <stddef.h>
#include <stdint.h>

#include "aa_metric.h"
#include "temporal.h"

typedef struct aa_temporal_opt_params {
    size_t count; /* N */
    aa_blend blend;
    double range;                       /* offsets in [-range/2, range/2]^2 */
    const aa_pattern *frame;            /* NULL: one sample at the pixel centre */
    const aa_temporal_resolve *resolve; /* NULL: none (with one, flicker_weight must be 0) */
    const aa_metric_params *metric;
    const aa_point *start; /* [N] or NULL */
    long max_starts;       /* 0: unbounded (then max_seconds must be > 0) */
    double max_seconds;    /* 0: unbounded */
    int descent_steps;     /* per q level; 0: 60 */
    double hop;            /* > 0: every other start perturbs the best by up to hop * range */
    double grid_step;      /* > 0: offsets on multiples of it (e.g. 1/16 px), see above */
    double flicker_weight; /* lambda: the objective is E2 + lambda F2 (power means in descent) */
    double flicker_cap;    /* > 0: E2 + lambda max(0, F2 - cap) instead (a penalty above a cap) */
    uint64_t seed;
} aa_temporal_opt_params;

typedef struct aa_temporal_opt_result {
    double score;     /* of best: E2 + lambda F2 */
    double e2, f2;    /* of best */
    long starts;      /* run */
    long evaluations; /* objective and gradient evaluations */
    double seconds;
    double first_score; /* the first start's result */
} aa_temporal_opt_result;

/* best: [N]. Errors as aa_temporal_build, and AA_EINVAL for a bad range or no bound. */
int aa_temporal_optimize(const aa_temporal_opt_params *p, aa_point *best,
                         aa_temporal_opt_result *result, aa_error *err);

/* Worst-phase E2 of a sequence under the blend (no after-cut curve, no flicker). */
int aa_temporal_e2(const aa_point *jitter, size_t n, aa_blend blend, const aa_pattern *frame,
                   const aa_temporal_resolve *resolve, const aa_metric_params *metric, double *e2,
                   aa_error *err);

/* The descent's objective M_q (plus lambda times the flicker's, as the optimizer forms it) of a
 * sequence and its gradient per offset (grad: [n], or NULL): what the tests check against
 * central differences. */
int aa_temporal_power_mean(const aa_point *jitter, size_t n, aa_blend blend,
                           const aa_pattern *frame, const aa_temporal_resolve *resolve,
                           const aa_metric_params *metric, double q, double flicker_weight,
                           double *value, aa_point *grad, aa_error *err);

#endif
