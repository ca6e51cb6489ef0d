/* POST /v1/tokens on the wire: {"label"?: string of at most PROTO_TOKEN_LABEL_MAX bytes}; an
 * empty body is {}. */
#ifndef AALAB_PROTO_REQUEST_TOKEN_H
#define AALAB_PROTO_REQUEST_TOKEN_H

#include <jansson.h>

#include "aa_core.h"

#define PROTO_TOKEN_LABEL_MAX 100

typedef struct proto_token_request {
    const char *label; /* borrowed from the body, or NULL */
} proto_token_request;

/* Strict: an unknown key, or a label that is not a string without NUL bytes of at most
 * PROTO_TOKEN_LABEL_MAX bytes, is AA_EINVAL naming the field. */
int proto_decode_token_request(const json_t *body, proto_token_request *out, aa_error *err);

#endif
