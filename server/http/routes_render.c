/* POST /v1/render and GET /v1/tiles/{id}.png: pattern references {"job": ID} are resolved
 * here, then the renderer's handlers (handlers_render.c) run. */
#include <stdlib.h>
#include <string.h>

#include "handlers.h"
#include "handlers_render.h"

void route_render(api_context *ctx, const api_request *req, api_response *resp)
{
    /* Rewrite the body only when it holds a reference; otherwise pass it through untouched so
     * the renderer reports its own parse errors. */
    json_t *body =
        req->body_len ? json_loadb(req->body, req->body_len, JSON_REJECT_DUPLICATES, NULL) : NULL;
    if (!body || !json_is_object(body)) {
        json_decref(body);
        handle_render(ctx, req, resp);
        return;
    }
    aa_error err = {0};
    char *before = json_dumps(body, JSON_COMPACT | JSON_SORT_KEYS);
    int rc = api_resolve_pattern_refs(ctx, &req->caller, body, &err);
    char *after = rc ? NULL : json_dumps(body, JSON_COMPACT | JSON_SORT_KEYS);
    json_decref(body);
    if (rc) {
        api_reply_aa_error(resp, &err);
    } else if (before && after && strcmp(before, after)) {
        api_request copy = *req;
        copy.body = after;
        copy.body_len = strlen(after);
        handle_render(ctx, &copy, resp);
    } else {
        handle_render(ctx, req, resp);
    }
    free(before);
    free(after);
}

void route_tile(api_context *ctx, const api_request *req, api_response *resp, const char *id)
{
    handle_tile(ctx, req, resp, id);
}
