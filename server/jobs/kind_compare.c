/* Job kind "compare": one scene, a list of patterns (preset names, pattern objects, resolved
 * job results); one row per pattern with samples/pixel, E2, RMSE, max deviation and render
 * time, against one reference per output grid (odd / even kernel size). The table the
 * dashboard plots as error against run time.
 * Spec: {"kind":"compare", "scene":{...}, "patterns":[...], "reference":{...},
 *        "acuity":..., "tiles":true} */
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "kinds.h"
#include "render_pattern.h"
#include "render_spec.h"
#include "aa_render.h"
#include "tile_parallel.h"
#include "tile_render.h"
#include "tile_store.h"

#define COMPARE_MAX_PATTERNS 64

typedef struct compare_spec {
    render_spec common;
    size_t count;
    aa_pattern *patterns;
    char (*names)[64];
} compare_spec;

static void compare_spec_free(compare_spec *cp)
{
    for (size_t i = 0; i < cp->count; i++)
        aa_pattern_free(&cp->patterns[i]);
    free(cp->patterns);
    free(cp->names);
}

/* The name a row shows: the preset's, the pattern's "name", or its family. */
static void pattern_name(const json_t *pj, const aa_pattern *p, char out[64])
{
    const char *name = json_is_string(pj) ? json_string_value(pj) : NULL;
    if (!name && json_is_string(json_object_get(pj, "preset")))
        name = json_string_value(json_object_get(pj, "preset"));
    if (!name && json_is_string(json_object_get(pj, "name")))
        name = json_string_value(json_object_get(pj, "name"));
    snprintf(out, 64, "%s", name ? name : p->family);
}

static const char *const kind_keys[] = {"patterns", NULL};

static int compare_spec_decode(const json_t *spec, compare_spec *cp, aa_error *err)
{
    int rc = render_spec_decode(spec, kind_keys, RENDER_SPEC_ACUITY | RENDER_SPEC_TILES,
                                &cp->common, err);
    json_t *list = json_object_get(spec, "patterns");
    if (!rc && (!json_is_array(list) || json_array_size(list) == 0 ||
                json_array_size(list) > COMPARE_MAX_PATTERNS))
        rc = aa_error_set(err, AA_EINVAL, "patterns", "a list of 1..%d patterns is required",
                          COMPARE_MAX_PATTERNS);
    size_t n = json_array_size(list);
    if (!rc) {
        cp->patterns = calloc(n, sizeof *cp->patterns);
        cp->names = calloc(n, sizeof *cp->names);
        if (!cp->patterns || !cp->names)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    for (size_t i = 0; i < n && !rc; i++) {
        char field[32];
        snprintf(field, sizeof field, "patterns[%zu]", i);
        json_t *pj = json_array_get(list, i);
        rc = render_pattern_decode(pj, &cp->patterns[i], field, err);
        if (!rc) {
            cp->count = i + 1;
            pattern_name(pj, &cp->patterns[i], cp->names[i]);
        }
    }
    if (rc)
        compare_spec_free(cp);
    return rc;
}

JOB_KIND_SPEC_PARAMS(kind_compare, compare_spec, compare_spec_decode, compare_spec_free)

/* References at output offsets 0.5 (odd K) and 1 (even K), rendered when first needed. */
typedef struct reference_slot {
    bool done;
    aa_image img;
    aa_reference_stats st;
    double seconds;
    json_t *tile;
} reference_slot;

JOB_KIND_JSON_RESULT(kind_compare)

int kind_compare_run(void *params, job_ctx *ctx, void **result, aa_error *err)
{
    compare_spec *cp = params;
    tile_store *ts = job_ctx_tiles(ctx);
    /* The tiles belong to the job's owner and are private when the job is. */
    const tile_access access = {job_ctx_owner(ctx), job_ctx_private(ctx)};
    aa_scene scene;
    int rc = aa_scene_init(&scene, &cp->common.scene, err);
    if (rc)
        return rc;
    reference_slot slot[2];
    memset(slot, 0, sizeof slot);
    json_t *rows = json_array(), *refs = json_array();
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
            double t0 = aa_seconds_now();
            if (!rc)
                rc = tile_reference_parallel(&scene, &rp, off, &slot[s].img, job_ctx_workers(ctx),
                                             &slot[s].st, err);
            slot[s].seconds = aa_seconds_now() - t0;
            if (rc)
                break;
            slot[s].done = true;
            units += 1;
            if (ts && cp->common.tiles)
                slot[s].tile = tile_put_image(ts, &access, &slot[s].img, NULL);
            json_array_append_new(
                refs, json_pack("{s:f, s:f, s:I, s:I, s:I, s:o*}", "output_offset", off, "seconds",
                                slot[s].seconds, "supersampled",
                                (json_int_t)slot[s].st.pixels_supersampled, "input_pixels_sampled",
                                (json_int_t)slot[s].st.input_pixels, "samples",
                                (json_int_t)slot[s].st.samples, "tile",
                                slot[s].tile ? json_incref(slot[s].tile) : NULL));
        }
        double e2 = 0;
        rc = aa_pattern_e2(p, cp->common.ref.params.filter, &cp->common.acuity, &e2, err);
        if (rc)
            break;
        aa_raster_stats rs;
        double t0 = aa_seconds_now();
        rc = aa_render_pattern(&scene, p, true, &img, NULL, &rs, err);
        double seconds = aa_seconds_now() - t0;
        if (rc)
            break;
        aa_diff_stats d;
        aa_diff_init(&d);
        aa_diff_add(&d, &img, &slot[s].img);
        aa_diff_finish(&d);
        json_t *row = json_pack(
            "{s:s, s:s, s:f, s:f, s:f, s:f, s:f, s:I, s:I, s:o}", "name", cp->names[i], "family",
            p->family, "samples_per_pixel", p->cost_spp, "e2", e2, "rmse", d.rmse, "max_dev",
            d.max_dev, "render_seconds", seconds, "pixels_sampled", (json_int_t)rs.pixels_sampled,
            "coverage_samples", (json_int_t)rs.samples_evaluated, "stats", proto_encode_diff(&d));
        if (row && ts && cp->common.tiles) {
            json_t *tp = tile_put_image(ts, &access, &img, NULL);
            json_t *td = tile_put_difference(ts, &access, &img, &slot[s].img, NULL);
            json_object_set_new(row, "tiles",
                                json_pack("{s:o*, s:o*}", "pattern", tp, "difference", td));
        }
        json_array_append_new(rows, row);
        units += 1;
        if (job_ctx_progress(ctx, units / steps, NULL))
            rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
    }
    if (!rc) {
        const aa_filter *f = cp->common.ref.params.filter;
        *result = json_pack("{s:o, s:{s:I, s:I, s:s, s:o}, s:o}", "scene",
                            proto_encode_scene(&cp->common.scene), "reference", "spp",
                            (json_int_t)cp->common.ref.params.spp, "seed",
                            (json_int_t)cp->common.ref.params.seed, "filter",
                            f ? f->name : "mitchell", "renders", refs, "rows", rows);
        refs = rows = NULL;
        if (!*result)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    json_decref(rows);
    json_decref(refs);
    for (int s = 0; s < 2; s++) {
        aa_image_free(&slot[s].img);
        json_decref(slot[s].tile);
    }
    aa_image_free(&img);
    return rc;
}
