/* The spec fields the render job kinds (compare, animation, reference-convergence) share,
 * decoded in one place: "scene" (and "size"), "reference", and where the kind takes them
 * "acuity" and "tiles". Each kind names its own keys; render_spec_decode checks the spec
 * against the shared keys plus those (one unknown-key check, proto_check_keys) and decodes the
 * shared ones. Scenes and references are decoded by the tile layer's codec. */
#ifndef AALAB_RENDER_SPEC_H
#define AALAB_RENDER_SPEC_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_core.h"
#include "aa_metric.h"
#include "tile_render.h"

enum {
    RENDER_SPEC_ACUITY = 1u << 0,
    RENDER_SPEC_TILES = 1u << 1,
};

typedef struct render_spec {
    aa_scene_params scene;
    proto_reference_spec ref; /* ref.params.filter points into ref: never copy a render_spec */
    aa_acuity acuity;         /* default naiman */
    bool tiles;               /* default true: put the images in the tile store */
} render_spec;

int render_spec_decode(const json_t *spec, const char *const *kind_keys, unsigned fields,
                       render_spec *out, aa_error *err);

#endif
