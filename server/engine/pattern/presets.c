#include "presets.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "presets_data.inc"

size_t aa_preset_count(void)
{
    return sizeof presets / sizeof presets[0];
}

const aa_preset *aa_preset_at(size_t i)
{
    return i < aa_preset_count() ? &presets[i] : NULL;
}

const aa_preset *aa_preset_find(const char *name)
{
    for (size_t i = 0; i < aa_preset_count(); i++)
        if (!strcmp(presets[i].name, name))
            return &presets[i];
    return NULL;
}

int aa_pattern_from_preset(aa_pattern *p, const aa_preset *preset, aa_error *err)
{
    if (preset->form == AA_FORM_MIRRORED)
        return aa_pattern_from_mirrored(p, preset->samples, preset->sample_count, 0, err);
    const aa_sample *k = preset->samples;
    size_t n = preset->sample_count;
    return aa_pattern_from_kernels(p, &k, &n, 1, 0, err);
}
