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
 *  - Above N = 8 (exponential blend) the order is searched by pairwise swaps instead: sweeps
 *    over every pair (i, j), a swap kept when the true objective drops, until a sweep keeps none
 *    or swap_sweeps sweeps ran.
 * Reproducible when bounded by max_starts and max_seconds is 0. */
#ifndef AA_TEMPORAL_OPTIMIZE_H
#define AA_TEMPORAL_OPTIMIZE_H

#include <stddef.h>
#include <stdint.h>

#include "aa_metric.h"
#include "temporal.h"

/* What the progress callback sees: after every start (start >= 0, its figures set) and within
 * starts (start -1: only the fractions and counts), so that a caller can cancel promptly. */
typedef struct aa_temporal_opt_progress {
    double fraction; /* of the budget: starts or seconds, whichever is further */
    long start;      /* the start that just ended, or -1 */
    int start_from;  /* 0 the given sequence, 1 uniform random, 2 a hop from the best */
    double start_initial_score, start_score, start_e2, start_f2; /* the start's, when start >= 0 */
    double best_score, best_e2;                                  /* so far (INFINITY: none yet) */
    const aa_point *best;                                        /* [N], so far (NULL: none) */
    long starts, evaluations;
    double seconds;
} aa_temporal_opt_progress;

/* Nonzero: stop (aa_temporal_optimize returns AA_ECANCELED). */
typedef int (*aa_temporal_opt_progress_fn)(void *user, const aa_temporal_opt_progress *p);

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
    int swap_sweeps; /* N > 8: pairwise swap sweeps per start; 0: 4, < 0: no order search */
    aa_clock clock;  /* of max_seconds and the reported seconds (fn NULL: monotonic) */
    aa_temporal_opt_progress_fn progress; /* may be NULL */
    void *progress_user;
} aa_temporal_opt_params;

typedef struct aa_temporal_opt_result {
    double score;     /* of best: E2 + lambda F2 */
    double e2, f2;    /* of best */
    long starts;      /* run */
    long evaluations; /* objective and gradient evaluations */
    double seconds;
    double first_score; /* the first start's result */
} aa_temporal_opt_result;

/* best: [N]. Errors as aa_temporal_build, AA_EINVAL for a bad range or no bound, AA_ECANCELED
 * when the progress callback asked to stop (best then holds the best so far, if any start
 * ended: result->starts > 0). */
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
