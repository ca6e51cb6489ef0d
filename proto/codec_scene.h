/* The renderer's wire forms, shared by POST /v1/render and the render job kinds: scene,
 * reference and crop objects decoded into engine values (every bad field named by its JSON
 * path), and the scene and difference statistics encoded back.
 *
 * Request objects (all fields optional; unknown fields are rejected):
 *   scene:     {"name": "siemens-star", "width": 256, "height": 256, "zoom": 1, "angle": 0,
 *               "wedges": 16, "frames": 16, "frame": 0, "offset": 0, "mirror_x": false,
 *               "mirror_y": false}
 *   reference: {"spp": 1024, "seed": 1, "filter": "mitchell" | {"name": "mitchell", "B": ..,
 *               "C": .., "radius": .., "sigma": .., "a": ..}}
 *   crop:      {"x": 0, "y": 0, "width": 32, "height": 32, "scale": 8}  (magnified crop)
 * A pattern given as a string is a preset name (proto_pattern_from_preset_name). */
#ifndef AALAB_PROTO_CODEC_SCENE_H
#define AALAB_PROTO_CODEC_SCENE_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_core.h"
#include "aa_pattern.h"
#include "aa_render.h"

#define PROTO_MAX_CROP_SCALE 32
#define PROTO_MAX_CROP_PIXELS (1024 * 1024) /* magnified crop size */

typedef struct proto_crop {
    bool enabled;
    aa_rect rect;
    int scale;
} proto_crop;

/* Reference settings plus storage for a decoded filter (params.filter points into it). */
typedef struct proto_reference_spec {
    aa_reference_params params;
    aa_filter filter;
} proto_reference_spec;

/* prefix is the JSON path of the object ("scene", "reference", ...). j may be NULL (defaults).
 * Return AA_OK or AA_EINVAL with err->field = "<prefix>.<field>". */
int proto_decode_scene(const json_t *j, aa_scene_params *out, const char *prefix, aa_error *err);
/* The scene of a request object: "scene" as a name or object, and the optional top-level
 * "size":[w,h] beside it. */
int proto_decode_scene_request(const json_t *request, aa_scene_params *out, aa_error *err);
int proto_decode_reference(const json_t *j, proto_reference_spec *out, const char *prefix,
                           aa_error *err);
/* A crop of an image of width x height; j NULL or null: no crop (out->enabled false). */
int proto_decode_crop(const json_t *j, int width, int height, proto_crop *out, const char *prefix,
                      aa_error *err);
/* If j is a string, builds the preset of that name (AA_EINVAL naming field if unknown) and
 * returns AA_OK; returns 1 (nothing done) when j is not a string. */
int proto_pattern_from_preset_name(const json_t *j, aa_pattern *p, const char *field,
                                   aa_error *err);
/* A pattern as the render requests and kinds take it: a preset name, or any form of
 * proto_decode_pattern (flags as there). */
int proto_decode_pattern_or_name(const json_t *j, unsigned flags, aa_pattern *p, const char *field,
                                 aa_error *err);

/* {"name","width","height","zoom","angle","wedges","mirror_x","mirror_y"} plus "frames" and
 * "frame" for animations and "offset" for the half-plane. NULL on allocation failure. */
json_t *proto_encode_scene(const aa_scene_params *p);
/* {"rmse", "max_dev", "pixels", "histogram": [256], "penalised_histogram": [256]} */
json_t *proto_encode_diff(const aa_diff_stats *d);

#endif
