/* Job kind "reference-convergence": what the reference costs for the accuracy it gives. RMSE
 * and max deviation of the reference at 16, 64, 256, 1024 spp (or "levels") against one at
 * 4096 spp ("baseline_spp", an independent seed), with the wall time of each render.
 * Spec and result: proto/job_reference_convergence.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "job_reference_convergence.h"
#include "kinds.h"
#include "aa_render.h"
#include "tile_parallel.h"
#include "tile_render.h"

JOB_KIND_SPEC_PARAMS(kind_reference_convergence, proto_reference_convergence_spec,
                     proto_decode_reference_convergence_spec, proto_reference_convergence_spec_free)

static int render_level(const aa_scene *scene, const proto_reference_convergence_spec *cp, int spp,
                        uint64_t seed, job_progress_span *probe, aa_image *img,
                        proto_convergence_level *out, aa_error *err)
{
    aa_reference_params rp = cp->common.ref.params;
    rp.spp = spp;
    rp.seed = seed;
    rp.progress = job_progress_span_report;
    rp.user = probe;
    aa_reference_stats st;
    double t0 = aa_seconds_now();
    int rc = tile_reference_parallel(scene, &rp, aa_output_offset(cp->kernel_size), img,
                                     job_ctx_workers(probe->ctx), &st, err);
    out->seconds = aa_seconds_now() - t0;
    out->spp = spp;
    out->supersampled = (long long)st.pixels_supersampled;
    out->samples = (long long)st.samples;
    return rc;
}

static int convergence_run(void *params, job_ctx *ctx, proto_reference_convergence_result *out,
                           aa_error *err)
{
    proto_reference_convergence_spec *cp = params;
    out->scene = cp->common.scene;
    out->output_offset = aa_output_offset(cp->kernel_size);
    aa_scene scene;
    aa_image base, img;
    memset(&base, 0, sizeof base);
    memset(&img, 0, sizeof img);
    int rc = aa_scene_init(&scene, &cp->common.scene, err);
    if (!rc)
        rc = aa_image_init(&base, cp->common.scene.width, cp->common.scene.height, err);
    if (!rc)
        rc = aa_image_init(&img, cp->common.scene.width, cp->common.scene.height, err);
    /* Progress in proportion to the samples each render takes. */
    double total = cp->baseline_spp, done = 0;
    for (size_t i = 0; i < cp->level_count; i++)
        total += cp->levels[i];
    job_progress_span probe = {ctx, 0, cp->baseline_spp / total};
    if (!rc)
        rc = render_level(&scene, cp, cp->baseline_spp, cp->common.ref.params.seed + 1, &probe,
                          &base, &out->baseline, err);
    done = cp->baseline_spp;
    for (size_t i = 0; i < cp->level_count && !rc; i++) {
        probe.base = done / total;
        probe.span = cp->levels[i] / total;
        proto_convergence_level *row = &out->rows[i];
        rc = render_level(&scene, cp, cp->levels[i], cp->common.ref.params.seed, &probe, &img, row,
                          err);
        if (rc)
            break;
        done += cp->levels[i];
        aa_diff_stats d;
        aa_diff_init(&d);
        aa_diff_add(&d, &img, &base);
        aa_diff_finish(&d);
        row->rmse = d.rmse;
        row->max_dev = d.max_dev;
        out->row_count = i + 1;
    }
    if (rc == AA_ECANCELED)
        aa_error_set(err, AA_ECANCELED, "", "cancelled");
    aa_image_free(&base);
    aa_image_free(&img);
    return rc;
}

JOB_KIND_RESULT(kind_reference_convergence, proto_reference_convergence_result, convergence_run,
                proto_encode_reference_convergence_result, proto_reference_convergence_result_free)

/* The kind's row of the table of kinds (kind_list.h). */
JOB_KIND_ROW(reference_convergence, .name = "reference-convergence",
             .summary =
                 "Measures how the reference render's error falls with its samples per pixel, "
                 "against a high-sample baseline.");
