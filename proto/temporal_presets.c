/* Temporal presets: sequences and constants as their sources state them, nothing else
 * (docs/temporal.md section 4). */
#include "codec_temporal.h"

static const proto_temporal_preset presets[] = {
    {"halton23-8",
     "{\"jitter\":{\"generator\":\"halton\",\"bases\":[2,3],\"start\":1,\"count\":8},"
     "\"blend\":{\"kind\":\"exponential\",\"alpha\":0.1}}",
     "Halton(2,3) from index 1 minus 1/2 as in AMD FSR2's ffxFsr2GetJitterOffset (halton(i % N "
     "+ 1, 2) - 0.5), 8 phases; alpha 0.1 is the habitual blend factor named in issue 30"},
    {"halton23-16",
     "{\"jitter\":{\"generator\":\"halton\",\"bases\":[2,3],\"start\":1,\"count\":16},"
     "\"blend\":{\"kind\":\"exponential\",\"alpha\":0.1}}",
     "Halton(2,3) from index 1 minus 1/2 (FSR2's generator), 16 phases; alpha 0.1 as issue 30"},
    {"fsr2-1.5x",
     "{\"jitter\":{\"generator\":\"fsr2\",\"scale\":1.5},"
     "\"blend\":{\"kind\":\"exponential\",\"alpha\":0.1}}",
     "FSR2 rule: (int)(8 * 1.5^2) = 18 phases of Halton(2,3) from index 1 "
     "(ffxFsr2GetJitterPhaseCount), evaluated at native resolution; FSR2's own accumulation is "
     "not a fixed alpha: alpha 0.1 as issue 30"},
    {"fsr2-1.7x",
     "{\"jitter\":{\"generator\":\"fsr2\",\"scale\":1.7},"
     "\"blend\":{\"kind\":\"exponential\",\"alpha\":0.1}}",
     "FSR2 rule: (int)(8 * 1.7^2) = 23 phases of Halton(2,3) from index 1, native resolution, "
     "alpha 0.1 as issue 30"},
    {"fsr2-2x",
     "{\"jitter\":{\"generator\":\"fsr2\",\"scale\":2},"
     "\"blend\":{\"kind\":\"exponential\",\"alpha\":0.1}}",
     "FSR2 rule: 8 * 2^2 = 32 phases of Halton(2,3) from index 1, native resolution, alpha 0.1 "
     "as issue 30"},
    {"fsr2-3x",
     "{\"jitter\":{\"generator\":\"fsr2\",\"scale\":3},"
     "\"blend\":{\"kind\":\"exponential\",\"alpha\":0.1}}",
     "FSR2 rule: 8 * 3^2 = 72 phases of Halton(2,3) from index 1, native resolution, alpha 0.1 "
     "as issue 30"},
    {"urp-like",
     "{\"jitter\":{\"generator\":\"halton\",\"bases\":[2,3],\"start\":1,\"count\":8},"
     "\"resolve\":{\"filter\":{\"name\":\"gaussian\",\"sigma\":0.5,\"radius\":2},\"radius\":1},"
     "\"blend\":{\"kind\":\"exponential\",\"alpha\":0.1}}",
     "the setup issue 30 calls Unity URP-like (Halton, alpha 0.1, Gaussian resolve over 3 x 3); "
     "the Gaussian's sigma 0.5 is aalab's default Gaussian, not a value read from URP"},
    {"filament-rgss4",
     "{\"jitter\":{\"generator\":\"rgss4\"},\"blend\":{\"kind\":\"exponential\",\"alpha\":0.1}}",
     "Filament PostProcessManager::sRGSS4 (0.625,0.125) (0.125,0.375) (0.875,0.625) "
     "(0.375,0.875) minus 1/2; feedback 0.1 as issue 30"},
    {"filament-halton8",
     "{\"jitter\":{\"generator\":\"halton\",\"bases\":[2,3],\"start\":409,\"count\":8},"
     "\"blend\":{\"kind\":\"exponential\",\"alpha\":0.1}}",
     "Filament's halton(i, b) adds 409 to i (\"skipping a bunch of entries makes the average of "
     "the sequence closer to 0.5\"), i = 0..7, minus 1/2; feedback 0.1 as issue 30"},
    {"filament-halton16",
     "{\"jitter\":{\"generator\":\"halton\",\"bases\":[2,3],\"start\":409,\"count\":16},"
     "\"blend\":{\"kind\":\"exponential\",\"alpha\":0.1}}",
     "Filament's Halton(2,3) from index 409, 16 phases, minus 1/2; feedback 0.1 as issue 30"},
    {"filament-halton32",
     "{\"jitter\":{\"generator\":\"halton\",\"bases\":[2,3],\"start\":409,\"count\":32},"
     "\"blend\":{\"kind\":\"exponential\",\"alpha\":0.1}}",
     "Filament's Halton(2,3) from index 409, 32 phases (its sHaltonSamples table), minus 1/2; "
     "feedback 0.1 as issue 30"},
};

size_t proto_temporal_preset_count(void)
{
    return sizeof presets / sizeof presets[0];
}

const proto_temporal_preset *proto_temporal_preset_at(size_t i)
{
    return i < proto_temporal_preset_count() ? &presets[i] : NULL;
}
