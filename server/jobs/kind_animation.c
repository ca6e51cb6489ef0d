/* Job kind "animation": a rotating triangle or translating circle rendered frame by frame with
 * a pattern beside the reference (Hasselgren et al. 2005, sec. 6.1). Only the pixels whose
 * footprint meets this or the previous frame's moving content are recomputed (render.h).
 * Result: per-frame RMSE / max deviation / recomputed pixels / times / tiles, and the whole
 * animation's RMSE, max deviation and penalised histogram C(i) i^2 / n.
 * Spec: {"kind":"animation", "scene":{"name":"translating-circle", "frames":16, ...},
 *        "pattern":..., "reference":{...}, "acuity":..., "tiles":true} */
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "job_kind.h"
#include "aa_render.h"
#include "tile_render.h"
#include "tile_store.h"

typedef struct animation_params {
    aa_scene_params scene;
    tile_reference_spec ref;
    aa_acuity acuity;
    aa_pattern pattern;
    bool tiles;
} animation_params;

static void animation_free(void *params)
{
    animation_params *ap = params;
    if (!ap)
        return;
    aa_pattern_free(&ap->pattern);
    free(ap);
}

static const char *const spec_keys[] = {"kind",    "label",     "priority", "scene", "size",
                                        "pattern", "reference", "acuity",   "tiles", NULL};

static int animation_parse(const json_t *spec, void **params, aa_error *err)
{
    *params = NULL;
    int rc0 = proto_check_keys(spec, spec_keys, err, "");
    if (rc0)
        return rc0;
    animation_params *ap = calloc(1, sizeof *ap);
    if (!ap)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    ap->tiles = true;
    json_t *scene = json_object_get(spec, "scene");
    int rc = AA_OK;
    if (!json_is_string(scene) && !(json_is_object(scene) && json_object_get(scene, "name")))
        rc = aa_error_set(err, AA_EINVAL, "scene.name",
                          "an animation scene is required (rotating-triangle, "
                          "translating-circle)");
    if (!rc)
        rc = tile_decode_scene_request(spec, &ap->scene, err);
    if (!rc && !aa_scene_kind_is_animation(ap->scene.kind))
        rc = aa_error_set(err, AA_EINVAL, "scene.name",
                          "not an animation (rotating-triangle, translating-circle)");
    if (!rc)
        rc = tile_decode_reference(json_object_get(spec, "reference"), &ap->ref, "reference", err);
    if (!rc)
        rc = proto_decode_acuity(json_object_get(spec, "acuity"), &ap->acuity, "acuity", err);
    json_t *pj = json_object_get(spec, "pattern");
    if (!rc && !pj)
        rc = aa_error_set(err, AA_EINVAL, "pattern", "a pattern is required");
    if (!rc) {
        rc = tile_pattern_from_preset_name(pj, &ap->pattern, "pattern", err);
        if (rc == 1)
            rc = proto_decode_pattern(pj, 0, &ap->pattern, "pattern", err);
    }
    json_t *tiles = json_object_get(spec, "tiles");
    if (!rc && tiles) {
        if (!json_is_boolean(tiles))
            rc = aa_error_set(err, AA_EINVAL, "tiles", "must be true or false");
        else
            ap->tiles = json_is_true(tiles);
    }
    if (rc) {
        animation_free(ap);
        return rc;
    }
    *params = ap;
    return AA_OK;
}

static int animation_run(void *params, job_ctx *ctx, json_t **result, aa_error *err)
{
    animation_params *ap = params;
    tile_store *ts = job_ctx_services(ctx);
    /* The tiles belong to the job's owner and are private when the job is. */
    const tile_access access = {job_ctx_owner(ctx), job_ctx_private(ctx)};
    aa_render_params rp = aa_render_params_default(ap->scene.kind);
    rp.scene = ap->scene;
    rp.scene.frame = 0;
    rp.reference = ap->ref.params;
    rp.acuity = &ap->acuity;
    int F = rp.scene.frames;
    job_progress_span probe = {ctx, 0, 1.0 / F};
    rp.reference.progress = job_progress_span_report;
    rp.reference.user = &probe;
    double e2 = 0;
    int rc = aa_pattern_e2(&ap->pattern, rp.reference.filter, &ap->acuity, &e2, err);
    aa_animation an;
    memset(&an, 0, sizeof an);
    if (!rc)
        rc = aa_animation_init(&an, &rp, &ap->pattern, err);
    json_t *frames = json_array();
    aa_diff_stats total;
    aa_diff_init(&total);
    double pattern_seconds = 0, reference_seconds = 0;
    size_t recomputed = 0;
    for (int f = 0; f < F && !rc; f++) {
        probe.base = (double)f / F;
        aa_animation_frame_stats fs;
        rc = aa_animation_frame(&an, &fs, err);
        if (rc)
            break;
        aa_diff_add(&total, &an.pattern_img, &an.reference_img);
        pattern_seconds += fs.pattern_seconds;
        reference_seconds += fs.reference_seconds;
        recomputed += fs.pixels_recomputed;
        json_t *fj =
            json_pack("{s:I, s:f, s:f, s:I, s:I, s:I, s:f, s:f}", "frame", (json_int_t)f, "rmse",
                      fs.diff.rmse, "max_dev", fs.diff.max_dev, "pixels_recomputed",
                      (json_int_t)fs.pixels_recomputed, "pattern_sampled",
                      (json_int_t)fs.raster.pixels_sampled, "reference_supersampled",
                      (json_int_t)fs.ref.pixels_supersampled, "pattern_seconds", fs.pattern_seconds,
                      "reference_seconds", fs.reference_seconds);
        if (fj && ts && ap->tiles) {
            json_t *t = tile_put_render_images_as(ts, &access, &an.pattern_img, &an.reference_img,
                                                  NULL, err);
            if (t)
                json_object_set_new(fj, "tiles", t);
        }
        json_array_append_new(frames, fj);
        if (job_ctx_progress(ctx, (f + 1.0) / F, NULL))
            rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
    }
    if (!rc) {
        aa_diff_finish(&total);
        size_t full = (size_t)F * (size_t)rp.scene.width * (size_t)rp.scene.height;
        *result =
            json_pack("{s:o, s:{s:s, s:f}, s:f, s:o, s:o, s:{s:f, s:f}, s:{s:I, s:I}}", "scene",
                      tile_encode_scene(&rp.scene), "pattern", "family", ap->pattern.family,
                      "samples_per_pixel", ap->pattern.cost_spp, "e2", e2, "frames", frames,
                      "total", tile_encode_diff(&total), "times", "pattern_seconds",
                      pattern_seconds, "reference_seconds", reference_seconds, "pixels",
                      "recomputed", (json_int_t)recomputed, "all_frames", (json_int_t)full);
        frames = NULL;
        if (!*result)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    json_decref(frames);
    aa_animation_free(&an);
    return rc;
}

const job_kind job_kind_animation = {.name = "animation",
                                     .parse = animation_parse,
                                     .run = animation_run,
                                     .free_params = animation_free};
