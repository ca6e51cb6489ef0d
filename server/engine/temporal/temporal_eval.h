/* E2, flicker and the after-cut curve of a temporal pattern (docs/temporal.md).
 *
 *  - E2: max over phases, groups and angles of W(theta) E1(theta) of the phase kernels; the
 *    per-phase E2 (max over groups and angles) and their mean over phases.
 *  - Flicker: with ghat_p the step response of phase p and gbar their mean,
 *      F1(theta) = sqrt( integral (1/N) sum_p (ghat_p(a) - gbar(a))^2 da ),
 *    exact: the phases share the sorted projections, so the integrand is piecewise constant
 *    (every term >= 0, no cancellation). F2 = max over groups and theta of W F1.
 *  - After a cut: E2 of the kernel k frames after a cut, k = 1..K, and the first k from which
 *    on every value up to K is within 5 % of the steady state of the phase it shows
 *    (phase (k - 1) mod N). */
#ifndef AA_TEMPORAL_EVAL_H
#define AA_TEMPORAL_EVAL_H

#include <stddef.h>

#include "aa_metric.h"
#include "temporal.h"

#define AA_TEMPORAL_MAX_CUT_FRAMES 4096
#define AA_TEMPORAL_SETTLE_TOLERANCE 0.05

typedef struct aa_temporal_evaluation {
    size_t phase_count, group_count, angle_count;
    double e2; /* worst phase */
    size_t argmax_phase, argmax_group;
    double argmax_angle_deg;
    double mean_phase_e2;
    double *phase_e2;   /* [N] */
    double *angles_deg; /* [A] */
    double *weight;     /* [A] W(theta) */
    double *e1;         /* [N][G][A], unweighted */
    double f2;
    size_t f2_group;
    double f2_angle_deg;
    double *f1; /* [G][A], unweighted */
    size_t cut_count;
    double *after_cut;        /* [K]: E2 after k = 1..K frames */
    long frames_to_settle;    /* first k (1-based) within 5 % from there on; -1 if none up to K */
    double effective_samples; /* 1 / sum of the age weights squared */
} aa_temporal_evaluation;

/* cut_frames: K, 0 for the default 4 N (capped at AA_TEMPORAL_MAX_CUT_FRAMES). Errors name
 * "angles[i]", "cut_frames" or the pattern ("temporal"). */
int aa_temporal_evaluate(const aa_temporal *t, const aa_metric_params *params, size_t cut_frames,
                         aa_temporal_evaluation *out, aa_error *err);
void aa_temporal_evaluation_free(aa_temporal_evaluation *e);

/* F1 of one group at one direction (cos, sin), and its derivative in each sample's projection
 * (dp: the group's count, or NULL). Errors: AA_ENOMEM. */
int aa_temporal_flicker_at_direction(const aa_temporal *t, size_t g, double ct, double st,
                                     double *f1, double *dp);

/* The frame-to-frame counterpart of F1 at one direction: sqrt( integral (1/N) sum_p
 * (ghat_p(a) - ghat_{p-1}(a))^2 da ), the step responses of consecutive phases (exact as F1 is:
 * the jumps are the age weights' differences). Errors: AA_ENOMEM. */
int aa_temporal_flicker_step_at_direction(const aa_temporal *t, size_t g, double ct, double st,
                                          double *f1);

#endif
