/* The temporal pattern form {"temporal": {...}} (proto/schemas/temporal.json, docs/temporal.md):
 * a jitter sequence, a frame pattern, a resolve and a blend, decoded into an aa_temporal_spec;
 * the temporal presets (facts with their provenance); the evaluate answer. */
#ifndef AALAB_PROTO_CODEC_TEMPORAL_H
#define AALAB_PROTO_CODEC_TEMPORAL_H

#include <stdbool.h>
#include <stddef.h>

#include <jansson.h>

#include "aa_temporal.h"

typedef struct proto_temporal {
    size_t count;
    aa_point *jitter; /* [count] */
    double jitter_range;
    bool has_frame;
    aa_pattern frame;
    bool has_resolve;
    aa_temporal_resolve resolve;
    aa_blend blend;
    size_t cut_frames;  /* 0: the default 4 N */
    const char *preset; /* NULL or the preset's name (static) */
    const char *source; /* the preset's provenance (static) */
} proto_temporal;

/* j is the pattern object holding "temporal" (other keys of it are rejected); fields are named
 * relative to field_prefix ("pattern.temporal.blend.alpha"). On error *out holds nothing to
 * free (freeing is safe). */
int proto_decode_temporal(const json_t *j, proto_temporal *out, const char *field_prefix,
                          aa_error *err);
/* The inner temporal object v (the value of "temporal", without "preset"): what a job spec that
 * gives a sequence's setting beside a family decodes (fields named relative to field_prefix). */
int proto_decode_temporal_object(const json_t *v, proto_temporal *out, const char *field_prefix,
                                 aa_error *err);
aa_temporal_spec proto_temporal_spec(const proto_temporal *t);
/* Builds the engine's sequence of t into out; an error's field is named under field_prefix
 * ("pattern.temporal" + "jitter[3]"). */
int proto_temporal_build(const proto_temporal *t, const char *field_prefix, aa_temporal *out,
                         aa_error *err);
void proto_temporal_free(proto_temporal *t);
/* A deep copy (out owns its jitter and frame pattern). */
int proto_temporal_copy(const proto_temporal *t, proto_temporal *out, aa_error *err);
/* The explicit wire form {"temporal": {"jitter": [[x, y], ...], "jitter_range", "blend",
 * "frame_pattern"?, "resolve"?, "cut_frames"?}} that decodes back to the same kernels bit for
 * bit (offsets as 17-digit numbers); NULL when out of memory. */
json_t *proto_encode_temporal(const proto_temporal *t);

/* The evaluate answer: E2 (worst phase), its argmax, the mean over phases, per phase E2 and E1
 * per group and angle, F2 and F1 per group and angle, the after-cut curve and frames to 5 %. */
json_t *proto_encode_temporal_evaluation(const aa_temporal_evaluation *e, const aa_temporal *t,
                                         const proto_temporal *spec);

typedef struct proto_temporal_preset {
    const char *name;
    const char *spec; /* the temporal object as JSON */
    const char *source;
} proto_temporal_preset;
size_t proto_temporal_preset_count(void);
const proto_temporal_preset *proto_temporal_preset_at(size_t i);

#endif
