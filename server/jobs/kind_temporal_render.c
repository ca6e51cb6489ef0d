/* Job kind "temporal-render": a still scene rendered through the TAA loop of a temporal pattern
 * (render/taa_render.h, docs/temporal.md §9) against the supersampled reference: the steady-state
 * RMSE per phase, the RMSE per frame after a cut, the flicker of the static scene, the images of
 * the worst phase, and beside each phase the edge model's prediction from its kernels
 * (docs/predict.md) with the ratio. Work: the reference as in compare, then N m scene samples
 * plus O(N + K) per pixel an edge's footprint crosses (progress and cancel per image row), and
 * one prediction per phase (progress and cancel per phase). Spec and result:
 * proto/job_temporal_render.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "job_temporal_render.h"
#include "kinds.h"
#include "aa_render.h"
#include "tile_parallel.h"
#include "tile_render.h"
#include "tile_store.h"

JOB_KIND_SPEC_PARAMS(kind_temporal_render, proto_temporal_render_spec,
                     proto_decode_temporal_render_spec, proto_temporal_render_spec_free)

/* Progress shares of the parts. */
#define SHARE_REFERENCE 0.3
#define SHARE_TAA 0.5
#define SHARE_PREDICT 0.15

static int alloc_result(proto_temporal_render_result *out, size_t N, size_t K, aa_error *err)
{
    out->jitter = calloc(N, sizeof *out->jitter);
    out->phase_e2 = calloc(N, sizeof *out->phase_e2);
    out->phase_rmse = calloc(N, sizeof *out->phase_rmse);
    out->phase_max_dev = calloc(N, sizeof *out->phase_max_dev);
    out->phase_predicted = calloc(N, sizeof *out->phase_predicted);
    out->cut_rmse = calloc(K, sizeof *out->cut_rmse);
    if (!out->jitter || !out->phase_e2 || !out->phase_rmse || !out->phase_max_dev ||
        !out->phase_predicted || !out->cut_rmse)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    return AA_OK;
}

/* The edge model's RMSE of each phase's kernels (NaN where a phase does not make a pattern:
 * more than AA_MAX_KERNEL_SAMPLES samples per output pixel). */
static int predict_phases(const proto_temporal_render_spec *sp, const aa_scene *scene, job_ctx *ctx,
                          double base, proto_temporal_render_result *out, aa_error *err)
{
    const aa_temporal *t = &sp->built;
    size_t N = t->phase_count;
    aa_edge_histogram *hist = malloc(sizeof *hist);
    if (!hist)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    int rc = aa_edge_histogram_of_scene(scene, hist, err);
    out->flicker_predicted = out->flicker_step_predicted = NAN;
    if (!rc &&
        aa_taa_predict_flicker(t, hist, &out->flicker_predicted, &out->flicker_step_predicted, err))
        rc = AA_ENOMEM;
    for (size_t p = 0; p < N && !rc; p++) {
        aa_pattern pat;
        aa_prediction pred;
        out->phase_predicted[p] = NAN;
        if (aa_taa_phase_pattern(t, p, &pat, NULL) == AA_OK &&
            aa_predict_rmse(&pat, sp->common.ref.params.filter, hist, &pred, NULL) == AA_OK)
            out->phase_predicted[p] = pred.rmse;
        aa_pattern_free(&pat);
        if (job_ctx_progress(ctx, base + SHARE_PREDICT * (p + 1.0) / N, NULL))
            rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
    }
    free(hist);
    return rc;
}

static void summarise(const aa_taa_stats *st, proto_temporal_render_result *out)
{
    size_t N = st->phase_count, K = st->cut_count;
    for (size_t p = 0; p < N; p++) {
        out->phase_rmse[p] = aa_taa_rmse(st, st->phase_sum_sq[p]);
        out->phase_max_dev[p] = st->phase_max_dev[p];
        if (out->phase_rmse[p] > out->phase_rmse[out->worst_phase])
            out->worst_phase = p;
    }
    for (size_t k = 0; k < K; k++)
        out->cut_rmse[k] = aa_taa_rmse(st, st->cut_sum_sq[k]);
    /* As the evaluate's frames to 5 %: the first k from which every value up to K is within 5 %
     * of the steady state of the phase it shows, (k - 1) mod N. */
    out->frames_to_5pct = -1;
    for (size_t k = K; k >= 1; k--) {
        double ss = out->phase_rmse[(k - 1) % N];
        if (fabs(out->cut_rmse[k - 1] - ss) > AA_TEMPORAL_SETTLE_TOLERANCE * ss)
            break;
        out->frames_to_5pct = (long)k;
    }
    out->flicker_step_rmse = aa_taa_rmse(st, st->flicker_step_sum_sq / (double)N);
    out->flicker_mean_rmse = aa_taa_rmse(st, st->flicker_mean_sum_sq / (double)N);
    out->pixels_sampled = (long long)st->pixels_sampled;
    out->samples_evaluated = (long long)st->samples_evaluated;
}

static int temporal_render_run(void *params, job_ctx *ctx, proto_temporal_render_result *out,
                               aa_error *err)
{
    proto_temporal_render_spec *sp = params;
    const aa_temporal *t = &sp->built;
    size_t N = t->phase_count, K = sp->cut_frames;
    const aa_filter *f = sp->common.ref.params.filter;
    out->scene = sp->common.scene;
    out->reference_spp = sp->common.ref.params.spp;
    out->reference_seed = (long long)sp->common.ref.params.seed;
    snprintf(out->filter, sizeof out->filter, "%s", f ? f->name : "mitchell");
    proto_acuity_ref_set(&sp->common.acuity, out->acuity_name, sizeof out->acuity_name,
                         &out->acuity_version);
    out->phase_count = N;
    out->flicker_predicted = out->flicker_step_predicted = NAN;
    out->group_count = t->group_count;
    out->cut_count = K;
    out->samples_per_pixel = t->cost_spp;
    out->blend = t->blend;
    if (sp->temporal.preset)
        snprintf(out->preset, sizeof out->preset, "%s", sp->temporal.preset);
    int rc = alloc_result(out, N, K, err);
    if (rc)
        return rc;
    memcpy(out->jitter, sp->temporal.jitter, N * sizeof *out->jitter);

    aa_scene scene;
    aa_taa r;
    aa_image ref = {0}, img = {0};
    rc = aa_scene_init(&scene, &sp->common.scene, err);
    if (!rc)
        rc = aa_taa_init(&r, &scene, t, true, err);
    if (!rc)
        rc = aa_image_init(&ref, scene.p.width, scene.p.height, err);
    if (!rc) {
        out->output_offset = r.offset;
        job_progress_span probe = {ctx, 0, SHARE_REFERENCE};
        aa_reference_params rp = sp->common.ref.params;
        rp.progress = job_progress_span_report;
        rp.user = &probe;
        double t0 = aa_seconds_now();
        rc = tile_reference_parallel(&scene, &rp, r.offset, &ref, job_ctx_workers(ctx), NULL, err);
        out->reference_seconds = aa_seconds_now() - t0;
    }
    if (!rc) {
        /* E2, its mean over phases and F2 of the same kernels (one cut frame: the render has
         * its own after-cut curve). */
        aa_filter fd;
        aa_filter_default(&fd);
        aa_metric_params mp = {.filter = f ? f : &fd, .acuity = &sp->common.acuity};
        aa_temporal_evaluation ev = {0};
        rc = aa_temporal_evaluate(t, &mp, 1, &ev, err);
        if (!rc) {
            out->e2 = ev.e2;
            out->mean_phase_e2 = ev.mean_phase_e2;
            out->f2 = ev.f2;
            memcpy(out->phase_e2, ev.phase_e2, N * sizeof *out->phase_e2);
            aa_temporal_evaluation_free(&ev);
            /* The sequence's E2 is the job's best, as animation's, so the job list shows it
             * as the detail does (issue 34's "best E2 — in the lists"). */
            char family[32];
            snprintf(family, sizeof family, "T(%zu)", N);
            json_t *best = json_pack("{s:{s:s},s:f}", "pattern", "family", family, "e2", out->e2);
            if (job_ctx_progress(ctx, SHARE_REFERENCE, best))
                rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
            json_decref(best);
        }
    }
    if (!rc) {
        job_progress_span probe = {ctx, SHARE_REFERENCE, SHARE_TAA};
        aa_taa_stats st;
        double t0 = aa_seconds_now();
        rc = aa_taa_measure(&r, &ref, K, job_progress_span_report, &probe, &st, err);
        out->taa_seconds = aa_seconds_now() - t0;
        if (!rc) {
            summarise(&st, out);
            aa_taa_stats_free(&st);
        }
    }
    if (!rc) {
        double t0 = aa_seconds_now();
        rc = predict_phases(sp, &scene, ctx, SHARE_REFERENCE + SHARE_TAA, out, err);
        out->predict_seconds = aa_seconds_now() - t0;
    }
    tile_store *ts = job_ctx_tiles(ctx);
    if (!rc && ts && sp->common.tiles) {
        /* The tiles belong to the job's owner and are private when the job is. */
        const tile_access access = {job_ctx_owner(ctx), job_ctx_private(ctx)};
        rc = aa_image_init(&img, scene.p.width, scene.p.height, err);
        if (!rc)
            rc = aa_taa_phase_image(&r, out->worst_phase, &img, err);
        if (!rc)
            out->tiles = tile_put_render_images_as(ts, &access, &img, &ref, NULL, err);
    }
    if (!rc && job_ctx_progress(ctx, 1.0, NULL))
        rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
    aa_image_free(&ref);
    aa_image_free(&img);
    return rc;
}

JOB_KIND_RESULT(kind_temporal_render, proto_temporal_render_result, temporal_render_run,
                proto_encode_temporal_render_result, proto_temporal_render_result_free)

/* The kind's row of the table of kinds (kind_list.h). */
JOB_KIND_ROW(temporal_render, .name = "temporal-render",
             .summary =
                 "Renders a still scene through the TAA loop of a temporal pattern and reports "
                 "the steady-state RMSE per phase, the RMSE per frame after a cut and the flicker, "
                 "with the edge model's prediction per phase.");
