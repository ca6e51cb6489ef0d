/* Spec and result of the "animation" job kind: a moving scene rendered frame by frame with a
 * pattern beside the reference (Hasselgren et al. 2005, sec. 6.1).
 * Spec: {"scene": {"name": "rotating-triangle" | "translating-circle", "frames", ...}, "size",
 * "pattern": preset name or pattern object, "reference", "acuity", "tiles"}. */
#ifndef AALAB_PROTO_JOB_ANIMATION_H
#define AALAB_PROTO_JOB_ANIMATION_H

#include "job_render_spec.h"

typedef struct proto_animation_spec {
    proto_render_spec common;
    aa_pattern pattern;
} proto_animation_spec;

int proto_decode_animation_spec(const json_t *spec, proto_animation_spec *out, aa_error *err);
void proto_animation_spec_free(proto_animation_spec *s);

typedef struct proto_animation_frame {
    long long frame;
    double rmse, max_dev;
    long long pixels_recomputed, pattern_sampled, reference_supersampled;
    double pattern_seconds, reference_seconds;
    json_t *tiles; /* tile references of the frame's images, or NULL */
} proto_animation_frame;

typedef struct proto_animation_result {
    aa_scene_params scene;
    char family[48];
    double samples_per_pixel, e2;
    proto_animation_frame *frames;
    size_t frame_count;
    aa_diff_stats total;
    double pattern_seconds, reference_seconds;
    long long pixels_recomputed, pixels_all_frames;
    /* The acuity table e2 uses (proto_acuity_ref_set); "" in results stored before it was
     * recorded. */
    char acuity_name[24];
    int acuity_version;
} proto_animation_result;

/* {"scene", "pattern": {"family", "samples_per_pixel"}, "e2", "frames": [{"frame", "rmse",
 * "max_dev", "pixels_recomputed", "pattern_sampled", "reference_supersampled",
 * "pattern_seconds", "reference_seconds", "tiles"?}], "total": difference statistics,
 * "times": {"pattern_seconds", "reference_seconds"}, "pixels": {"recomputed", "all_frames"},
 * "acuity"?: {"name", "version"}}; NULL when out of memory. */
json_t *proto_encode_animation_result(const proto_animation_result *r);
int proto_decode_animation_result(const json_t *j, proto_animation_result *out, aa_error *err);
void proto_animation_result_free(proto_animation_result *r);

#endif
