/* PCG32 (O'Neill 2014): small, fast, explicit state, so every worker has its own stream and
 * results are reproducible from (seed, stream). */
#ifndef AA_RNG_H
#define AA_RNG_H

#include <stdint.h>

typedef struct aa_rng {
    uint64_t state, inc;
} aa_rng;

void aa_rng_seed(aa_rng *r, uint64_t seed, uint64_t stream);
uint32_t aa_rng_u32(aa_rng *r);
double aa_rng_uniform(aa_rng *r);             /* [0, 1) with 53 random bits */
uint32_t aa_rng_below(aa_rng *r, uint32_t n); /* unbiased [0, n) */

#endif
