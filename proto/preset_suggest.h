/* Unknown preset names: the error names the field and suggests the nearest known names (edit
 * distance), e.g. unknown preset "flipqaud"; did you mean "flipquad"? */
#ifndef AALAB_PROTO_PRESET_SUGGEST_H
#define AALAB_PROTO_PRESET_SUGGEST_H

#include <stddef.h>

#include "aa_core.h"

#define PROTO_SUGGEST_MAX 3

/* Up to PROTO_SUGGEST_MAX preset names nearest to name, nearest first; returns how many. */
size_t proto_preset_nearest(const char *name, const char *out[PROTO_SUGGEST_MAX]);
/* Sets err (AA_EINVAL, field) to `unknown preset "name"; did you mean "a", "b" or "c"?` and
 * returns AA_EINVAL. */
int proto_unknown_preset(aa_error *err, const char *field, const char *name);

#endif
