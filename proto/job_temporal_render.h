/* Spec and result of the "temporal-render" job kind: a still scene rendered through the TAA loop
 * of a temporal pattern (docs/temporal.md §9, render/taa_render.h) against the supersampled
 * reference, with the edge model's prediction per phase beside the render.
 * Spec: {"scene" (a still scene), "size", "reference", "acuity", "tiles",
 *        "pattern": {"temporal": {...}} (proto/schemas/temporal.json; its cut_frames is K of the
 *        after-cut curve, default 4 N)}. */
#ifndef AALAB_PROTO_JOB_TEMPORAL_RENDER_H
#define AALAB_PROTO_JOB_TEMPORAL_RENDER_H

#include "codec_temporal.h"
#include "job_render_spec.h"

/* The job's E2 part (aa_temporal_evaluate of the phase kernels, one cut frame) is not
 * cancellable: its work, group samples x (2 N + 1) x angles, is bounded at submission (2^27 is
 * about 10 s at 70 ns per sample-angle). The TAA loop and the predictions report progress. */
#define PROTO_TEMPORAL_RENDER_MAX_EVAL_WORK (1L << 27)

typedef struct proto_temporal_render_spec {
    proto_render_spec common;
    proto_temporal temporal;
    aa_temporal built; /* the expanded pattern */
    size_t cut_frames; /* K */
} proto_temporal_render_spec;

/* Kernel samples of one phase of the temporal pattern (every frame's, for every output pixel of
 * the frame pattern), from the spec alone: what aa_temporal_build will allocate, for bounds. */
double proto_temporal_planned_samples(const proto_temporal *t);

/* Errors name "scene.name", "pattern", "pattern.temporal..." and the shared render fields. */
int proto_decode_temporal_render_spec(const json_t *spec, proto_temporal_render_spec *out,
                                      aa_error *err);
void proto_temporal_render_spec_free(proto_temporal_render_spec *s);

/* What the kind measured, encoded by proto_encode_temporal_render_result. Arrays are owned. */
typedef struct proto_temporal_render_result {
    aa_scene_params scene;
    long long reference_spp, reference_seed;
    char filter[24];
    double output_offset;
    size_t phase_count, group_count, cut_count;
    double samples_per_pixel;
    aa_blend blend;
    aa_point *jitter; /* [N] */
    char preset[32];
    double e2, mean_phase_e2, f2;
    double *phase_e2, *phase_rmse, *phase_max_dev, *phase_predicted; /* [N]; predicted NaN: none */
    size_t worst_phase;
    double *cut_rmse; /* [K] */
    long frames_to_5pct;
    double flicker_step_rmse, flicker_mean_rmse;
    double flicker_predicted, flicker_step_predicted; /* aa_taa_predict_flicker's; NaN: none */
    double reference_seconds, taa_seconds, predict_seconds;
    long long pixels_sampled, samples_evaluated;
    json_t *tiles; /* {"reference", "pattern", "difference"} of the worst phase, or NULL */
    char acuity_name[24];
    int acuity_version;
} proto_temporal_render_result;

/* {"scene", "reference": {"spp", "seed", "filter", "output_offset"}, "pattern": {"family",
 * "phase_count", "group_count", "samples_per_pixel", "blend", "jitter", "preset"?}, "e2",
 * "mean_phase_e2", "f2", "phases": [{"phase", "e2", "rmse", "max_dev", "predicted_rmse"?,
 * "ratio"?}], "steady": {"worst_phase", "rmse", "mean_rmse", "predicted_rmse"?, "ratio"?},
 * "after_cut": [rmse], "frames_to_5pct", "flicker": {"step_rmse", "mean_rmse",
 * "predicted_mean_rmse"?, "ratio"?}, "times", "pixels", "tiles"?, "acuity"}
 * (proto/schemas/kinds/temporal-render.result.json). */
json_t *proto_encode_temporal_render_result(const proto_temporal_render_result *r);
void proto_temporal_render_result_free(proto_temporal_render_result *r);

#endif
