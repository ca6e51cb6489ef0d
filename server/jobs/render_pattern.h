/* The render job kinds (compare, animation) take a pattern as a preset name ("flipquad") or as
 * a pattern object (proto/codec.h); an unknown name suggests the nearest ones. */
#ifndef AALAB_RENDER_PATTERN_H
#define AALAB_RENDER_PATTERN_H

#include <jansson.h>

#include "aa_core.h"
#include "aa_pattern.h"

int render_pattern_decode(const json_t *j, aa_pattern *out, const char *field, aa_error *err);

#endif
