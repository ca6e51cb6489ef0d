/* Optimising a pattern for a scene (issue 18 point 4): the edge model's predicted RMSE of a
 * scene (docs/predict.md) as an objective with its analytic gradient, optionally blended with
 * the acuity-weighted E2 so that the worst case still counts, and a local descent on it.
 *
 * Scene term (the predictor's quantity, no rendering):
 *   S = 255 · sqrt( Σ_d L_d · mean_k E1_k(θ_d)² / N ),  θ_d = d degrees, d = 0..179,
 * E1 unweighted (W ≡ 1) with the render's reference filter, L_d the scene's edge length per 1°
 * bin of the normal angle (pixel-locked edges folded into their bins: the optimizer treats them
 * as spread offsets; the reported predicted_rmse is aa_predict_rmse's, which sums them exactly).
 *   dS/dE1_k(θ_d) = 255 · L_d · E1_k(θ_d) / (K · sqrt(N · Σ_d L_d mean_k E1_k²)).
 *
 * Blend (α = blend in [0, 1]):
 *   F = (1 − α) · S / S_ref + α · E2 / E2_ref,   (S: the exact term when one is given, below)
 * S_ref and E2_ref fixed per run (the job uses the scene term and E2 of the best global-E2
 * pattern it found first, so F = 1 there and F < 1 means better in the blend). α = 0: the scene
 * alone; α = 1: E2 alone. The descent minimises a smooth stand-in for E2, the power mean
 * (mean over kernels × angles of (W E1)^p)^(1/p) with p = AA_SCENE_E2_POWER (≤ E2, and within a
 * factor (kernels·angles)^(1/p) of it); every F reported and every "best" kept uses the true E2.
 *
 * This library (optimizer) does not see render's edge histograms: callers pass L as an array
 * (aa_edge_histogram_folded in render gives it). */
#ifndef AA_OBJECTIVE_SCENE_H
#define AA_OBJECTIVE_SCENE_H

#include <stddef.h>

#include "aa_core.h"
#include "aa_metric.h"
#include "aa_pattern.h"
#include "optimizer.h"

#define AA_SCENE_BINS 180
#define AA_SCENE_E2_POWER 32.0

typedef struct aa_scene_objective {
    const aa_filter *filter; /* the render's reference filter (NULL: the default) */
    double length[AA_SCENE_BINS];
    double pixels; /* N */
    /* Optional: the scene term as reported, e.g. aa_predict_rmse, which sums pixel-locked edges
     * exactly (their sampled sums have no useful position gradient: they are piecewise constant
     * in the positions). NULL: S itself. The descent steps on S's gradient and keeps its best by
     * F with this term, so a step that S likes but the exact sums do not is never reported. */
    int (*exact)(void *user, const aa_pattern *p, double *value, aa_error *err);
    void *exact_user;
} aa_scene_objective;

/* The scene term S of p, and (when gx is not NULL) its gradient with respect to every kernel
 * sample: gx, gy, gw each hold aa_pattern_total_kernel_samples(p) entries, kernel by kernel;
 * gw is projected onto Σ w = 1 per kernel. ws: scratch (one per thread). Errors: AA_EINVAL
 * (no edges, N <= 0, an empty kernel), AA_ENOMEM. */
int aa_scene_objective_eval(const aa_scene_objective *o, const aa_pattern *p,
                            aa_metric_workspace *ws, double *value, double *gx, double *gy,
                            double *gw, aa_error *err);

typedef struct aa_scene_optimize_params {
    aa_optimize_params local; /* mode, max_iterations, max_seconds, stall, rel_tolerance, clock;
                                 grid_bits must be 0 */
    double blend;             /* α in [0, 1] */
    double scene_ref;         /* S_ref (of the reported term); <= 0: the seed's */
    double e2_ref;            /* E2_ref; <= 0: the seed's */
} aa_scene_optimize_params;

typedef struct aa_scene_optimize_result {
    double objective; /* F of the best */
    double scene;     /* its S: o->exact's value when set, else the folded bins' */
    double e2;        /* its true E2 */
    double initial_objective, initial_scene, initial_e2;
    double scene_ref, e2_ref;
    long iterations, evaluations;
    double seconds;
} aa_scene_optimize_result;

/* Progress: the best so far; nonzero from the callback cancels (AA_ECANCELED, *best holds the
 * best so far). Called at most every 10 ms and once at the end. */
typedef struct aa_scene_progress {
    double seconds;
    long iterations;
    double objective, scene, e2; /* of the best */
    const aa_pattern *best;      /* valid during the call only */
} aa_scene_progress;
typedef int (*aa_scene_progress_fn)(void *user, const aa_scene_progress *progress);

/* Local descent on F from seed: projected gradient steps on the free variables of the mode
 * (the optimizer's sites, sharing and mirroring hold by construction, weights renormalised per
 * kernel), the step grown 1.2× on acceptance and halved on rejection of a trial that does not
 * lower the smooth F; stops when the best true F has not fallen by rel_tolerance in
 * stall_iterations steps, at max_iterations, at max_seconds, or when the step underflows.
 * *best receives a new pattern (free it). Deterministic except for the time budget. */
int aa_optimize_scene(const aa_pattern *seed, const aa_metric_params *metric,
                      const aa_scene_objective *o, const aa_scene_optimize_params *params,
                      aa_scene_progress_fn progress, void *user, aa_pattern *best,
                      aa_scene_optimize_result *result, aa_error *err);

/* F, S and true E2 of a pattern without descending (the references as in params). */
int aa_scene_objective_blend(const aa_pattern *p, const aa_metric_params *metric,
                             const aa_scene_objective *o, double blend, double scene_ref,
                             double e2_ref, double *objective, double *scene, double *e2,
                             aa_error *err);

#endif
