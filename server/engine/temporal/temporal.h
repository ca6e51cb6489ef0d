/* Temporal antialiasing as weighted kernels (docs/temporal.md).
 *
 * A temporal pattern has N jitter offsets o_f (pixels from the pixel centre), f = 0..N-1. Frame f
 * takes the samples of a per-frame spatial pattern (default: one sample at the pixel centre)
 * shifted by o_f. Each frame is reconstructed either by the frame pattern's own kernels, or by a
 * resolve filter h: every shifted sample of the (2R+1)^2 pixels around the output pixel weighs
 * h(dx) h(dy) (d its offset from the output pixel's centre), normalised per frame. The history
 * blends the frames: in steady state (static scene, no clamping) phase p's newest frame is f = p
 * and the frame j frames older weighs
 *     exponential: alpha (1 - alpha)^j / (1 - (1 - alpha)^N)   (every past period summed),
 *     box:         1 / N.
 * Phase p's kernel is the union of the N frames' samples, each with its frame weight times its
 * per-frame weight. All phases share the sample positions: only the weights differ.
 *
 * Groups. The frame pattern has s output pixels (its kernels, or the T x T pixels of its tile
 * with a resolve); each is one group of N phase kernels that share their positions. */
#ifndef AA_TEMPORAL_H
#define AA_TEMPORAL_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_pattern.h"

#define AA_TEMPORAL_MAX_PHASES 1024
#define AA_TEMPORAL_MAX_RESOLVE_RADIUS 4
#define AA_TEMPORAL_MIN_ALPHA 1e-6

typedef enum aa_blend_kind { AA_BLEND_EXPONENTIAL, AA_BLEND_BOX } aa_blend_kind;

typedef struct aa_blend {
    aa_blend_kind kind;
    double alpha; /* exponential: the newest frame's share, in (0, 1] */
} aa_blend;

typedef struct aa_temporal_resolve {
    aa_filter filter; /* h, applied separably: h(dx) h(dy) */
    int radius;       /* pixels read around the output pixel: (2 radius + 1)^2 */
} aa_temporal_resolve;

typedef struct aa_temporal_spec {
    size_t count;                       /* N */
    const aa_point *jitter;             /* [N] */
    const aa_pattern *frame;            /* NULL: one sample at the pixel centre */
    const aa_temporal_resolve *resolve; /* NULL: the frame pattern's kernels */
    aa_blend blend;
} aa_temporal_spec;

typedef struct aa_temporal_group {
    size_t count;     /* samples: every frame's */
    aa_point *pos;    /* [count], relative to the output point */
    size_t *frame;    /* [count]: the frame (jitter index) of each sample */
    double *in_frame; /* [count]: the sample's weight within its frame (sums to 1 per frame) */
} aa_temporal_group;

typedef struct aa_temporal {
    size_t phase_count; /* N */
    aa_blend blend;
    double *age_weight; /* [N]: weight of the frame j frames older than the newest */
    size_t group_count;
    aa_temporal_group *groups;
    double cost_spp; /* samples rendered per pixel per frame */
} aa_temporal;

/* Weights of frames 0..n-1 frames old under the blend, over a period of n. Exponential:
 * alpha b^j / (1 - b^n), b = 1 - alpha, with b^j and 1 - b^n from log1p/expm1 (relative error
 * a few ulp for alpha down to AA_TEMPORAL_MIN_ALPHA). Errors name "blend.alpha". */
int aa_blend_weights(const aa_blend *blend, size_t n, double *out, aa_error *err);
/* After a cut, k >= 1 frames in: weight of the i-th frame since the cut, i = 1..k (out[i-1]).
 * Exponential: frame 1 (1 - alpha)^(k-1), frame i > 1 alpha (1 - alpha)^(k-i). Box over period
 * n: 1/k each while k < n, then 1/n for the last n frames. */
int aa_blend_after_cut_weights(const aa_blend *blend, size_t n, size_t k, double *out,
                               aa_error *err);
/* 1 / sum w^2 over the weights: (2 - alpha)/alpha for an exponential blend as n grows. */
double aa_effective_samples(const double *w, size_t n);

/* Expands the spec. Errors name "jitter[i]", "blend.alpha", "resolve.radius", "frame_pattern"
 * (relative to the temporal object). */
int aa_temporal_build(aa_temporal *t, const aa_temporal_spec *spec, aa_error *err);
void aa_temporal_free(aa_temporal *t);

/* Phase p's kernel of group g (samples with weight exactly 0 left out: alpha = 1 gives the
 * one-frame kernel). out holds group->count samples; returns how many were written. */
size_t aa_temporal_phase_kernel(const aa_temporal *t, size_t g, size_t p, aa_sample *out);
/* The kernel after a cut, k >= 1 frames in (the first frame after the cut is jitter 0): the
 * group's samples with frame f weighing the sum of the after-cut weights of the frames that
 * used jitter f. weights: scratch of k doubles. Returns the count written. */
size_t aa_temporal_cut_kernel(const aa_temporal *t, size_t g, size_t k, double *weights,
                              double *frame_sum, aa_sample *out);

#endif
