/* A static scene rendered through the TAA loop of a temporal pattern (docs/temporal.md §9).
 *
 * Frame f of the loop reconstructs output pixel (i, j) from the scene sampled at its group's
 * frame-f samples (the frame pattern shifted by jitter offset f, and with a resolve the shifted
 * samples of its neighbourhood), weighted by their in-frame weights: F_f(i, j). The history
 * blends the frames per pixel:
 *  - steady state (every past period summed): S_p = sum_j w_j F_{(p - j) mod N}, computed as
 *    S_0 directly and then S_p = alpha F_p + (1 - alpha) S_{p-1} (box: the mean of the frames);
 *  - after a cut: H_1 = F_0, H_k = alpha F_{(k-1) mod N} + (1 - alpha) H_{k-1} (box: the mean of
 *    the last min(k, N) frames).
 * All of it is per pixel and linear, so the steady state of phase p equals the render of phase
 * p's kernels (aa_taa_phase_pattern) with the spatial renderer, to rounding.
 *
 * Output grid. Pixel (i, j) reads group (i mod T, j mod T) when the temporal pattern has T x T
 * groups, else group (j width + i) mod G (the spatial renderer's rule for patterns with no
 * known repetition), at (i + off, j + off), off = aa_output_offset(K) for the smallest K whose
 * block holds every group sample: the grid aa_taa_phase_pattern's patterns render on.
 *
 * Pixels whose footprint (every group sample) the scene is constant on get that constant in
 * every frame without sampling (raster_traverse.h); the others evaluate each group sample once
 * and feed all N frames from it, so a pixel costs N m scene evaluations plus O(N + K)
 * arithmetic, and memory stays O(N + K) per call, whatever N. */
#ifndef AA_TAA_RENDER_H
#define AA_TAA_RENDER_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_temporal.h"
#include "edge_histogram.h"
#include "image.h"
#include "scene.h"

typedef struct aa_taa {
    aa_scene scene;
    const aa_temporal *t;
    int tile;        /* T, or 0: groups assigned cyclically */
    int kernel_size; /* K of the phase patterns */
    double offset;   /* output point offset from the pixel corner */
    double extent;   /* largest |x|, |y| of a group sample */
    bool skip;       /* leave out pixels the scene is constant on (false: sample every pixel) */
} aa_taa;

/* t must outlive r. Errors: AA_EINVAL (empty temporal pattern). */
int aa_taa_init(aa_taa *r, const aa_scene *s, const aa_temporal *t, bool skip, aa_error *err);

/* The steady state and after-cut errors against reference (scene-sized, rendered at
 * r->offset), 0..255 scale as aa_diff_stats:
 *  - phase_sum_sq[p], phase_max_dev[p]: sum over pixels of (255 (S_p - ref))^2 and its max |.|;
 *  - cut_sum_sq[k - 1], k = 1..cut_count: the same for H_k;
 *  - flicker_step_sum_sq: sum over phases and pixels of (255 (S_p - S_{p-1 mod N}))^2 (the
 *    frame-to-frame difference of the static scene in steady state);
 *  - flicker_mean_sum_sq: sum over phases and pixels of (255 (S_p - mean_q S_q))^2 (the
 *    rendered counterpart of F1, docs/temporal.md §3). */
typedef struct aa_taa_stats {
    size_t phase_count, cut_count, pixels;
    double *phase_sum_sq, *phase_max_dev; /* [N] */
    double *cut_sum_sq;                   /* [K] */
    double flicker_step_sum_sq, flicker_mean_sum_sq;
    size_t pixels_sampled, samples_evaluated;
} aa_taa_stats;

/* progress (may be NULL) is called about once per image row with the fraction done; nonzero
 * cancels (AA_ECANCELED). Errors: AA_EINVAL (sizes, cut_count 0 or above
 * AA_TEMPORAL_MAX_CUT_FRAMES), AA_ENOMEM. */
int aa_taa_measure(const aa_taa *r, const aa_image *reference, size_t cut_count,
                   int (*progress)(void *user, double fraction), void *user, aa_taa_stats *out,
                   aa_error *err);
void aa_taa_stats_free(aa_taa_stats *s);

/* RMSE of a sum of squares over the image's pixels. */
double aa_taa_rmse(const aa_taa_stats *s, double sum_sq);

/* The image of frame f alone (F_f), and the steady-state image of phase p (S_p). */
int aa_taa_frame_image(const aa_taa *r, size_t f, aa_image *out, aa_error *err);
int aa_taa_phase_image(const aa_taa *r, size_t p, aa_image *out, aa_error *err);

/* Phase p's kernels as a spatial pattern (one kernel per group, every group sample kept, with
 * weight 0 where the phase gives it none, so that every phase has the same K and grid). Errors
 * of aa_pattern_from_kernels (more than AA_MAX_KERNEL_SAMPLES samples per group: AA_ERANGE). */
int aa_taa_phase_pattern(const aa_temporal *t, size_t p, aa_pattern *out, aa_error *err);

/* The flicker predicted by the edge model (docs/temporal.md §9): along an edge the squared
 * deviation of phase p from the mean over phases, summed over phases / N, is F1(theta)^2 per unit
 * length (§3) as E1^2 is for the error (docs/predict.md), so
 *   mean_rmse ~ 255 sqrt( sum_d L(d) mean_g F1_g(theta_d)^2 / (width height) ),
 * and step_rmse the same with the frame-to-frame F1 (aa_temporal_flicker_step_at_direction).
 * L(d) is the histogram's length in bin d with its locked edges (taken as evenly spread: a
 * locked edge whose offsets never move a sample across it flickers less). Errors: AA_ENOMEM. */
int aa_taa_predict_flicker(const aa_temporal *t, const aa_edge_histogram *h, double *mean_rmse,
                           double *step_rmse, aa_error *err);

#endif
