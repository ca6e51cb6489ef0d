/* POST /v1/predict on the wire: the edge model's RMSE prediction (server/engine/render/predict.h)
 * for one pattern or a list of patterns on one scene, without rendering.
 *
 * Request: {"scene": name | {...}, "size": [w, h], "pattern": name | {...} or
 *           "patterns": [name | {...}, ...] (exactly one of the two; at most
 *           PROTO_PREDICT_MAX_PATTERNS), "reference": {...}, "e1_by_angle": bool,
 *           "model": "edge" | "reference-profile" | "exact"}
 * scene, size and pattern as in POST /v1/render (codec_render.h); of "reference" only the filter
 * matters (spp and seed are accepted, so that a render request's body predicts as is).
 * "e1_by_angle": true adds each pattern's E1 at all 180 bins (for drawing it, as the dashboard's
 * Tiles view does); off by default, since it costs E1 at every angle, not only the scene's.
 * "model" picks predict.h's model flags: "edge" (0, the default), "reference-profile"
 * (AA_PREDICT_REFERENCE_PROFILE) or "exact" (AA_PREDICT_EXACT_REFERENCE); E1 everywhere in the
 * answer (angles[].e1_rms, e1_by_angle) is then measured against the same reference. */
#ifndef AALAB_PROTO_CODEC_PREDICT_H
#define AALAB_PROTO_CODEC_PREDICT_H

#include <stdbool.h>
#include <stddef.h>

#include <jansson.h>

#include "aa_render.h"
#include "codec_scene.h"

#define PROTO_PREDICT_MAX_PATTERNS 64
/* Phase patterns of the request's temporal patterns: their kernel samples in all (each costs at
 * least one E1 evaluation, so the handler's work bound, 2^23, refuses more anyway). */
#define PROTO_PREDICT_MAX_PHASE_SAMPLES (1L << 23)

typedef struct proto_predict_request {
    aa_scene_params scene;
    size_t pattern_count;
    aa_pattern *patterns; /* [pattern_count] */
    char (*names)[64];    /* [pattern_count]: preset name, or "" */
    /* A temporal pattern {"temporal": {...}} is predicted per phase: it expands into one
     * pattern per phase (its phase kernels, aa_taa_phase_pattern), each with these set. */
    size_t *source;                 /* [pattern_count]: index of the pattern in the request */
    long *phase;                    /* [pattern_count]: the phase, or -1 for a spatial pattern */
    size_t *phase_count;            /* [pattern_count]: N, or 0 */
    proto_reference_spec reference; /* reference.params.filter points into it: no copies */
    bool single;                    /* "pattern" (not "patterns") */
    bool e1_by_angle;               /* answer with E1 at every bin */
    unsigned model;                 /* predict.h's AA_PREDICT_* flags */
} proto_predict_request;

/* On error out holds nothing to free; on success free it with proto_predict_request_free.
 * Errors name "pattern", "patterns", "patterns[i]...", "scene...", "size", "reference...". */
int proto_decode_predict_request(const json_t *body, proto_predict_request *out, aa_error *err);
void proto_predict_request_free(proto_predict_request *r);
/* JSON field of (expanded) pattern i as the request named it: "pattern" or "patterns[j]". */
void proto_predict_pattern_field(const proto_predict_request *r, size_t i, char *out, size_t cap);

/* The wire name of model flags: "edge", "reference-profile", "exact" (NULL: no wire name). */
const char *proto_predict_model_name(unsigned model);

/* {"scene", "reference": {"filter"}, "model", "edges": {...}, "predictions": [...]}
 * (proto/schemas/predict_response.json). pred[i] belongs to r->patterns[i]; e1_by_angle[i]
 * (aa_predict_e1_rms at every bin), when not NULL, is encoded as predictions[i].e1_by_angle.
 * NULL on allocation failure. */
json_t *proto_encode_predictions(const proto_predict_request *r, const aa_edge_histogram *h,
                                 const aa_prediction *pred,
                                 const double (*e1_by_angle)[AA_EDGE_BINS]);

#endif
