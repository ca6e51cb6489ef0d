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
#include "kinds.h"
#include "render_pattern.h"
#include "render_spec.h"
#include "aa_render.h"
#include "tile_render.h"
#include "tile_store.h"

typedef struct animation_spec {
    render_spec common;
    aa_pattern pattern;
} animation_spec;

static void animation_spec_free(animation_spec *ap)
{
    aa_pattern_free(&ap->pattern);
}

static const char *const kind_keys[] = {"pattern", NULL};

static int animation_spec_decode(const json_t *spec, animation_spec *ap, aa_error *err)
{
    /* Without a scene the render default (a still one) would be taken: ask for a moving one. */
    json_t *scene = json_object_get(spec, "scene");
    if (!json_is_string(scene) && !(json_is_object(scene) && json_object_get(scene, "name")))
        return aa_error_set(err, AA_EINVAL, "scene.name",
                            "an animation scene is required (rotating-triangle, "
                            "translating-circle)");
    int rc = render_spec_decode(spec, kind_keys, RENDER_SPEC_ACUITY | RENDER_SPEC_TILES,
                                &ap->common, err);
    if (!rc && !aa_scene_kind_is_animation(ap->common.scene.kind))
        rc = aa_error_set(err, AA_EINVAL, "scene.name",
                          "not an animation (rotating-triangle, translating-circle)");
    json_t *pj = json_object_get(spec, "pattern");
    if (!rc && !pj)
        rc = aa_error_set(err, AA_EINVAL, "pattern", "a pattern is required");
    if (!rc)
        rc = render_pattern_decode(pj, &ap->pattern, "pattern", err);
    return rc;
}

JOB_KIND_SPEC_PARAMS(kind_animation, animation_spec, animation_spec_decode, animation_spec_free)

JOB_KIND_JSON_RESULT(kind_animation)

int kind_animation_run(void *params, job_ctx *ctx, void **result, aa_error *err)
{
    animation_spec *ap = params;
    tile_store *ts = job_ctx_tiles(ctx);
    /* The tiles belong to the job's owner and are private when the job is. */
    const tile_access access = {job_ctx_owner(ctx), job_ctx_private(ctx)};
    aa_render_params rp = aa_render_params_default(ap->common.scene.kind);
    rp.scene = ap->common.scene;
    rp.scene.frame = 0;
    rp.reference = ap->common.ref.params;
    rp.acuity = &ap->common.acuity;
    int F = rp.scene.frames;
    job_progress_span probe = {ctx, 0, 1.0 / F};
    rp.reference.progress = job_progress_span_report;
    rp.reference.user = &probe;
    double e2 = 0;
    int rc = aa_pattern_e2(&ap->pattern, rp.reference.filter, &ap->common.acuity, &e2, err);
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
        if (fj && ts && ap->common.tiles) {
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
                      proto_encode_scene(&rp.scene), "pattern", "family", ap->pattern.family,
                      "samples_per_pixel", ap->pattern.cost_spp, "e2", e2, "frames", frames,
                      "total", proto_encode_diff(&total), "times", "pattern_seconds",
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
