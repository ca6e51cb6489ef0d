/* Jitter sequences of temporal antialiasing: offsets in pixels from the pixel centre.
 * Generators write (u - 1/2) * range for u in [0, 1)^2, so range 1 gives [-0.5, 0.5)^2. */
#ifndef AA_JITTER_H
#define AA_JITTER_H

#include <stddef.h>

#include "aa_pattern.h"

#define AA_JITTER_MAX_INDEX 1000000000L /* start + count of the index generators */

/* Radical inverse of index in base (>= 2): the index's digits mirrored about the radix point,
 * rounded once to double (exact for base 2). */
double aa_radical_inverse(unsigned long index, unsigned base);

/* Halton(base_x, base_y) points start, start + 1, ..., start + count - 1. */
int aa_jitter_halton(aa_point *out, size_t count, unsigned base_x, unsigned base_y,
                     unsigned long start, double range, aa_error *err);
/* Roberts' R2 sequence: u_n = frac(1/2 + n / g), v_n = frac(1/2 + n / g^2), g the plastic
 * number (the real root of g^3 = g + 1), n = start ... start + count - 1. */
int aa_jitter_r2(aa_point *out, size_t count, unsigned long start, double range, aa_error *err);
/* Filament's RGSS x4 table (PostProcessManager::sRGSS4): (0.625, 0.125), (0.125, 0.375),
 * (0.875, 0.625), (0.375, 0.875), in this order; count 4. */
#define AA_JITTER_RGSS4_COUNT 4
void aa_jitter_rgss4(aa_point *out, double range);

/* The FSR2 rule: phase count = (int)(8 * scale^2), scale = display / render width
 * (ffxFsr2GetJitterPhaseCount). 0 for scale < 1/sqrt(8) or non-finite. */
int aa_jitter_fsr2_phase_count(double scale);

#endif
