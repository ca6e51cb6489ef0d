/* Pattern references {"job": ID} in request bodies: a job's best pattern stands in for a
 * pattern. Which body fields may hold them is a column of the route table (router.c, api_refs);
 * api_request_body resolves them for every route that declares them, once, on the parsed body. */
#ifndef AALAB_PATTERN_REFS_H
#define AALAB_PATTERN_REFS_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_core.h"
#include "api.h"

/* Replaces every pattern reference {"job": ID} under the keys "pattern" and the elements of
 * "patterns" (at any depth of body) by that job's best pattern JSON. Errors: AA_EINVAL with the
 * field naming the reference ("pattern.job", "patterns[1].job") for a bad or unknown id, a job
 * the caller may not read (reported as unknown), or a job without a pattern. */
int api_resolve_pattern_refs(api_context *ctx, const api_caller *caller, json_t *body,
                             aa_error *err);

/* The request body as one JSON object (api_parse_body), its references resolved as the route
 * declares (api_request.refs). NULL when resp holds the answer (the body does not parse) or
 * asks for the pool (resp->needs_pool: a reference on an HTTP thread, which never reads the job
 * store). A reference that does not resolve sets *refs_err (code != 0) and the body is still
 * returned: the handler answers it where its endpoint's order of checks puts it. *had_refs
 * (may be NULL) tells whether the body held a reference. */
json_t *api_request_body(api_context *ctx, const api_request *req, api_response *resp,
                         aa_error *refs_err, bool *had_refs);

#endif
