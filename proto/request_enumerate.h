/* POST /v1/families/enumerate on the wire: {"family": "P(4,1+,n)" | "P(4,1+,<cost>)",
 * "cost"?: number}. The cost is given once or twice (in the family's n and in "cost"; then they
 * agree), a multiple of 0.25 in (0, AA_ENUMERATE_MAX_COST]. */
#ifndef AALAB_PROTO_REQUEST_ENUMERATE_H
#define AALAB_PROTO_REQUEST_ENUMERATE_H

#include <jansson.h>

#include "aa_pattern.h"

typedef struct proto_enumerate_request {
    double cost; /* samples per pixel */
} proto_enumerate_request;

/* Strict: unknown keys, a missing family, a family other than P(4,1+,...), a missing, bad or
 * disagreeing cost are AA_EINVAL or AA_ERANGE naming the field. */
int proto_decode_enumerate_request(const json_t *body, proto_enumerate_request *out, aa_error *err);

#endif
