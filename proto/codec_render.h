/* POST /v1/render on the wire: the request body decoded into engine values and the answer
 * encoded from a render result. Limits that depend on the daemon's configuration (tile size,
 * work per request, wall time) are the handler's; this checks only the form.
 *
 * Request: {"scene": name | {...}, "size": [w, h], "pattern": name | {...} (required),
 *           "reference": {...}, "crop": {...}, "acuity": {...}, "visibility": "team"|"private",
 *           "phase": p (a temporal pattern only)}
 * (scene, reference and crop as in codec_scene.h; pattern and acuity as in codec.h). */
#ifndef AALAB_PROTO_CODEC_RENDER_H
#define AALAB_PROTO_CODEC_RENDER_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_metric.h"
#include "codec_scene.h"

/* Holds pointers into itself once decoded (reference.params.filter): do not copy it. */
typedef struct proto_render_request {
    aa_scene_params scene;
    aa_pattern pattern;
    proto_reference_spec reference;
    proto_crop crop;
    aa_acuity acuity;
    bool private_tiles; /* "visibility": "private" */
    /* A temporal pattern renders one phase's steady state: pattern holds that phase's kernels
     * (aa_taa_phase_pattern), phase its index ("phase", default 0) of phase_count; -1 and 0 for a
     * spatial pattern. */
    long phase;
    size_t phase_count;
} proto_render_request;

/* "team" (also when j is NULL) or "private"; anything else is AA_EINVAL naming field. */
int proto_decode_visibility(const json_t *j, bool *private_out, const char *field, aa_error *err);
/* On error out holds nothing to free; on success free it with proto_render_request_free. */
int proto_decode_render_request(const json_t *body, proto_render_request *out, aa_error *err);
void proto_render_request_free(proto_render_request *r);
/* The render parameters the request asks for: scene, reference and acuity (pointing into r). */
aa_render_params proto_render_params(const proto_render_request *r);

/* The answer: {"scene", "pattern": {"family", "samples_per_pixel", "kernels", "kernel_size",
 * "border"}, "reference": {"spp", "seed", "filter"}, "e2", "stats" (proto_encode_diff),
 * "times": {"pattern_seconds", "reference_seconds"}, "pixels": {...}, "tiles"}. tiles (the
 * stored images) is taken over, also on failure. NULL on allocation failure. A temporal pattern's
 * phase is added as "temporal": {"phase", "phase_count"} by proto_encode_render_phase. */
json_t *proto_encode_render_result(const aa_render_params *rp, const aa_pattern *p,
                                   const aa_render_result *r, json_t *tiles);

/* Adds "temporal": {"phase", "phase_count"} to a render answer when r rendered a temporal phase. */
void proto_encode_render_phase(json_t *answer, const proto_render_request *r);

#endif
