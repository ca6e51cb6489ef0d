/* Placement configurations of the mirrored P(4,1+,n) family (Hasselgren et al. 2005, sec. 5 and
 * App. A): how many samples of the one mirrored pixel sit on each corner (0 or 1, cost 0.25),
 * on each edge (any number, cost 0.5 each) and inside (cost 1 each).
 *
 * Indices, in the pixel's coordinates relative to its centre (x right, y up), counterclockwise:
 *   corners[0] = (-0.5, -0.5), corners[1] = (+0.5, -0.5), corners[2] = (+0.5, +0.5),
 *   corners[3] = (-0.5, +0.5);
 *   edges[0] = bottom (y = -0.5), edges[1] = right (x = +0.5), edges[2] = top (y = +0.5),
 *   edges[3] = left (x = -0.5).
 * So a rotation by 90 degrees maps corner i to corner i+1 and edge i to edge i+1 (mod 4). */
#ifndef AA_ENUMERATE_H
#define AA_ENUMERATE_H

#include <stddef.h>

#include "aa_core.h"
#include "family.h"
#include "filter.h"
#include "pattern.h"

typedef struct aa_mirrored_config {
    int corners[4];
    int edges[4];
    int interior;
} aa_mirrored_config;

/* Cost in samples per pixel: 0.25 per corner, 0.5 per edge sample, 1 per interior sample. */
double aa_mirrored_config_cost(const aa_mirrored_config *c);
/* The lexicographically smallest image of c under the 8 symmetries of the square. */
void aa_mirrored_config_canonical(const aa_mirrored_config *c, aa_mirrored_config *out);
/* Applies symmetry g (0..7: rotation by g%4 quarter turns, then a mirror x -> -x if g >= 4). */
void aa_mirrored_config_transform(const aa_mirrored_config *c, int g, aa_mirrored_config *out);

#define AA_ENUMERATE_MAX_COST 16.0

/* All configurations of exactly this cost (a positive multiple of 0.25, at most
 * AA_ENUMERATE_MAX_COST), one per orbit of the square's symmetry group, in their canonical form,
 * sorted ascending (lexicographic on corners, edges, interior). *out is malloc'd (free it);
 * errors name field "cost". */
int aa_enumerate_mirrored(double cost, aa_mirrored_config **out, size_t *count, aa_error *err);

/* A seed pattern of the configuration: corners fixed, edge samples spread along their edge at
 * random (stratified when an edge holds several), interior samples from the seed distribution,
 * weights from the filter's impulse response h(x) h(y), normalised. */
int aa_mirrored_config_seed(const aa_mirrored_config *c, aa_seed_distribution distribution,
                            const aa_filter *filter, aa_rng *rng, aa_pattern *out, aa_error *err);

#endif
