/* Rendering a scene with a sampling pattern (L&A sec. 3, Fig. 3).
 *
 * The pattern is anchored at the image origin: tile sample t in tile cell (a, b) sits at
 * tile_samples[t] + T (a, b) in pixel coordinates. Coverage (the scene value) is evaluated
 * once per such global sample, however many kernels read it (shared border samples, mirrored
 * neighbours, overlapping K x K kernels), and output pixel (i, j) is the weighted sum of its
 * kernel's samples, kernel (i mod T, j mod T). The output point is the kernel block's centre:
 * (i + 0.5, j + 0.5) for odd K, (i + 1, j + 1) for even K (the grid shifted by half a pixel).
 * Patterns with no known repetition (tile == 0: explicit kernels, s not a square) assign the
 * kernels to pixels cyclically in row-major order and share nothing.
 *
 * Pixels whose kernel footprint (the box holding all kernel samples) the scene is constant on
 * get that constant exactly, without sampling (raster_traverse.h). */
#ifndef AA_RASTER_H
#define AA_RASTER_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_core.h"
#include "image.h"
#include "aa_pattern.h"
#include "scene.h"

typedef struct aa_raster_stats {
    size_t pixels;            /* output pixels computed (the region) */
    size_t pixels_sampled;    /* of which the traversal could not settle (an edge crosses the
                               * kernel footprint; for a one-point kernel the box test is the
                               * sample itself, so this can be 0) */
    size_t samples_evaluated; /* distinct global samples whose coverage was evaluated */
} aa_raster_stats;

/* Offset of the output point from the pixel's corner for a K x K kernel: 0.5 or 1. */
double aa_output_offset(int kernel_size);

/* Renders region (NULL: the whole image) of out, which must be scene-sized. skip = false
 * samples every pixel (baseline). Errors: AA_EINVAL (size mismatch, empty pattern),
 * AA_ENOMEM. */
int aa_render_pattern(const aa_scene *s, const aa_pattern *p, bool skip, aa_image *out,
                      const aa_rect *region, aa_raster_stats *st, aa_error *err);

#endif
