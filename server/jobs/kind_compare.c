/* Job kind "compare": one scene, a list of patterns (preset names, pattern objects, resolved
 * job results); one row per pattern with samples/pixel, E2, RMSE, max deviation and render
 * time, against one reference per output grid (odd / even kernel size). The table the
 * dashboard plots as error against run time. Beside each measured RMSE the edge model's
 * prediction (docs/predict.md; no render, microseconds to milliseconds), and Spearman's rho
 * between the two over the rows: the validation of the model on every compare run. Spec and
 * result: proto/job_compare.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "job_compare.h"
#include "kinds.h"
#include "aa_render.h"
#include "tile_parallel.h"
#include "tile_render.h"
#include "tile_store.h"

JOB_KIND_SPEC_PARAMS(kind_compare, proto_compare_spec, proto_decode_compare_spec,
                     proto_compare_spec_free)

/* References at output offsets 0.5 (odd K) and 1 (even K), rendered when first needed. */
typedef struct reference_slot {
    bool done;
    aa_image img;
} reference_slot;

static int compare_run(void *params, job_ctx *ctx, proto_compare_result *out, aa_error *err)
{
    proto_compare_spec *cp = params;
    tile_store *ts = job_ctx_tiles(ctx);
    /* The tiles belong to the job's owner and are private when the job is. */
    const tile_access access = {job_ctx_owner(ctx), job_ctx_private(ctx)};
    const aa_filter *f = cp->common.ref.params.filter;
    out->scene = cp->common.scene;
    out->reference_spp = cp->common.ref.params.spp;
    out->reference_seed = (long long)cp->common.ref.params.seed;
    snprintf(out->filter, sizeof out->filter, "%s", f ? f->name : "mitchell");
    proto_acuity_ref_set(&cp->common.acuity, out->acuity_name, sizeof out->acuity_name,
                         &out->acuity_version);
    out->rows = calloc(cp->count, sizeof *out->rows);
    if (!out->rows)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    aa_scene scene;
    int rc = aa_scene_init(&scene, &cp->common.scene, err);
    if (rc)
        return rc;
    aa_edge_histogram *hist = malloc(sizeof *hist);
    if (!hist)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    rc = aa_edge_histogram_of_scene(&scene, hist, err);
    if (rc) {
        free(hist);
        return rc;
    }
    reference_slot slot[2];
    memset(slot, 0, sizeof slot);
    aa_image img;
    memset(&img, 0, sizeof img);
    rc = aa_image_init(&img, cp->common.scene.width, cp->common.scene.height, err);
    /* Work units: each reference render and each pattern render is one; progress only grows. */
    double steps = (double)cp->count + 2, units = 0;
    for (size_t i = 0; i < cp->count && !rc; i++) {
        const aa_pattern *p = &cp->patterns[i];
        int s = p->kernel_size % 2 == 0;
        double off = aa_output_offset(p->kernel_size);
        if (!slot[s].done) {
            job_progress_span probe = {ctx, units / steps, 1.0 / steps};
            aa_reference_params rp = cp->common.ref.params;
            rp.progress = job_progress_span_report;
            rp.user = &probe;
            rc = aa_image_init(&slot[s].img, cp->common.scene.width, cp->common.scene.height, err);
            aa_reference_stats st;
            double t0 = aa_seconds_now();
            if (!rc)
                rc = tile_reference_parallel(&scene, &rp, off, &slot[s].img, job_ctx_workers(ctx),
                                             &st, err);
            double seconds = aa_seconds_now() - t0;
            if (rc)
                break;
            slot[s].done = true;
            units += 1;
            proto_compare_render *r = &out->renders[out->render_count++];
            *r = (proto_compare_render){.output_offset = off,
                                        .seconds = seconds,
                                        .supersampled = (long long)st.pixels_supersampled,
                                        .input_pixels_sampled = (long long)st.input_pixels,
                                        .samples = (long long)st.samples};
            if (ts && cp->common.tiles)
                r->tile = tile_put_image(ts, &access, &slot[s].img, NULL);
        }
        proto_compare_row *row = &out->rows[i];
        rc = aa_pattern_e2(p, cp->common.ref.params.filter, &cp->common.acuity, &row->e2, err);
        if (rc)
            break;
        aa_raster_stats rs;
        double t0 = aa_seconds_now();
        rc = aa_render_pattern(&scene, p, true, &img, NULL, &rs, err);
        row->render_seconds = aa_seconds_now() - t0;
        if (rc)
            break;
        out->row_count = i + 1;
        aa_diff_init(&row->stats);
        aa_diff_add(&row->stats, &img, &slot[s].img);
        aa_diff_finish(&row->stats);
        snprintf(row->name, sizeof row->name, "%s", cp->names[i]);
        snprintf(row->family, sizeof row->family, "%s", p->family);
        row->samples_per_pixel = p->cost_spp;
        row->rmse = row->stats.rmse;
        aa_prediction pred;
        row->predicted_rmse = NAN;
        if (aa_predict_rmse(p, f, hist, &pred, NULL) == AA_OK && isfinite(pred.rmse))
            row->predicted_rmse = pred.rmse;
        row->subpixel_error_share =
            hist->subpixel_area > 0 ? aa_subpixel_error_share(&scene, &img, &slot[s].img) : NAN;
        row->max_dev = row->stats.max_dev;
        row->pixels_sampled = (long long)rs.pixels_sampled;
        row->coverage_samples = (long long)rs.samples_evaluated;
        if (ts && cp->common.tiles) {
            row->have_tiles = true;
            row->tile_pattern = tile_put_image(ts, &access, &img, NULL);
            row->tile_difference = tile_put_difference(ts, &access, &img, &slot[s].img, NULL);
        }
        units += 1;
        if (job_ctx_progress(ctx, units / steps, NULL))
            rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
    }
    if (!rc) {
        double *measured = malloc(out->row_count * sizeof *measured);
        double *predicted = malloc(out->row_count * sizeof *predicted);
        if (measured && predicted) {
            size_t n = 0;
            for (size_t i = 0; i < out->row_count; i++)
                if (isfinite(out->rows[i].predicted_rmse)) {
                    measured[n] = out->rows[i].rmse;
                    predicted[n++] = out->rows[i].predicted_rmse;
                }
            out->have_prediction = true;
            out->spearman_predicted = aa_spearman(predicted, measured, n);
            out->subpixel_area_share =
                hist->subpixel_area / ((double)hist->width * (double)hist->height);
        } else {
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
        }
        free(measured);
        free(predicted);
    }
    free(hist);
    for (int s = 0; s < 2; s++)
        aa_image_free(&slot[s].img);
    aa_image_free(&img);
    return rc;
}

JOB_KIND_RESULT(kind_compare, proto_compare_result, compare_run, proto_encode_compare_result,
                proto_compare_result_free)

/* The kind's row of the table of kinds (kind_list.h). */
JOB_KIND_ROW(compare, .name = "compare",
             .summary =
                 "Renders one scene with several patterns and tabulates samples per pixel, E2, "
                 "RMSE and max deviation against a supersampled reference.");
