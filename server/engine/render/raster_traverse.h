/* Tiled traversal with early in/out (the rasterisation lecture's "modern approach"): blocks of
 * output pixels whose joint footprint the scene is constant on get that constant exactly and
 * are never sampled; subdivision continues down to single pixels, which are marked for
 * sampling when an edge crosses their footprint. Shared by the pattern renderer and the
 * reference. */
#ifndef AA_RASTER_TRAVERSE_H
#define AA_RASTER_TRAVERSE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "image.h"
#include "scene.h"

#define AA_TRAVERSE_BLOCK 32 /* side of the top-level blocks, pixels */

/* Output pixel (i, j) is reconstructed at (i + offset, j + offset) and reads the scene on the
 * closed box of half-width extent around that point. For every pixel of region: either writes
 * the constant to out and mask 0, or sets mask 1 (mask is region-local, row-major, of
 * aa_rect_area(region) bytes). skip = false marks every pixel (the supersample-everything
 * baseline). Returns the number of marked pixels. */
size_t aa_traverse_footprints(const aa_scene *s, aa_rect region, double offset, double extent,
                              bool skip, aa_image *out, uint8_t *mask);

#endif
