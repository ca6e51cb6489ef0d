/* Rendered images as PNG tiles in the tile store, each answered as its JSON reference
 * {"id", "url", "width", "height", "bytes"}: shared by POST /v1/render and the render job kinds.
 * The request and answer forms around them are proto's (codec_scene.h, codec_render.h). */
#ifndef AALAB_TILE_RENDER_H
#define AALAB_TILE_RENDER_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_render.h"
#include "codec_scene.h"
#include "tile_store.h"

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
                                  const proto_crop *crop, aa_error *err);

#endif
