/* The temporal half of the pattern exports (handlers_export.c): a temporal pattern in json (its
 * explicit wire form), jitter-c / jitter-hlsl (the sequence and the blend constants as source),
 * or one phase's kernels ("phase") in the point-set formats; vulkan and d3d12 (MSAA sample
 * positions) and a phase without a point format are 400s naming the field. */
#ifndef AALAB_HANDLERS_EXPORT_TEMPORAL_H
#define AALAB_HANDLERS_EXPORT_TEMPORAL_H

#include <stdbool.h>

#include <jansson.h>

#include "api.h"

/* True when the request is the temporal half's (the pattern is temporal, the format is a jitter
 * format, or a phase is given): resp then holds the answer. format NULL: json; phase NULL: none;
 * job > 0 is named in the json answer. */
bool export_temporal_answer(api_response *resp, const json_t *pattern, const char *format,
                            const json_t *phase, long long job);

#endif
