/* The supersampled reference: the scene filtered with the reference filter (Mitchell-Netravali
 * B = C = 1/3 over 4 x 4 pixels by default) at the same output points as the pattern render
 * (offset 0.5 for odd K, 1 for even K; raster.h).
 *
 * Estimator, for an output pixel o an edge's footprint crosses: the sum over the input pixels
 * p its footprint meets of
 *  - v * (G(p.x1 - o.x) - G(p.x0 - o.x)) * (G(p.y1 - o.y) - G(p.y0 - o.y)), exactly, when the
 *    scene is constant (v) on p (G the filter's CDF), else
 *  - (1/spp) sum over spp jittered samples s of p (a sqrt(spp) x sqrt(spp) stratified grid,
 *    one uniform point per stratum) of h(s.x - o.x) h(s.y - o.y) v(s).
 * Unbiased; each sample is evaluated once and feeds every output pixel whose footprint holds
 * it. Jitter depends only on (seed, input pixel, stratum): the same seed gives the same image
 * whatever the region or traversal order.
 *
 * Left out: output pixels whose footprint no edge crosses get the exact constant with no
 * sampling, and input pixels no edge crosses are integrated exactly (raster_traverse.h); the
 * cost grows with edge length, not area. skip = false samples every input pixel of every
 * output pixel (the baseline). */
#ifndef AA_REFERENCE_H
#define AA_REFERENCE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "aa_core.h"
#include "aa_pattern.h"
#include "image.h"
#include "scene.h"

#define AA_REFERENCE_MAX_SPP 4096

typedef struct aa_reference_params {
    int spp;                 /* samples per pixel: a square 1..4096; default 1024 */
    uint64_t seed;           /* default 1 */
    const aa_filter *filter; /* NULL: Mitchell-Netravali (1/3, 1/3), radius 2 */
    bool skip;               /* default true; false supersamples every pixel (baseline) */
    /* Called about once per input row with the fraction done; nonzero cancels. May be NULL. */
    int (*progress)(void *user, double fraction);
    void *user;
} aa_reference_params;

aa_reference_params aa_reference_params_default(void);

typedef struct aa_reference_stats {
    size_t pixels;              /* output pixels computed (the region) */
    size_t pixels_supersampled; /* output pixels an edge's footprint crosses */
    size_t input_pixels;        /* input pixels that were sampled */
    size_t samples;             /* scene evaluations */
} aa_reference_stats;

/* Errors: AA_EINVAL ("spp", size mismatch), AA_ENOMEM, AA_ECANCELED. */
int aa_render_reference(const aa_scene *s, const aa_reference_params *rp, double out_offset,
                        aa_image *out, const aa_rect *region, aa_reference_stats *st,
                        aa_error *err);

#endif
