/* GET /v1/kinds: {"envelope_schema", "kinds": [{"name", "summary", "spec_schema",
 * "result_schema", "examples"}, ...]} for every kind this daemon runs, encoded once at start
 * (kind_schemas_document). */
#define _GNU_SOURCE
#include <string.h>

#include "handlers.h"

void handle_kinds(api_context *ctx, const api_request *req, api_response *resp)
{
    (void)req;
    const char *body = api_context_kinds_body(ctx);
    char *copy = strdup(body);
    if (!copy) {
        api_reply_wire(resp, WIRE_INTERNAL, "", "out of memory");
        return;
    }
    api_reply_owned(resp, 200, copy, strlen(body));
}
