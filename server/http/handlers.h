/* Handlers behind the router (one concept per file) and the helpers they share. */
#ifndef AALAB_HANDLERS_H
#define AALAB_HANDLERS_H

#include <jansson.h>

#include "aa_core.h"
#include "api.h"
#include "api_context.h"
#include "pattern_refs.h"

/* Parses the body as one JSON object (duplicate keys rejected); on failure replies 400 and
 * returns NULL. */
json_t *api_parse_body(const api_request *req, api_response *resp);
/* Unknown keys -> 400 naming the key (prefix.key). Returns 0 if all keys are allowed. */
int api_reject_unknown(const json_t *obj, const char *const *allowed, const char *prefix,
                       api_response *resp);
/* An engine error (AA_E*) answered from the error table with err's field and message. */
void api_reply_aa_error(api_response *resp, const aa_error *err);
/* A service code (JM_E*, TOKEN_E*, ... proto/service_error.h) answered from its row: the row's
 * wire error and field, err's message or else the row's; any other code is an engine error
 * (api_reply_aa_error). */
void api_reply_service_error(api_response *resp, int rc, const aa_error *err);
/* Job id from a path segment: positive decimal without sign or leading zeros, else -1. */
long long api_parse_job_id(const char *s);
/* Value of key in a raw query string (percent-decoding not needed for our keys); NULL if
 * absent. Copies into buf. */
const char *api_query_get(const char *query, const char *key, char *buf, size_t cap);

void handle_health(api_context *ctx, const api_request *req, api_response *resp);
void handle_kinds(api_context *ctx, const api_request *req, api_response *resp);
void handle_presets_list(api_context *ctx, const api_request *req, api_response *resp);
void handle_preset_get(api_context *ctx, const api_request *req, api_response *resp,
                       const char *name);
void handle_filters(api_context *ctx, const api_request *req, api_response *resp);
void handle_acuity(api_context *ctx, const api_request *req, api_response *resp);
void handle_evaluate(api_context *ctx, const api_request *req, api_response *resp);
/* POST /v1/analyze (handlers_analyze.c). */
void handle_analyze(api_context *ctx, const api_request *req, api_response *resp);
/* POST /v1/predict (handlers_predict.c). */
void handle_predict(api_context *ctx, const api_request *req, api_response *resp);
void handle_jobs_post(api_context *ctx, const api_request *req, api_response *resp);
void handle_jobs_list(api_context *ctx, const api_request *req, api_response *resp);
void handle_job_get(api_context *ctx, const api_request *req, api_response *resp, const char *id);
void handle_job_delete(api_context *ctx, const api_request *req, api_response *resp,
                       const char *id);
void handle_job_patch(api_context *ctx, const api_request *req, api_response *resp, const char *id);
void handle_usage(api_context *ctx, const api_request *req, api_response *resp);
void handle_enumerate(api_context *ctx, const api_request *req, api_response *resp);
void handle_export(api_context *ctx, const api_request *req, api_response *resp, const char *id);
void handle_export_post(api_context *ctx, const api_request *req, api_response *resp);
void handle_tokens_post(api_context *ctx, const api_request *req, api_response *resp);
void handle_tokens_list(api_context *ctx, const api_request *req, api_response *resp);
void handle_token_delete(api_context *ctx, const api_request *req, api_response *resp,
                         const char *id);
void handle_static(api_context *ctx, const api_request *req, api_response *resp);

#endif
