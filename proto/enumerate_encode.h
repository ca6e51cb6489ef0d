/* JSON of POST /v1/families/enumerate: the mirrored P(4,1+,n) placement configurations. */
#ifndef AALAB_ENUMERATE_ENCODE_H
#define AALAB_ENUMERATE_ENCODE_H

#include <stddef.h>

#include <jansson.h>

#include "aa_pattern.h"

/* {"family":"P(4,1+,n)","cost":c,"count":N,"configurations":[{"corners":[4],"edges":[4],
 * "interior":k,"samples":m,"label":"..."}...]}; NULL on allocation failure. */
json_t *enumerate_encode(double cost, const aa_mirrored_config *configs, size_t count);

#endif
