/* Point distributions for seed patterns: uniform, jittered, N-rooks, Poisson disk (dart
 * throwing) and Lloyd relaxation (Keller & Heidrich 2001, appendix: Monte Carlo Voronoi
 * estimation with periodic boundaries), all on the torus [0, T)^2 so the tile repeats. */
#ifndef AA_SEEDS_H
#define AA_SEEDS_H

#include <stddef.h>

#include "aa_core.h"
#include "family.h"
#include "pattern.h"

/* Poisson disk: dart throwing on the torus at a stated radius r (pixels): no two points closer
 * than r. The default radius for spp points per pixel is AA_POISSON_RADIUS_FACTOR / sqrt(spp):
 * 0.365 px at 4 spp, which reproduces L&A Table 3's Poisson Min / Avg / Max for P(16,16,4)
 * (data/README.md; bench_table3). A throw that jams is restarted, up to AA_POISSON_THROWS
 * times, each with at most AA_POISSON_DARTS_PER_POINT darts per point. */
#define AA_POISSON_RADIUS_FACTOR 0.73
#define AA_POISSON_THROWS 8
#define AA_POISSON_DARTS_PER_POINT 400
#define AA_POISSON_GENERATOR "dart-throwing-torus"
double aa_poisson_default_radius(double spp);
/* The generator behind a distribution, as results record it: "dart-throwing-torus" (poisson),
 * "jittered-grid", "n-rooks", "lloyd-torus", "uniform". */
const char *aa_seed_generator_name(aa_seed_distribution distribution);

/* Writes count points in [0, tile)^2 to out. Returns AA_OK, AA_EINVAL (count 0, tile < 1) or
 * AA_ENOMEM (Lloyd's scratch). Deterministic for the rng state. Poisson uses the default radius. */
int aa_seed_points(aa_seed_distribution distribution, size_t count, int tile, aa_rng *rng,
                   aa_point *out);
/* The same with a stated Poisson-disk radius in pixels (0: the default); AA_ERANGE when the
 * radius leaves no room for count points. */
int aa_seed_points_radius(aa_seed_distribution distribution, size_t count, int tile,
                          double poisson_radius, aa_rng *rng, aa_point *out);

/* Lloyd relaxation on the torus in place: iterations steps, each estimating the Voronoi cells
 * from oversample * count uniform points (K&H use M = 10000 for N = 100; a few dozen suffice for
 * seeding). */
int aa_lloyd_torus(aa_point *pts, size_t count, int tile, int iterations, int oversample,
                   aa_rng *rng);

#endif
