/* JSON side of the renderer, shared by POST /v1/render and the render job kinds: decoding the
 * scene / reference / crop objects (every bad field named by its JSON path), encoding the
 * statistics, and storing the images as PNG tiles.
 *
 * Request objects (all fields optional; unknown fields are rejected):
 *   scene:     {"name": "siemens-star", "width": 256, "height": 256, "zoom": 1, "angle": 0,
 *               "wedges": 16, "frames": 16, "frame": 0, "offset": 0, "mirror_x": false,
 *               "mirror_y": false}
 *   reference: {"spp": 1024, "seed": 1, "filter": "mitchell" | {"name": "mitchell", "B": ..,
 *               "C": .., "radius": .., "sigma": .., "a": ..}}
 *   crop:      {"x": 0, "y": 0, "width": 32, "height": 32, "scale": 8}  (magnified crop)
 * A pattern given as a string is a preset name (tile_pattern_from_preset_name). */
#ifndef AALAB_TILE_RENDER_H
#define AALAB_TILE_RENDER_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_render.h"
#include "tile_store.h"

#define TILE_MAX_CROP_SCALE 32
#define TILE_MAX_CROP_PIXELS (1024 * 1024) /* magnified crop size */

typedef struct tile_crop {
    bool enabled;
    aa_rect rect;
    int scale;
} tile_crop;

/* Reference settings plus storage for a decoded filter (params.filter points into it). */
typedef struct tile_reference_spec {
    aa_reference_params params;
    aa_filter filter;
} tile_reference_spec;

/* prefix is the JSON path of the object ("scene", "reference", ...). j may be NULL (defaults).
 * Return AA_OK or AA_EINVAL with err->field = "<prefix>.<field>". */
int tile_decode_scene(const json_t *j, aa_scene_params *out, const char *prefix, aa_error *err);
/* The scene of a request object: "scene" as a name or object, and the optional top-level
 * "size":[w,h] (the short form). */
int tile_decode_scene_request(const json_t *request, aa_scene_params *out, aa_error *err);
int tile_decode_reference(const json_t *j, tile_reference_spec *out, const char *prefix,
                          aa_error *err);
int tile_decode_crop(const json_t *j, int width, int height, tile_crop *out, const char *prefix,
                     aa_error *err);
/* If j is a string, builds the preset of that name (AA_EINVAL naming field if unknown) and
 * returns AA_OK; returns 1 (nothing done) when j is not a string. */
int tile_pattern_from_preset_name(const json_t *j, aa_pattern *p, const char *field, aa_error *err);

json_t *tile_encode_scene(const aa_scene_params *p);
/* {"rmse", "max_dev", "pixels", "histogram": [256], "penalised_histogram": [256]} */
json_t *tile_encode_diff(const aa_diff_stats *d);

/* Stores PNGs with an access (NULL = team) and returns {"id", "url", "width", "height",
 * "bytes"}; NULL with err on failure. */
json_t *tile_put_gray8_as(tile_store *ts, const tile_access *access, const uint8_t *px, int width,
                          int height, aa_error *err);
json_t *tile_put_image(tile_store *ts, const tile_access *access, const aa_image *img,
                       aa_error *err);
json_t *tile_put_difference(tile_store *ts, const tile_access *access, const aa_image *a,
                            const aa_image *ref, aa_error *err);
/* {"pattern", "reference", "difference"} (and "crop": {...} of the three when enabled). */
json_t *tile_put_render_images_as(tile_store *ts, const tile_access *access,
                                  const aa_image *pattern, const aa_image *reference,
                                  const tile_crop *crop, aa_error *err);

/* The whole answer for one tile render; its tiles stored with access (NULL = team). */
json_t *tile_render_result_json(tile_store *ts, const tile_access *access,
                                const aa_render_params *rp, const aa_pattern *p,
                                const aa_render_result *r, const tile_crop *crop, aa_error *err);

#endif
