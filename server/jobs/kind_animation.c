/* Job kind "animation": a rotating triangle or translating circle rendered frame by frame with
 * a pattern beside the reference (Hasselgren et al. 2005, sec. 6.1). Only the pixels whose
 * footprint meets this or the previous frame's moving content are recomputed (render.h).
 * Result: per-frame RMSE / max deviation / recomputed pixels / times / tiles, and the whole
 * animation's RMSE, max deviation and penalised histogram C(i) i^2 / n.
 * Spec and result: proto/job_animation.h. */
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "job_animation.h"
#include "kinds.h"
#include "aa_render.h"
#include "tile_render.h"
#include "tile_store.h"

JOB_KIND_SPEC_PARAMS(kind_animation, proto_animation_spec, proto_decode_animation_spec,
                     proto_animation_spec_free)

static int animation_run(void *params, job_ctx *ctx, proto_animation_result *out, aa_error *err)
{
    proto_animation_spec *ap = params;
    tile_store *ts = job_ctx_tiles(ctx);
    /* The tiles belong to the job's owner and are private when the job is. */
    const tile_access access = {job_ctx_owner(ctx), job_ctx_private(ctx)};
    aa_render_params rp = aa_render_params_default(ap->common.scene.shape);
    rp.scene = ap->common.scene;
    rp.scene.frame = 0;
    rp.reference = ap->common.ref.params;
    rp.acuity = &ap->common.acuity;
    int F = rp.scene.frames;
    out->scene = rp.scene;
    snprintf(out->family, sizeof out->family, "%s", ap->pattern.family);
    out->samples_per_pixel = ap->pattern.cost_spp;
    proto_acuity_ref_set(&ap->common.acuity, out->acuity_name, sizeof out->acuity_name,
                         &out->acuity_version);
    out->frames = calloc(F > 0 ? (size_t)F : 1, sizeof *out->frames);
    if (!out->frames)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    job_progress_span probe = {ctx, 0, 1.0 / F};
    rp.reference.progress = job_progress_span_report;
    rp.reference.user = &probe;
    int rc = aa_pattern_e2(&ap->pattern, rp.reference.filter, &ap->common.acuity, &out->e2, err);
    /* The pattern's E2 is the job's best (job.json: {pattern: {family, samples_per_pixel}, e2}),
     * so the job list shows it as the detail does. */
    json_t *best = rc ? NULL
                      : json_pack("{s:{s:s,s:f},s:f}", "pattern", "family", out->family,
                                  "samples_per_pixel", out->samples_per_pixel, "e2", out->e2);
    aa_animation an;
    memset(&an, 0, sizeof an);
    if (!rc)
        rc = aa_animation_init(&an, &rp, &ap->pattern, err);
    aa_diff_init(&out->total);
    size_t recomputed = 0;
    for (int f = 0; f < F && !rc; f++) {
        probe.base = (double)f / F;
        aa_animation_frame_stats fs;
        rc = aa_animation_frame(&an, &fs, err);
        if (rc)
            break;
        aa_diff_add(&out->total, &an.pattern_img, &an.reference_img);
        out->pattern_seconds += fs.pattern_seconds;
        out->reference_seconds += fs.reference_seconds;
        recomputed += fs.pixels_recomputed;
        out->frames[f] =
            (proto_animation_frame){.frame = f,
                                    .rmse = fs.diff.rmse,
                                    .max_dev = fs.diff.max_dev,
                                    .pixels_recomputed = (long long)fs.pixels_recomputed,
                                    .pattern_sampled = (long long)fs.raster.pixels_sampled,
                                    .reference_supersampled = (long long)fs.ref.pixels_supersampled,
                                    .pattern_seconds = fs.pattern_seconds,
                                    .reference_seconds = fs.reference_seconds};
        out->frame_count = (size_t)f + 1;
        if (ts && ap->common.tiles)
            out->frames[f].tiles = tile_put_render_images_as(ts, &access, &an.pattern_img,
                                                             &an.reference_img, NULL, err);
        if (job_ctx_progress(ctx, (f + 1.0) / F, best))
            rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
    }
    if (!rc) {
        aa_diff_finish(&out->total);
        out->pixels_recomputed = (long long)recomputed;
        out->pixels_all_frames =
            (long long)((size_t)F * (size_t)rp.scene.width * (size_t)rp.scene.height);
    }
    aa_animation_free(&an);
    json_decref(best);
    return rc;
}

JOB_KIND_RESULT(kind_animation, proto_animation_result, animation_run,
                proto_encode_animation_result, proto_animation_result_free)

/* The kind's row of the table of kinds (kind_list.h). */
JOB_KIND_ROW(animation, .name = "animation",
             .summary =
                 "Renders a moving scene frame by frame with a pattern beside the reference and "
                 "reports the error of each frame and of the whole animation.");
