/* Point distributions for seed patterns: uniform, jittered, N-rooks, Poisson disk (dart
 * throwing) and Lloyd relaxation (Keller & Heidrich 2001, appendix: Monte Carlo Voronoi
 * estimation with periodic boundaries), all on the torus [0, T)^2 so the tile repeats. */
#ifndef AA_SEEDS_H
#define AA_SEEDS_H

#include <stddef.h>

#include "aa_core.h"
#include "family.h"
#include "pattern.h"

/* Writes count points in [0, tile)^2 to out. Returns AA_OK, AA_EINVAL (count 0, tile < 1) or
 * AA_ENOMEM (Lloyd's scratch). Deterministic for the rng state. */
int aa_seed_points(aa_seed_kind kind, size_t count, int tile, aa_rng *rng, aa_point *out);

/* Lloyd relaxation on the torus in place: iterations steps, each estimating the Voronoi cells
 * from oversample * count uniform points (K&H use M = 10000 for N = 100; a few dozen suffice for
 * seeding). */
int aa_lloyd_torus(aa_point *pts, size_t count, int tile, int iterations, int oversample,
                   aa_rng *rng);

#endif
