/* Jitter sequence generators (jitter.h). */
#include <math.h>
#include <stdint.h>

#include "jitter.h"

double aa_radical_inverse(unsigned long index, unsigned base)
{
    /* Digits as an integer numerator over base^k, divided once: one rounding, so Halton points
     * are the nearest doubles whatever the base (for base^k below 2^63). */
    uint64_t num = 0, den = 1;
    unsigned long i = index;
    while (i > 0 && den <= UINT64_MAX / base / base) {
        num = num * base + i % base;
        den *= base;
        i /= base;
    }
    if (i == 0)
        return (double)num / (double)den;
    /* Not reached for indices below AA_JITTER_MAX_INDEX; the digit loop in double otherwise. */
    double r = (double)num / (double)den, f = 1.0 / (double)den;
    while (i > 0) {
        f /= base;
        r += f * (double)(i % base);
        i /= base;
    }
    return r;
}

static int check_common(size_t count, unsigned long start, double range, aa_error *err)
{
    if (count == 0)
        return aa_error_set(err, AA_EINVAL, "jitter.count", "the sequence needs at least 1 offset");
    if ((double)start + (double)count > (double)AA_JITTER_MAX_INDEX)
        return aa_error_set(err, AA_ERANGE, "jitter.start", "start + count must be at most %ld",
                            AA_JITTER_MAX_INDEX);
    if (!(isfinite(range) && range > 0 && range <= 16))
        return aa_error_set(err, AA_EINVAL, "jitter_range",
                            "jitter_range must be a number in (0, 16] pixels");
    return AA_OK;
}

int aa_jitter_halton(aa_point *out, size_t count, unsigned base_x, unsigned base_y,
                     unsigned long start, double range, aa_error *err)
{
    if (base_x < 2 || base_x > 1000)
        return aa_error_set(err, AA_EINVAL, "jitter.bases[0]", "a base must be in [2, 1000]");
    if (base_y < 2 || base_y > 1000)
        return aa_error_set(err, AA_EINVAL, "jitter.bases[1]", "a base must be in [2, 1000]");
    int rc = check_common(count, start, range, err);
    if (rc)
        return rc;
    for (size_t f = 0; f < count; f++) {
        out[f].x = (aa_radical_inverse(start + f, base_x) - 0.5) * range;
        out[f].y = (aa_radical_inverse(start + f, base_y) - 0.5) * range;
    }
    return AA_OK;
}

int aa_jitter_r2(aa_point *out, size_t count, unsigned long start, double range, aa_error *err)
{
    int rc = check_common(count, start, range, err);
    if (rc)
        return rc;
    /* The plastic number, and its reciprocal powers in long double so that n / g stays exact to
     * double precision for n up to AA_JITTER_MAX_INDEX. */
    const long double g = 1.32471795724474602596090885447809734L;
    const long double a1 = 1.0L / g, a2 = 1.0L / (g * g);
    for (size_t f = 0; f < count; f++) {
        long double n = (long double)(start + f);
        long double u = 0.5L + n * a1, v = 0.5L + n * a2;
        u -= floorl(u);
        v -= floorl(v);
        out[f].x = ((double)u - 0.5) * range;
        out[f].y = ((double)v - 0.5) * range;
    }
    return AA_OK;
}

void aa_jitter_rgss4(aa_point *out, double range)
{
    static const aa_point table[AA_JITTER_RGSS4_COUNT] = {
        {0.625, 0.125}, {0.125, 0.375}, {0.875, 0.625}, {0.375, 0.875}};
    for (size_t f = 0; f < AA_JITTER_RGSS4_COUNT; f++) {
        out[f].x = (table[f].x - 0.5) * range;
        out[f].y = (table[f].y - 0.5) * range;
    }
}

int aa_jitter_fsr2_phase_count(double scale)
{
    if (!isfinite(scale) || scale <= 0 || scale > 64)
        return 0;
    /* FSR2 computes this in float: 8 * pow(float ratio, 2) truncated. */
    float s = (float)scale;
    float v = 8.0f * powf(s, 2.0f);
    return (int)v;
}
