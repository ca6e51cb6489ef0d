#include "job_animation.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "codec_internal.h"

static const char *const kind_keys[] = {"pattern", NULL};

int proto_decode_animation_spec(const json_t *spec, proto_animation_spec *ap, aa_error *err)
{
    memset(ap, 0, sizeof *ap);
    /* Without a scene the render default (a still one) would be taken: ask for a moving one. */
    json_t *scene = json_object_get(spec, "scene");
    if (!json_is_string(scene) && !(json_is_object(scene) && json_object_get(scene, "name")))
        return aa_error_set(err, AA_EINVAL, "scene.name",
                            "an animation scene is required (rotating-triangle, "
                            "translating-circle)");
    int rc = proto_render_spec_decode(
        spec, kind_keys, PROTO_RENDER_SPEC_ACUITY | PROTO_RENDER_SPEC_TILES, &ap->common, err);
    if (!rc && !aa_scene_shape_is_animation(ap->common.scene.shape))
        rc = aa_error_set(err, AA_EINVAL, "scene.name",
                          "not an animation (rotating-triangle, translating-circle)");
    json_t *pj = json_object_get(spec, "pattern");
    if (!rc && !pj)
        rc = aa_error_set(err, AA_EINVAL, "pattern", "a pattern is required");
    if (!rc)
        rc = proto_render_pattern_decode(pj, &ap->pattern, "pattern", err);
    return rc;
}

void proto_animation_spec_free(proto_animation_spec *ap)
{
    aa_pattern_free(&ap->pattern);
}

static json_t *encode_frame(const proto_animation_frame *f)
{
    return json_pack("{s:I, s:f, s:f, s:I, s:I, s:I, s:f, s:f, s:O*}", "frame",
                     (json_int_t)f->frame, "rmse", f->rmse, "max_dev", f->max_dev,
                     "pixels_recomputed", (json_int_t)f->pixels_recomputed, "pattern_sampled",
                     (json_int_t)f->pattern_sampled, "reference_supersampled",
                     (json_int_t)f->reference_supersampled, "pattern_seconds", f->pattern_seconds,
                     "reference_seconds", f->reference_seconds, "tiles", f->tiles);
}

json_t *proto_encode_animation_result(const proto_animation_result *r)
{
    json_t *frames = json_array();
    for (size_t i = 0; frames && i < r->frame_count; i++)
        if (json_array_append_new(frames, encode_frame(&r->frames[i]))) {
            json_decref(frames);
            return NULL;
        }
    json_t *out =
        json_pack("{s:o, s:{s:s, s:f}, s:f, s:o, s:o, s:{s:f, s:f}, s:{s:I, s:I}}", "scene",
                  proto_encode_scene(&r->scene), "pattern", "family", r->family,
                  "samples_per_pixel", r->samples_per_pixel, "e2", r->e2, "frames", frames, "total",
                  proto_encode_diff(&r->total), "times", "pattern_seconds", r->pattern_seconds,
                  "reference_seconds", r->reference_seconds, "pixels", "recomputed",
                  (json_int_t)r->pixels_recomputed, "all_frames", (json_int_t)r->pixels_all_frames);
    if (out && !proto_acuity_ref_encode(out, r->acuity_name, r->acuity_version)) {
        json_decref(out);
        return NULL;
    }
    return out;
}

static const char *const result_keys[] = {"scene", "pattern", "e2",     "frames", "total",
                                          "times", "pixels",  "acuity", NULL};
static const char *const pattern_keys[] = {"family", "samples_per_pixel", NULL};
static const char *const frame_keys[] = {"frame",           "rmse",
                                         "max_dev",         "pixels_recomputed",
                                         "pattern_sampled", "reference_supersampled",
                                         "pattern_seconds", "reference_seconds",
                                         "tiles",           NULL};
static const char *const times_keys[] = {"pattern_seconds", "reference_seconds", NULL};
static const char *const pixels_keys[] = {"recomputed", "all_frames", NULL};

static int decode_object(const json_t *j, const char *const *keys, const char *at, aa_error *err)
{
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, at, "must be an object");
    return proto_check_keys(j, keys, err, at);
}

static int decode_frame(const json_t *j, proto_animation_frame *f, const char *at, aa_error *err)
{
    int rc = decode_object(j, frame_keys, at, err);
    if (!rc)
        rc = proto_result_count(j, "frame", &f->frame, at, err);
    if (!rc)
        rc = proto_result_number(j, "rmse", &f->rmse, at, err);
    if (!rc)
        rc = proto_result_number(j, "max_dev", &f->max_dev, at, err);
    if (!rc)
        rc = proto_result_count(j, "pixels_recomputed", &f->pixels_recomputed, at, err);
    if (!rc)
        rc = proto_result_count(j, "pattern_sampled", &f->pattern_sampled, at, err);
    if (!rc)
        rc = proto_result_count(j, "reference_supersampled", &f->reference_supersampled, at, err);
    if (!rc)
        rc = proto_result_number(j, "pattern_seconds", &f->pattern_seconds, at, err);
    if (!rc)
        rc = proto_result_number(j, "reference_seconds", &f->reference_seconds, at, err);
    if (!rc)
        rc = proto_result_tile(j, "tiles", &f->tiles, at, err);
    return rc;
}

int proto_decode_animation_result(const json_t *j, proto_animation_result *r, aa_error *err)
{
    memset(r, 0, sizeof *r);
    const json_t *pattern = json_object_get(j, "pattern"), *frames = json_object_get(j, "frames");
    const json_t *times = json_object_get(j, "times"), *pixels = json_object_get(j, "pixels");
    int rc = decode_object(j, result_keys, "", err);
    if (!rc)
        rc = proto_decode_scene(json_object_get(j, "scene"), &r->scene, "scene", err);
    if (!rc)
        rc = decode_object(pattern, pattern_keys, "pattern", err);
    if (!rc)
        rc = proto_result_string(pattern, "family", r->family, sizeof r->family, "pattern", err);
    if (!rc)
        rc = proto_result_number(pattern, "samples_per_pixel", &r->samples_per_pixel, "pattern",
                                 err);
    if (!rc)
        rc = proto_result_number(j, "e2", &r->e2, "", err);
    if (!rc && !json_is_array(frames))
        rc = aa_error_set(err, AA_EINVAL, "frames", "must be an array");
    size_t n = json_array_size(frames);
    if (!rc && n && !(r->frames = calloc(n, sizeof *r->frames)))
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t i = 0; !rc && i < n; i++) {
        char at[32];
        snprintf(at, sizeof at, "frames[%zu]", i);
        r->frame_count = i + 1;
        rc = decode_frame(json_array_get(frames, i), &r->frames[i], at, err);
    }
    if (!rc)
        rc = proto_decode_diff(json_object_get(j, "total"), &r->total, "total", err);
    if (!rc)
        rc = decode_object(times, times_keys, "times", err);
    if (!rc)
        rc = proto_result_number(times, "pattern_seconds", &r->pattern_seconds, "times", err);
    if (!rc)
        rc = proto_result_number(times, "reference_seconds", &r->reference_seconds, "times", err);
    if (!rc)
        rc = decode_object(pixels, pixels_keys, "pixels", err);
    if (!rc)
        rc = proto_result_count(pixels, "recomputed", &r->pixels_recomputed, "pixels", err);
    if (!rc)
        rc = proto_result_count(pixels, "all_frames", &r->pixels_all_frames, "pixels", err);
    if (!rc)
        rc = proto_acuity_ref_decode(j, r->acuity_name, sizeof r->acuity_name, &r->acuity_version,
                                     err);
    if (rc)
        proto_animation_result_free(r);
    return rc;
}

void proto_animation_result_free(proto_animation_result *r)
{
    for (size_t i = 0; i < r->frame_count; i++)
        json_decref(r->frames[i].tiles);
    free(r->frames);
    memset(r, 0, sizeof *r);
}
