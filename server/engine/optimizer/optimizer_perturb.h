/* Internal to the optimizer: the move of the iterated local search (optimizer_perturb.c), apart
 * so that tests can check it. Not part of the public API. */
#ifndef AA_OPTIMIZER_PERTURB_H
#define AA_OPTIMIZER_PERTURB_H

#include <stdbool.h>

#include "aa_core.h"
#include "aa_pattern.h"
#include "optimizer_state.h" /* OPT_SITE_MARGIN */

/* The jittered neighbour of a tile pattern p: every sample moved by N(0, sigma^2) pixels in x
 * and y on the tile's torus [0, T)^2 and kept OPT_SITE_MARGIN inside the pixel it lands in, as
 * the descent keeps interior samples (so a sample may change pixels; the sample count, and so
 * the cost, stays); `redraw` distinct samples chosen at random are drawn afresh, uniformly in
 * their pixel; weights from filter's impulse response. keep_pixels: each sample is jittered
 * inside its own pixel instead (aa_perturb_params). *out receives a new pattern (tile_samples in
 * p's order). */
int opt_jittered_neighbour(const aa_pattern *p, double sigma, int redraw, bool keep_pixels,
                           const aa_filter *filter, aa_rng *rng, aa_pattern *out, aa_error *err);

#endif
