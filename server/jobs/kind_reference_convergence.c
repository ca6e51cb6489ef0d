/* Job kind "reference-convergence": what the reference costs for the accuracy it gives. RMSE
 * and max deviation of the reference at 16, 64, 256, 1024 spp (or "levels") against one at
 * 4096 spp ("baseline_spp", an independent seed), with the wall time of each render.
 * Spec: {"kind":"reference-convergence", "scene":{...}, "reference":{"seed", "filter"},
 *        "levels":[16,64,256,1024], "baseline_spp":4096, "kernel_size":1} */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "kinds.h"
#include "render_spec.h"
#include "aa_render.h"
#include "tile_parallel.h"
#include "tile_render.h"

#define CONVERGENCE_MAX_LEVELS 8

typedef struct convergence_spec {
    render_spec common;
    int levels[CONVERGENCE_MAX_LEVELS];
    size_t level_count;
    int baseline_spp;
    int kernel_size; /* selects the output grid: 0.5 (odd) or 1 (even) */
} convergence_spec;

static const char *const kind_keys[] = {"levels", "baseline_spp", "kernel_size", NULL};

static bool valid_spp(json_t *v, int *out)
{
    if (!json_is_integer(v))
        return false;
    json_int_t x = json_integer_value(v);
    if (x < 1 || x > AA_REFERENCE_MAX_SPP)
        return false;
    long m = lround(sqrt((double)x));
    *out = (int)x;
    return m * m == x;
}

static int convergence_spec_decode(const json_t *spec, convergence_spec *cp, aa_error *err)
{
    static const int default_levels[] = {16, 64, 256, 1024};
    memcpy(cp->levels, default_levels, sizeof default_levels);
    cp->level_count = 4;
    cp->baseline_spp = 4096;
    cp->kernel_size = 1;
    int rc = render_spec_decode(spec, kind_keys, 0, &cp->common, err);
    json_t *levels = json_object_get(spec, "levels");
    if (!rc && levels) {
        if (!json_is_array(levels) || json_array_size(levels) == 0 ||
            json_array_size(levels) > CONVERGENCE_MAX_LEVELS) {
            rc = aa_error_set(err, AA_EINVAL, "levels", "a list of 1..%d spp values",
                              CONVERGENCE_MAX_LEVELS);
        } else {
            cp->level_count = json_array_size(levels);
            for (size_t i = 0; i < cp->level_count && !rc; i++) {
                if (!valid_spp(json_array_get(levels, i), &cp->levels[i])) {
                    char field[32];
                    snprintf(field, sizeof field, "levels[%zu]", i);
                    rc = aa_error_set(err, AA_EINVAL, field, "spp must be a square in 1..%d",
                                      AA_REFERENCE_MAX_SPP);
                }
            }
        }
    }
    json_t *base = json_object_get(spec, "baseline_spp");
    if (!rc && base && !valid_spp(base, &cp->baseline_spp))
        rc = aa_error_set(err, AA_EINVAL, "baseline_spp", "spp must be a square in 1..%d",
                          AA_REFERENCE_MAX_SPP);
    json_t *ks = json_object_get(spec, "kernel_size");
    if (!rc && ks) {
        if (!json_is_integer(ks) || json_integer_value(ks) < 1 ||
            json_integer_value(ks) > AA_MAX_KERNEL_SIZE)
            rc = aa_error_set(err, AA_EINVAL, "kernel_size", "must be 1..%d", AA_MAX_KERNEL_SIZE);
        else
            cp->kernel_size = (int)json_integer_value(ks);
    }
    return rc;
}

static void convergence_spec_free(convergence_spec *cp)
{
    (void)cp; /* nothing of its own to free */
}

JOB_KIND_SPEC_PARAMS(kind_reference_convergence, convergence_spec, convergence_spec_decode,
                     convergence_spec_free)

static int render_level(const aa_scene *scene, const convergence_spec *cp, int spp, uint64_t seed,
                        job_progress_span *probe, aa_image *img, aa_reference_stats *st,
                        double *seconds, aa_error *err)
{
    aa_reference_params rp = cp->common.ref.params;
    rp.spp = spp;
    rp.seed = seed;
    rp.progress = job_progress_span_report;
    rp.user = probe;
    double t0 = aa_seconds_now();
    int rc = tile_reference_parallel(scene, &rp, aa_output_offset(cp->kernel_size), img,
                                     job_ctx_workers(probe->ctx), st, err);
    *seconds = aa_seconds_now() - t0;
    return rc;
}

JOB_KIND_JSON_RESULT(kind_reference_convergence)

int kind_reference_convergence_run(void *params, job_ctx *ctx, void **result, aa_error *err)
{
    convergence_spec *cp = params;
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
    aa_reference_stats st;
    double seconds = 0;
    job_progress_span probe = {ctx, 0, cp->baseline_spp / total};
    if (!rc)
        rc = render_level(&scene, cp, cp->baseline_spp, cp->common.ref.params.seed + 1, &probe,
                          &base, &st, &seconds, err);
    json_t *rows = json_array();
    json_t *baseline =
        rc ? NULL
           : json_pack("{s:I, s:f, s:I, s:I}", "spp", (json_int_t)cp->baseline_spp, "seconds",
                       seconds, "supersampled", (json_int_t)st.pixels_supersampled, "samples",
                       (json_int_t)st.samples);
    done = cp->baseline_spp;
    for (size_t i = 0; i < cp->level_count && !rc; i++) {
        probe.base = done / total;
        probe.span = cp->levels[i] / total;
        rc = render_level(&scene, cp, cp->levels[i], cp->common.ref.params.seed, &probe, &img, &st,
                          &seconds, err);
        if (rc)
            break;
        done += cp->levels[i];
        aa_diff_stats d;
        aa_diff_init(&d);
        aa_diff_add(&d, &img, &base);
        aa_diff_finish(&d);
        json_array_append_new(rows, json_pack("{s:I, s:f, s:f, s:f, s:I, s:I}", "spp",
                                              (json_int_t)cp->levels[i], "rmse", d.rmse, "max_dev",
                                              d.max_dev, "seconds", seconds, "supersampled",
                                              (json_int_t)st.pixels_supersampled, "samples",
                                              (json_int_t)st.samples));
    }
    if (rc == AA_ECANCELED)
        aa_error_set(err, AA_ECANCELED, "", "cancelled");
    if (!rc) {
        *result = json_pack("{s:o, s:f, s:o, s:o}", "scene", proto_encode_scene(&cp->common.scene),
                            "output_offset", aa_output_offset(cp->kernel_size), "baseline",
                            baseline, "rows", rows);
        baseline = rows = NULL;
        if (!*result)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    json_decref(baseline);
    json_decref(rows);
    aa_image_free(&base);
    aa_image_free(&img);
    return rc;
}
