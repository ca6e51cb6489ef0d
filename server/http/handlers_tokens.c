/* POST /v1/tokens (issue, Unix socket only), GET /v1/tokens (the caller's; root sees all),
 * DELETE /v1/tokens/{id} (revoke: the owner or root). Tokens admit TCP requests as their uid.
 * The POST body is decoded by proto/request_token.c. */
#include <string.h>

#include "handlers.h"
#include "request_token.h"
#include "token_store.h"

void handle_tokens_post(api_context *ctx, const api_request *req, api_response *resp)
{
    /* A token can only come from someone who can already reach the socket: a token holder
     * minting more tokens would outlive a revocation. */
    if (req->caller.via_tcp) {
        api_reply_wire(resp, WIRE_FORBIDDEN, "",
                       "tokens are issued on the Unix socket only (aalab token)");
        return;
    }
    if (req->caller.uid < 0) {
        api_reply_wire(resp, WIRE_FORBIDDEN, "", "the caller's uid is unknown");
        return;
    }
    json_t *body = req->body_len ? api_parse_body(req, resp) : json_object();
    if (!body)
        return;
    aa_error err = {0};
    proto_token_request rq;
    if (proto_decode_token_request(body, &rq, &err)) {
        json_decref(body);
        api_reply_aa_error(resp, &err);
        return;
    }
    err = (aa_error){0};
    json_t *out = NULL;
    int rc = token_store_issue(api_context_tokens(ctx), req->caller.uid, rq.label,
                               api_context_config(ctx)->user_tokens, &out, &err);
    json_decref(body);
    if (rc) {
        /* TOKEN_EQUOTA answers as itself; any other failure (AA_ENOMEM too) is the store's. */
        api_reply_service_error(resp, proto_service_row_of(rc) ? rc : TOKEN_ESTORE, &err);
        return;
    }
    api_reply_json(resp, 201, out);
    resp->cache_control = "no-store";
}

void handle_tokens_list(api_context *ctx, const api_request *req, api_response *resp)
{
    if (req->caller.uid < 0 && !req->caller.admin) {
        api_reply_wire(resp, WIRE_FORBIDDEN, "", "the caller's uid is unknown");
        return;
    }
    json_t *list =
        token_store_list(api_context_tokens(ctx), req->caller.admin ? -1 : req->caller.uid);
    api_reply_json(resp, 200, json_pack("{s:o}", "tokens", list));
    resp->cache_control = "no-store";
}

void handle_token_delete(api_context *ctx, const api_request *req, api_response *resp,
                         const char *id_text)
{
    long long id = api_parse_job_id(id_text); /* the same positive-decimal rule */
    int rc =
        id > 0 ? token_store_revoke(api_context_tokens(ctx), id, req->caller.uid, req->caller.admin)
               : TOKEN_ENOENT;
    if (!rc) {
        api_reply_json(resp, 200, json_pack("{s:I,s:b}", "id", (json_int_t)id, "revoked", 1));
        return;
    }
    aa_error err = {0};
    if (rc == TOKEN_ENOENT)
        aa_error_set(&err, rc, "id", "no token %.40s", id_text);
    /* ENOENT and EFORBIDDEN answer as themselves; any other failure is the store's. */
    api_reply_service_error(resp, proto_service_row_of(rc) ? rc : TOKEN_ESTORE, &err);
}
