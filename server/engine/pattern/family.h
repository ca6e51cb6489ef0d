/* Pattern families P(s, r, n) and seed patterns for them (L&A sec. 3, 5; Keller & Heidrich
 * appendix for Lloyd relaxation on the torus). */
#ifndef AA_FAMILY_H
#define AA_FAMILY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "aa_core.h"
#include "filter.h"
#include "pattern.h"

typedef struct aa_family {
    int tile;        /* T: s = T^2 */
    int kernel_size; /* K: r = K^2 */
    bool border;     /* r+ */
    bool mirrored;   /* P(4,1+,n) built by mirroring one pixel (Hasselgren App. A) */
    double cost;     /* n: samples per pixel; for P(4,1+,n) a multiple of 0.25 */
    char label[48];  /* canonical "P(4,1+,2)" */
} aa_family;

/* Parses "P(s,r,n)" / "P(s,r+,n)" with s in {1, 4, 16, ...} (perfect squares) and r in
 * {1, 4, 16} (K^2). P(4,1+,n) means the mirrored family. Errors name field "family". */
int aa_family_parse(const char *text, aa_family *out, aa_error *err);

typedef enum aa_seed_distribution {
    AA_SEED_UNIFORM,  /* uniform random in each pixel */
    AA_SEED_JITTERED, /* one sample per stratum of a jittered grid */
    AA_SEED_NROOKS,   /* N-rooks within each pixel */
    AA_SEED_POISSON,  /* Poisson disk (dart throwing on the torus) */
    AA_SEED_LLOYD     /* Lloyd relaxation on the torus */
} aa_seed_distribution;

int aa_seed_distribution_parse(const char *name, aa_seed_distribution *out);
const char *aa_seed_distribution_name(aa_seed_distribution k);

/* A random seed pattern of the family: positions from the distribution, weights from the
 * filter's impulse response (normalised). For the mirrored family a random placement
 * configuration of the right cost is drawn (corner 0.25, edge 0.5, interior 1). */
int aa_family_seed(const aa_family *family, aa_seed_distribution distribution,
                   const aa_filter *filter, aa_rng *rng, aa_pattern *out, aa_error *err);
/* The same with a stated Poisson-disk radius in pixels for tiled families (0: the default,
 * aa_poisson_default_radius; the mirrored family always uses the default). A radius with no
 * room for the family's samples is AA_ERANGE naming "poisson_radius". */
int aa_family_seed_radius(const aa_family *family, aa_seed_distribution distribution,
                          double poisson_radius, const aa_filter *filter, aa_rng *rng,
                          aa_pattern *out, aa_error *err);

#endif
