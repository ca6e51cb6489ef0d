#include "job_temporal_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "codec_internal.h"

static const char *const kind_keys[] = {"pattern", NULL};

double proto_temporal_planned_samples(const proto_temporal *t)
{
    double per_frame;
    if (t->has_resolve) {
        int T = t->has_frame ? t->frame.tile : 1, R = t->resolve.radius;
        double tc = t->has_frame ? (double)t->frame.tile_count : 1;
        double reach = T > 0 ? (double)((2 * R + 1 + T - 1) / T + 1) : 1;
        per_frame = (double)(T > 0 ? T * T : 1) * tc * reach * reach;
    } else {
        per_frame = t->has_frame ? (double)aa_pattern_total_kernel_samples(&t->frame) : 1;
    }
    return (double)t->count * per_frame;
}

int proto_decode_temporal_render_spec(const json_t *spec, proto_temporal_render_spec *s,
                                      aa_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = proto_render_spec_decode(
        spec, kind_keys, PROTO_RENDER_SPEC_ACUITY | PROTO_RENDER_SPEC_TILES, &s->common, err);
    if (!rc && aa_scene_shape_is_animation(s->common.scene.shape))
        rc = aa_error_set(err, AA_EINVAL, "scene.name",
                          "the TAA loop renders a still scene (not %s)",
                          aa_scene_shape_name(s->common.scene.shape));
    const json_t *pj = json_object_get(spec, "pattern");
    if (!rc && !(json_is_object(pj) && json_object_get(pj, "temporal")))
        rc = aa_error_set(err, AA_EINVAL, "pattern",
                          "a temporal pattern {\"temporal\": {...}} is required (spatial "
                          "patterns render with the compare kind)");
    if (!rc)
        rc = proto_decode_temporal(pj, &s->temporal, "pattern", err);
    if (!rc &&
        proto_temporal_planned_samples(&s->temporal) * (2.0 * (double)s->temporal.count + 1) * 36 >
            (double)PROTO_TEMPORAL_RENDER_MAX_EVAL_WORK)
        rc = aa_error_set(err, AA_ERANGE, "pattern.temporal",
                          "%.0f samples per output pixel over %zu phases is more than a render "
                          "job evaluates (group samples x (2 N + 1) x 36 angles <= %ld)",
                          proto_temporal_planned_samples(&s->temporal), s->temporal.count,
                          PROTO_TEMPORAL_RENDER_MAX_EVAL_WORK);
    if (!rc)
        rc = proto_temporal_build(&s->temporal, "pattern.temporal", &s->built, err);
    if (!rc) {
        s->cut_frames = s->temporal.cut_frames ? s->temporal.cut_frames : 4 * s->built.phase_count;
        if (s->cut_frames > AA_TEMPORAL_MAX_CUT_FRAMES)
            s->cut_frames = AA_TEMPORAL_MAX_CUT_FRAMES;
    }
    if (rc)
        proto_temporal_render_spec_free(s);
    return rc;
}

void proto_temporal_render_spec_free(proto_temporal_render_spec *s)
{
    aa_temporal_free(&s->built);
    proto_temporal_free(&s->temporal);
}

void proto_temporal_render_result_free(proto_temporal_render_result *r)
{
    free(r->jitter);
    free(r->phase_e2);
    free(r->phase_rmse);
    free(r->phase_max_dev);
    free(r->phase_predicted);
    free(r->cut_rmse);
    json_decref(r->tiles);
    memset(r, 0, sizeof *r);
}

/* predicted / rendered, or nothing when either is missing or the render is exact. */
static void set_prediction(json_t *o, double predicted, double rendered)
{
    if (!isfinite(predicted))
        return;
    json_object_set_new(o, "predicted_rmse", proto_real(predicted));
    if (rendered > 0)
        json_object_set_new(o, "ratio", proto_real(predicted / rendered));
}

json_t *proto_encode_temporal_render_result(const proto_temporal_render_result *r)
{
    size_t N = r->phase_count;
    json_t *phases = json_array(), *jit = json_array();
    double mean_sq = 0, pred_sq = 0;
    bool all_predicted = true;
    for (size_t p = 0; phases && p < N; p++) {
        json_t *row = json_pack("{s:I,s:o,s:o,s:o}", "phase", (json_int_t)p, "e2",
                                proto_real(r->phase_e2[p]), "rmse", proto_real(r->phase_rmse[p]),
                                "max_dev", proto_real(r->phase_max_dev[p]));
        if (row)
            set_prediction(row, r->phase_predicted[p], r->phase_rmse[p]);
        json_array_append_new(phases, row);
        mean_sq += r->phase_rmse[p] * r->phase_rmse[p];
        pred_sq += r->phase_predicted[p] * r->phase_predicted[p];
        all_predicted = all_predicted && isfinite(r->phase_predicted[p]);
    }
    for (size_t f = 0; jit && f < N; f++)
        json_array_append_new(jit, json_pack("[ff]", r->jitter[f].x, r->jitter[f].y));
    char family[32];
    snprintf(family, sizeof family, "T(%zu)", N);
    json_t *blend = r->blend.kind == AA_BLEND_BOX ? json_pack("{s:s}", "kind", "box")
                                                  : json_pack("{s:s,s:o}", "kind", "exponential",
                                                              "alpha", proto_real(r->blend.alpha));
    json_t *pattern =
        json_pack("{s:s,s:I,s:I,s:o,s:o,s:o}", "family", family, "phase_count", (json_int_t)N,
                  "group_count", (json_int_t)r->group_count, "samples_per_pixel",
                  proto_real(r->samples_per_pixel), "blend", blend, "jitter", jit);
    if (pattern && r->preset[0])
        json_object_set_new(pattern, "preset", json_string(r->preset));
    /* The RMS over phases (the error of the steady state seen over a period). */
    double mean_rmse = N ? sqrt(mean_sq / (double)N) : 0;
    json_t *steady =
        json_pack("{s:I,s:o,s:o}", "worst_phase", (json_int_t)r->worst_phase, "rmse",
                  proto_real(r->phase_rmse[r->worst_phase]), "mean_rmse", proto_real(mean_rmse));
    if (steady && all_predicted)
        set_prediction(steady, sqrt(pred_sq / (double)N), mean_rmse);
    json_t *out = json_pack(
        "{s:o,s:{s:I,s:I,s:s,s:o},s:o,s:o,s:o,s:o,s:o,s:o,s:o,s:o,s:{s:o,s:o},s:{s:o,s:o,s:o},"
        "s:{s:I,s:I}}",
        "scene", proto_encode_scene(&r->scene), "reference", "spp", (json_int_t)r->reference_spp,
        "seed", (json_int_t)r->reference_seed, "filter", r->filter, "output_offset",
        proto_real(r->output_offset), "pattern", pattern, "e2", proto_real(r->e2), "mean_phase_e2",
        proto_real(r->mean_phase_e2), "f2", proto_real(r->f2), "phases", phases, "steady", steady,
        "after_cut", proto_real_array(r->cut_rmse, r->cut_count), "frames_to_5pct",
        r->frames_to_5pct > 0 ? json_integer(r->frames_to_5pct) : json_null(), "flicker",
        "step_rmse", proto_real(r->flicker_step_rmse), "mean_rmse",
        proto_real(r->flicker_mean_rmse), "times", "reference_seconds",
        proto_real(r->reference_seconds), "taa_seconds", proto_real(r->taa_seconds),
        "predict_seconds", proto_real(r->predict_seconds), "pixels", "sampled",
        (json_int_t)r->pixels_sampled, "samples_evaluated", (json_int_t)r->samples_evaluated);
    json_t *flicker = out ? json_object_get(out, "flicker") : NULL;
    if (flicker && isfinite(r->flicker_predicted)) {
        json_object_set_new(flicker, "predicted_mean_rmse", proto_real(r->flicker_predicted));
        if (r->flicker_mean_rmse > 0)
            json_object_set_new(flicker, "ratio",
                                proto_real(r->flicker_predicted / r->flicker_mean_rmse));
    }
    if (flicker && isfinite(r->flicker_step_predicted)) {
        json_object_set_new(flicker, "predicted_step_rmse", proto_real(r->flicker_step_predicted));
        if (r->flicker_step_rmse > 0)
            json_object_set_new(flicker, "step_ratio",
                                proto_real(r->flicker_step_predicted / r->flicker_step_rmse));
    }
    if (out && r->tiles)
        json_object_set(out, "tiles", r->tiles);
    if (out && !proto_acuity_ref_encode(out, r->acuity_name, r->acuity_version)) {
        json_decref(out);
        return NULL;
    }
    return out;
}
