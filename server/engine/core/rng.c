#include "rng.h"

#include <assert.h>

void aa_rng_seed(aa_rng *r, uint64_t seed, uint64_t stream)
{
    r->state = 0;
    r->inc = (stream << 1u) | 1u;
    aa_rng_u32(r);
    r->state += seed;
    aa_rng_u32(r);
}

uint32_t aa_rng_u32(aa_rng *r)
{
    uint64_t old = r->state;
    r->state = old * 6364136223846793005ULL + r->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
}

double aa_rng_uniform(aa_rng *r)
{
    uint64_t hi = aa_rng_u32(r) >> 5, lo = aa_rng_u32(r) >> 6; /* 27 + 26 bits */
    return (double)(hi * 67108864.0 + lo) / 9007199254740992.0;
}

uint32_t aa_rng_below(aa_rng *r, uint32_t n)
{
    assert(n > 0); /* [0, 0) is empty: the caller checks its count first */
    uint32_t threshold = (uint32_t)(-n) % n;
    for (;;) {
        uint32_t v = aa_rng_u32(r);
        if (v >= threshold)
            return v % n;
    }
}
