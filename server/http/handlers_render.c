/* POST /v1/render and GET /v1/tiles/{id}.png (handlers_render.h). */
#include "handlers_render.h"

#include <stdlib.h>
#include <string.h>

#include "api_context.h"
#include "codec.h"
#include "aa_render.h"
#include "codec_render.h"
#include "handlers.h"
#include "job_access.h"
#include "tile_render.h"
#include "tile_store.h"

/* Stops the reference when the wall-time budget is spent. */
static int over_budget(void *user, double fraction)
{
    (void)fraction;
    return aa_seconds_now() > *(const double *)user;
}

void handle_render(api_context *ctx, const api_request *req, api_response *resp)
{
    tile_store *ts = api_context_tiles(ctx);
    if (!ts) {
        api_reply_wire(resp, WIRE_INTERNAL, "", "the tile store is not configured");
        return;
    }
    aa_error err = {0};
    /* the one body parser (its errors are UTF-8), references resolved */
    json_t *root = api_request_body(ctx, req, resp, &err, NULL);
    if (!root)
        return;
    proto_render_request rq;
    int rc = err.code ? err.code : proto_decode_render_request(root, &rq, &err);
    json_decref(root);
    if (rc) {
        api_reply_aa_error(resp, &err);
        return;
    }
    aa_render_result result;
    bool rendered = false;
    /* The tiles belong to the requester; private ones are served to them and root only. */
    tile_access access = {.owner = req->caller.uid, .private_tile = rq.private_tiles};
    if (access.private_tile && access.owner < 0) {
        api_reply_wire(resp, WIRE_INVALID_FIELD, "visibility",
                       "a private render needs a known caller");
        goto done;
    }
    const aalab_config *cfg = api_context_config(ctx);
    if ((long long)rq.scene.width * rq.scene.height > cfg->render_max_pixels) {
        api_reply_wire(resp, WIRE_OUT_OF_RANGE, "scene.width",
                       "at most %ld pixels per tile here; use a compare job for larger renders",
                       cfg->render_max_pixels);
        goto done;
    }
    size_t widest = 0;
    for (size_t k = 0; k < rq.pattern.kernel_count; k++)
        widest = rq.pattern.kernels[k].count > widest ? rq.pattern.kernels[k].count : widest;
    if ((double)rq.scene.width * rq.scene.height * (double)widest >
        (double)RENDER_MAX_KERNEL_WORK) {
        api_reply_wire(resp, WIRE_OUT_OF_RANGE, "pattern",
                       "%zu samples per kernel on %d x %d pixels is too much work here; use a "
                       "compare job",
                       widest, rq.scene.width, rq.scene.height);
        goto done;
    }
    aa_render_params rp = proto_render_params(&rq);
    double deadline = aa_seconds_now() + cfg->render_seconds;
    rp.reference.progress = over_budget;
    rp.reference.user = &deadline;
    rc = aa_render_tile(&rp, &rq.pattern, &result, &err);
    if (rc == AA_ECANCELED) {
        api_reply_wire(resp, WIRE_OVER_TIME_BUDGET, "reference.spp",
                       "the reference exceeded %g s; lower spp or submit a compare job",
                       cfg->render_seconds);
        goto done;
    }
    if (rc) {
        api_reply_aa_error(resp, &err);
        goto done;
    }
    rendered = true;
    rp.reference.progress = NULL;
    rp.reference.user = NULL;
    json_t *tiles =
        tile_put_render_images_as(ts, &access, &result.pattern, &result.reference, &rq.crop, &err);
    json_t *out = tiles ? proto_encode_render_result(&rp, &rq.pattern, &result, tiles) : NULL;
    if (!out) {
        if (!tiles || !err.code)
            aa_error_set(&err, AA_ENOMEM, "", "out of memory");
        api_reply_aa_error(resp, &err);
        goto done;
    }
    proto_encode_render_phase(out, &rq);
    json_t *enc = proto_encode_pattern(&rq.pattern);
    if (enc)
        json_object_set_new(json_object_get(out, "pattern"), "wire", enc);
    api_reply_json(resp, 200, out);
done:
    if (rendered)
        aa_render_result_free(&result);
    proto_render_request_free(&rq);
}

void handle_tile(api_context *ctx, const api_request *req, api_response *resp, const char *id)
{
    tile_store *ts = api_context_tiles(ctx);
    if (!ts) {
        api_reply_wire(resp, WIRE_INTERNAL, "", "the tile store is not configured");
        return;
    }
    char bare[TILE_ID_LEN + 1];
    size_t n = id ? strlen(id) : 0;
    if (n == TILE_ID_LEN + 4 && strcmp(id + TILE_ID_LEN, ".png") == 0)
        n = TILE_ID_LEN;
    if (n != TILE_ID_LEN) {
        api_reply_wire(resp, WIRE_INVALID_FIELD, "id", "a tile id is %d hex characters",
                       TILE_ID_LEN);
        return;
    }
    memcpy(bare, id, TILE_ID_LEN);
    bare[TILE_ID_LEN] = 0;
    void *data;
    size_t len;
    int rc = tile_store_get_as(ts, bare, req->caller.uid, req->caller.admin, &data, &len);
    if (rc == AA_EINVAL) {
        api_reply_wire(resp, WIRE_INVALID_FIELD, "id", "a tile id is %d lowercase hex characters",
                       TILE_ID_LEN);
        return;
    }
    if (rc == TILE_ENOENT) {
        api_reply_wire(resp, WIRE_NOT_FOUND, "id",
                       "no tile %s (tiles are evicted when the "
                       "store is full; render again)",
                       bare);
        return;
    }
    if (rc) {
        api_reply_wire(resp, WIRE_OUT_OF_MEMORY, "", "out of memory");
        return;
    }
    resp->status = 200;
    resp->content_type = "image/png";
    resp->body = data;
    resp->body_len = len;
    /* Content-addressed: the bytes behind an id never change. Private to the browser: the
     * tile's access may be per user. */
    resp->cache_control = "private, max-age=31536000, immutable";
}
