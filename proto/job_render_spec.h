/* The spec fields the render job kinds (compare, animation, reference-convergence) share,
 * decoded in one place: "scene" (and "size"), "reference", and where the kind takes them
 * "acuity" and "tiles". Each kind names its own keys; proto_render_spec_decode checks the spec
 * against the shared keys plus those (one unknown-key check) and decodes the shared ones.
 * Also the pieces their results share: difference statistics and tile references. */
#ifndef AALAB_PROTO_JOB_RENDER_SPEC_H
#define AALAB_PROTO_JOB_RENDER_SPEC_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_core.h"
#include "aa_metric.h"
#include "aa_pattern.h"
#include "aa_render.h"
#include "codec_scene.h"

enum {
    PROTO_RENDER_SPEC_ACUITY = 1u << 0,
    PROTO_RENDER_SPEC_TILES = 1u << 1,
};

typedef struct proto_render_spec {
    aa_scene_params scene;
    proto_reference_spec ref; /* ref.params.filter points into ref: never copy the struct */
    aa_acuity acuity;         /* default naiman */
    bool tiles;               /* default true: put the images in the tile store */
} proto_render_spec;

int proto_render_spec_decode(const json_t *spec, const char *const *kind_keys, unsigned fields,
                             proto_render_spec *out, aa_error *err);

/* A render kind's pattern: a preset name ("flipquad", an unknown name suggests the nearest
 * ones) or a pattern object (proto/codec.h). */
int proto_render_pattern_decode(const json_t *j, aa_pattern *out, const char *field, aa_error *err);

/* The difference statistics proto_encode_diff writes, read back strictly (prefix: the JSON
 * path of the object). The histogram is kept; the penalised histogram is recomputed from it,
 * as aa_diff_finish does, and must agree with it. */
int proto_decode_diff(const json_t *j, aa_diff_stats *out, const char *prefix, aa_error *err);
/* A tile reference in a result (an object the tile store made; opaque here): obj[key] absent
 * or an object. *out is a new reference or NULL. */
int proto_result_tile(const json_t *obj, const char *key, json_t **out, const char *prefix,
                      aa_error *err);
/* obj[key] as a string of at most size - 1 bytes copied into out. */
int proto_result_string(const json_t *obj, const char *key, char *out, size_t size,
                        const char *prefix, aa_error *err);
/* obj[key] as an integer >= 0. */
int proto_result_count(const json_t *obj, const char *key, long long *out, const char *prefix,
                       aa_error *err);
/* obj[key] as a finite number (the render results hold no nulls). */
int proto_result_number(const json_t *obj, const char *key, double *out, const char *prefix,
                        aa_error *err);

#endif
