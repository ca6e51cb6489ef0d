/* Exports of a temporal pattern (docs/temporal.md section 6, docs/api.md Exports): the jitter
 * sequence as a C or HLSL table with the blend's constants (what an engine's TAA pass reads),
 * and one phase's kernels as a spatial pattern (for the generic point-set formats). */
#ifndef AALAB_PROTO_EXPORT_TEMPORAL_H
#define AALAB_PROTO_EXPORT_TEMPORAL_H

#include <stdbool.h>
#include <stddef.h>

#include "codec_temporal.h"

#define PROTO_JITTER_FORMATS "jitter-c or jitter-hlsl"

/* "jitter-c" or "jitter-hlsl": true and *hlsl set; false for anything else. */
bool proto_jitter_format_parse(const char *name, bool *hlsl);
/* The sequence as C (static const float arrays) or HLSL (static const float2) source: the
 * offsets per frame, the blend's alpha and the steady-state weight of each frame age, with the
 * exact wire form on its first line ("// aalab-temporal {JSON}"). malloc'd, NUL-terminated, *len
 * without the NUL; NULL with err set on failure. */
char *proto_export_jitter_text(const proto_temporal *t, bool hlsl, size_t *len, aa_error *err);
/* Phase p's kernels, one per output pixel (group), as an explicit-kernels pattern. Errors name
 * "phase" (out of range) or come from the expansion. */
int proto_temporal_phase_pattern(const proto_temporal *t, size_t phase, aa_pattern *out,
                                 aa_error *err);

#endif
