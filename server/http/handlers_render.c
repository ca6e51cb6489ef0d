/* POST /v1/render and GET /v1/tiles/{id}.png (handlers_render.h). */
#include "handlers_render.h"

#include <stdlib.h>
#include <string.h>

#include "api_context.h"
#include "codec.h"
#include "job_access.h"
#include "aa_render.h"
#include "tile_render.h"
#include "tile_store.h"

static const char *const render_keys[] = {"scene", "size",   "pattern",    "reference",
                                          "crop",  "acuity", "visibility", NULL};

static bool known_key(const char *key)
{
    for (size_t i = 0; render_keys[i]; i++)
        if (strcmp(key, render_keys[i]) == 0)
            return true;
    return false;
}

static void reply_engine_error(api_response *resp, const aa_error *err)
{
    int status = err->code == AA_ENOMEM ? 503 : 400;
    const char *code = err->code == AA_ENOMEM   ? "internal"
                       : err->code == AA_ERANGE ? "out_of_range"
                                                : "invalid_field";
    api_reply_error(resp, status, code, err->field, "%s", err->message);
}

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
        api_reply_error(resp, 500, "internal", "", "the tile store is not configured");
        return;
    }
    json_error_t jerr;
    json_t *root =
        req->body_len ? json_loadb(req->body, req->body_len, JSON_REJECT_DUPLICATES, &jerr) : NULL;
    if (!root) {
        api_reply_error(resp, 400, "invalid_json", "", "body is not JSON: %s",
                        req->body_len ? jerr.text : "empty body");
        return;
    }
    aa_error err = {0};
    aa_pattern pattern;
    memset(&pattern, 0, sizeof pattern);
    aa_render_params rp = aa_render_params_default(AA_SCENE_SIEMENS_STAR);
    tile_reference_spec ref;
    tile_crop crop;
    aa_acuity acuity;
    aa_render_result result;
    bool rendered = false;
    const char *key;
    json_t *v;
    if (!json_is_object(root)) {
        api_reply_error(resp, 400, "invalid_field", "", "body must be a JSON object");
        goto done;
    }
    json_object_foreach(root, key, v)
    {
        if (!known_key(key)) {
            api_reply_error(resp, 400, "invalid_field", key, "unknown field");
            goto done;
        }
    }
    json_t *vis = json_object_get(root, JOB_VISIBILITY_KEY);
    if (!job_visibility_valid(vis)) {
        api_reply_error(resp, 400, "invalid_field", JOB_VISIBILITY_KEY,
                        "visibility must be \"team\" or \"private\"");
        goto done;
    }
    /* The tiles belong to the requester; private ones are served to them and root only. */
    tile_access access = {.owner = req->caller.uid,
                          .private_tile = vis && !strcmp(json_string_value(vis), "private")};
    if (access.private_tile && access.owner < 0) {
        api_reply_error(resp, 400, "invalid_field", JOB_VISIBILITY_KEY,
                        "a private render needs a known caller");
        goto done;
    }
    if (tile_decode_scene_request(root, &rp.scene, &err)) {
        reply_engine_error(resp, &err);
        goto done;
    }
    const aalab_config *cfg = api_context_config(ctx);
    if ((long long)rp.scene.width * rp.scene.height > cfg->render_max_pixels) {
        api_reply_error(resp, 400, "out_of_range", "scene.width",
                        "at most %ld pixels per tile here; use a compare job for larger renders",
                        cfg->render_max_pixels);
        goto done;
    }
    json_t *pj = json_object_get(root, "pattern");
    if (!pj) {
        api_reply_error(resp, 400, "invalid_field", "pattern", "a pattern is required");
        goto done;
    }
    int rc = tile_pattern_from_preset_name(pj, &pattern, "pattern", &err);
    if (rc == 1)
        rc = proto_decode_pattern(pj, 0, &pattern, "pattern", &err);
    if (rc || tile_decode_reference(json_object_get(root, "reference"), &ref, "reference", &err) ||
        tile_decode_crop(json_object_get(root, "crop"), rp.scene.width, rp.scene.height, &crop,
                         "crop", &err) ||
        proto_decode_acuity(json_object_get(root, "acuity"), &acuity, "acuity", &err)) {
        reply_engine_error(resp, &err);
        goto done;
    }
    size_t widest = 0;
    for (size_t k = 0; k < pattern.kernel_count; k++)
        widest = pattern.kernels[k].count > widest ? pattern.kernels[k].count : widest;
    if ((double)rp.scene.width * rp.scene.height * (double)widest >
        (double)RENDER_MAX_KERNEL_WORK) {
        api_reply_error(resp, 400, "out_of_range", "pattern",
                        "%zu samples per kernel on %d x %d pixels is too much work here; use a "
                        "compare job",
                        widest, rp.scene.width, rp.scene.height);
        goto done;
    }
    rp.reference = ref.params;
    rp.acuity = &acuity;
    double deadline = aa_seconds_now() + cfg->render_seconds;
    rp.reference.progress = over_budget;
    rp.reference.user = &deadline;
    rc = aa_render_tile(&rp, &pattern, &result, &err);
    if (rc == AA_ECANCELED) {
        api_reply_error(resp, 422, "out_of_range", "reference.spp",
                        "the reference exceeded %g s; lower spp or submit a compare job",
                        cfg->render_seconds);
        goto done;
    }
    if (rc) {
        reply_engine_error(resp, &err);
        goto done;
    }
    rendered = true;
    rp.reference.progress = NULL;
    rp.reference.user = NULL;
    json_t *out = tile_render_result_json(ts, &access, &rp, &pattern, &result, &crop, &err);
    if (!out) {
        api_reply_error(resp, 503, "internal", "", "%s", err.message);
        goto done;
    }
    json_t *enc = proto_encode_pattern(&pattern);
    if (enc)
        json_object_set_new(json_object_get(out, "pattern"), "wire", enc);
    api_reply_json(resp, 200, out);
done:
    if (rendered)
        aa_render_result_free(&result);
    aa_pattern_free(&pattern);
    json_decref(root);
}

void handle_tile(api_context *ctx, const api_request *req, api_response *resp, const char *id)
{
    tile_store *ts = api_context_tiles(ctx);
    if (!ts) {
        api_reply_error(resp, 500, "internal", "", "the tile store is not configured");
        return;
    }
    char bare[TILE_ID_LEN + 1];
    size_t n = id ? strlen(id) : 0;
    if (n == TILE_ID_LEN + 4 && strcmp(id + TILE_ID_LEN, ".png") == 0)
        n = TILE_ID_LEN;
    if (n != TILE_ID_LEN) {
        api_reply_error(resp, 400, "invalid_field", "id", "a tile id is %d hex characters",
                        TILE_ID_LEN);
        return;
    }
    memcpy(bare, id, TILE_ID_LEN);
    bare[TILE_ID_LEN] = 0;
    void *data;
    size_t len;
    int rc = tile_store_get_as(ts, bare, req->caller.uid, req->caller.admin, &data, &len);
    if (rc == AA_EINVAL) {
        api_reply_error(resp, 400, "invalid_field", "id",
                        "a tile id is %d lowercase hex characters", TILE_ID_LEN);
        return;
    }
    if (rc == TILE_ENOENT) {
        api_reply_error(resp, 404, "not_found", "id",
                        "no tile %s (tiles are evicted when the "
                        "store is full; render again)",
                        bare);
        return;
    }
    if (rc) {
        api_reply_error(resp, 503, "internal", "", "out of memory");
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
