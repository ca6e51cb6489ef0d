/* POST /v1/families/enumerate {"family":"P(4,1+,n)","cost":1.25}: the mirrored configurations
 * of a cost (the optimizer's aa_enumerate_mirrored, server/engine/pattern/enumerate.h): decoded
 * by proto/request_enumerate.c, enumerated, encoded by proto/enumerate_encode.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "handlers.h"

#include "aa_pattern.h"
#include "eval_cache.h"
#include "enumerate_encode.h"
#include "request_enumerate.h"

void handle_enumerate(api_context *ctx, const api_request *req, api_response *resp)
{
    json_t *body = api_parse_body(req, resp);
    if (!body)
        return;
    aa_error err = {0};
    proto_enumerate_request rq;
    int rc = proto_decode_enumerate_request(body, &rq, &err);
    json_decref(body);
    if (rc) {
        api_reply_aa_error(resp, &err);
        return;
    }
    double cost = rq.cost;
    /* The answer depends on the cost alone; at cost 16 it is 29,529 configurations (4.4 MB,
     * 0.17 s to enumerate and encode), so it is kept in the answer cache. */
    char key[64];
    int key_len = snprintf(key, sizeof key, "enumerate P(4,1+,n) %.2f", cost);
    eval_cache *cache = api_context_eval_cache(ctx);
    char *hit = NULL;
    size_t hit_len = 0;
    if (eval_cache_get(cache, key, (size_t)key_len, &hit, &hit_len)) {
        api_reply_owned(resp, 200, hit, hit_len);
        return;
    }
    aa_mirrored_config *configs = NULL;
    size_t count = 0;
    rc = aa_enumerate_mirrored(cost, &configs, &count, &err);
    if (rc) {
        api_reply_aa_error(resp, &err);
        return;
    }
    api_reply_json(resp, 200, enumerate_encode(cost, configs, count));
    free(configs);
    if (resp->status == 200)
        eval_cache_put(cache, key, (size_t)key_len, resp->body, resp->body_len);
}
