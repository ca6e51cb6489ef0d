/* The classic patterns, with citations and exact coordinates (data/presets.json). Static const
 * data: safe to read from any thread. */
#ifndef AA_PRESETS_H
#define AA_PRESETS_H

#include <stddef.h>

#include "pattern.h"

typedef struct aa_preset {
    const char *name;
    const char *family;
    double cost_spp;
    const char *source;
    const char *note;     /* NULL if none */
    double published_e2;  /* Laine & Aila Table 2, or NaN if the paper does not list it */
    aa_pattern_form form; /* AA_FORM_KERNELS or AA_FORM_MIRRORED */
    size_t kernel_count;  /* kernels form */
    size_t sample_count;  /* samples of the one kernel / the mirrored pixel */
    const aa_sample *samples;
} aa_preset;

size_t aa_preset_count(void);
const aa_preset *aa_preset_at(size_t i);
const aa_preset *aa_preset_find(const char *name); /* NULL if unknown */
int aa_pattern_from_preset(aa_pattern *p, const aa_preset *preset, aa_error *err);

#endif
