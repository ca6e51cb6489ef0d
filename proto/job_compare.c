#include "job_compare.h"

#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "codec_internal.h"
#include "codec_temporal.h"
#include "job_temporal_render.h"

void proto_compare_spec_free(proto_compare_spec *cp)
{
    for (size_t i = 0; i < cp->count; i++)
        aa_pattern_free(&cp->patterns[i]);
    free(cp->patterns);
    free(cp->names);
    cp->patterns = NULL;
    cp->names = NULL;
    cp->count = 0;
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

/* Room for n more rows. */
static int grow(proto_compare_spec *cp, size_t *cap, size_t n, aa_error *err)
{
    if (cp->count + n <= *cap)
        return AA_OK;
    size_t c = (cp->count + n) * 2;
    aa_pattern *p = realloc(cp->patterns, c * sizeof *p);
    if (p)
        cp->patterns = p;
    char(*names)[64] = p ? realloc(cp->names, c * sizeof *names) : NULL;
    if (!names)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    cp->names = names;
    *cap = c;
    return AA_OK;
}

/* A temporal pattern: one row per phase, its steady state (the phase's kernels). samples: the
 * rows' kernel samples so far, bounded before anything is built. */
static int decode_temporal_rows(const json_t *pj, const char *field, proto_compare_spec *cp,
                                size_t *cap, double *samples, aa_error *err)
{
    proto_temporal spec;
    int rc = proto_decode_temporal(pj, &spec, field, err);
    if (rc)
        return rc;
    char tf[64];
    snprintf(tf, sizeof tf, "%s.temporal", field);
    *samples += proto_temporal_planned_samples(&spec) * (double)spec.count;
    if (*samples > (double)PROTO_COMPARE_MAX_PHASE_SAMPLES ||
        cp->count + spec.count > PROTO_COMPARE_MAX_ROWS)
        rc = aa_error_set(err, AA_ERANGE, tf,
                          "the phases are more rows (at most %d) or kernel samples (at most %ld) "
                          "than a compare renders",
                          PROTO_COMPARE_MAX_ROWS, PROTO_COMPARE_MAX_PHASE_SAMPLES);
    aa_temporal t = {0};
    if (!rc)
        rc = proto_temporal_build(&spec, tf, &t, err);
    if (!rc)
        rc = grow(cp, cap, t.phase_count, err);
    for (size_t p = 0; !rc && p < t.phase_count; p++) {
        rc = aa_taa_phase_pattern(&t, p, &cp->patterns[cp->count], err);
        if (rc) { /* more than AA_MAX_KERNEL_SAMPLES per output pixel */
            snprintf(err->field, sizeof err->field, "%s.jitter", tf);
            break;
        }
        snprintf(cp->names[cp->count], sizeof cp->names[cp->count], "%.40s phase %u",
                 spec.preset ? spec.preset : "temporal", (unsigned)p);
        cp->count++;
    }
    aa_temporal_free(&t);
    proto_temporal_free(&spec);
    return rc;
}

int proto_decode_compare_spec(const json_t *spec, proto_compare_spec *cp, aa_error *err)
{
    memset(cp, 0, sizeof *cp);
    int rc = proto_render_spec_decode(
        spec, kind_keys, PROTO_RENDER_SPEC_ACUITY | PROTO_RENDER_SPEC_TILES, &cp->common, err);
    json_t *list = json_object_get(spec, "patterns");
    if (!rc && (!json_is_array(list) || json_array_size(list) == 0 ||
                json_array_size(list) > PROTO_COMPARE_MAX_PATTERNS))
        rc = aa_error_set(err, AA_EINVAL, "patterns", "a list of 1..%d patterns is required",
                          PROTO_COMPARE_MAX_PATTERNS);
    size_t n = json_array_size(list), cap = 0;
    double samples = 0;
    for (size_t i = 0; i < n && !rc; i++) {
        char field[32];
        snprintf(field, sizeof field, "patterns[%zu]", i);
        json_t *pj = json_array_get(list, i);
        if (json_is_object(pj) && json_object_get(pj, "temporal")) {
            rc = decode_temporal_rows(pj, field, cp, &cap, &samples, err);
            continue;
        }
        rc = grow(cp, &cap, 1, err);
        if (!rc)
            rc = proto_render_pattern_decode(pj, &cp->patterns[cp->count], field, err);
        if (!rc) {
            pattern_name(pj, &cp->patterns[cp->count], cp->names[cp->count]);
            cp->count++;
        }
    }
    if (rc)
        proto_compare_spec_free(cp);
    return rc;
}

static json_t *encode_render(const proto_compare_render *r)
{
    return json_pack("{s:f, s:f, s:I, s:I, s:I, s:O*}", "output_offset", r->output_offset,
                     "seconds", r->seconds, "supersampled", (json_int_t)r->supersampled,
                     "input_pixels_sampled", (json_int_t)r->input_pixels_sampled, "samples",
                     (json_int_t)r->samples, "tile", r->tile);
}

static json_t *encode_row(const proto_compare_row *r)
{
    json_t *row =
        json_pack("{s:s, s:s, s:f, s:f, s:f, s:f, s:f, s:I, s:I, s:o}", "name", r->name, "family",
                  r->family, "samples_per_pixel", r->samples_per_pixel, "e2", r->e2, "rmse",
                  r->rmse, "max_dev", r->max_dev, "render_seconds", r->render_seconds,
                  "pixels_sampled", (json_int_t)r->pixels_sampled, "coverage_samples",
                  (json_int_t)r->coverage_samples, "stats", proto_encode_diff(&r->stats));
    if (row && isfinite(r->predicted_rmse) &&
        json_object_set_new(row, "predicted_rmse", json_real(r->predicted_rmse))) {
        json_decref(row);
        return NULL;
    }
    if (row && isfinite(r->subpixel_error_share) &&
        json_object_set_new(row, "subpixel_error_share", json_real(r->subpixel_error_share))) {
        json_decref(row);
        return NULL;
    }
    if (row && r->have_tiles &&
        json_object_set_new(row, "tiles",
                            json_pack("{s:O*, s:O*}", "pattern", r->tile_pattern, "difference",
                                      r->tile_difference))) {
        json_decref(row);
        return NULL;
    }
    return row;
}

json_t *proto_encode_compare_result(const proto_compare_result *r)
{
    json_t *renders = json_array(), *rows = json_array();
    bool ok = renders && rows;
    for (size_t i = 0; ok && i < r->render_count; i++)
        ok = !json_array_append_new(renders, encode_render(&r->renders[i]));
    for (size_t i = 0; ok && i < r->row_count; i++)
        ok = !json_array_append_new(rows, encode_row(&r->rows[i]));
    if (!ok) {
        json_decref(renders);
        json_decref(rows);
        return NULL;
    }
    json_t *out = json_pack("{s:o, s:{s:I, s:I, s:s, s:o}, s:o}", "scene",
                            proto_encode_scene(&r->scene), "reference", "spp",
                            (json_int_t)r->reference_spp, "seed", (json_int_t)r->reference_seed,
                            "filter", r->filter, "renders", renders, "rows", rows);
    if (out && r->have_prediction &&
        json_object_set_new(out, "prediction",
                            json_pack("{s:o, s:f}", "spearman", proto_real(r->spearman_predicted),
                                      "subpixel_area_share", r->subpixel_area_share))) {
        json_decref(out);
        return NULL;
    }
    if (out && !proto_acuity_ref_encode(out, r->acuity_name, r->acuity_version)) {
        json_decref(out);
        return NULL;
    }
    return out;
}

static const char *const result_keys[] = {"scene",      "reference", "rows",
                                          "prediction", "acuity",    NULL};
static const char *const prediction_keys[] = {"spearman", "subpixel_area_share", NULL};
static const char *const reference_keys[] = {"spp", "seed", "filter", "renders", NULL};
static const char *const render_keys[] = {
    "output_offset", "seconds", "supersampled", "input_pixels_sampled", "samples", "tile", NULL};
static const char *const row_keys[] = {"name",
                                       "family",
                                       "samples_per_pixel",
                                       "e2",
                                       "rmse",
                                       "subpixel_error_share",
                                       "predicted_rmse",
                                       "max_dev",
                                       "render_seconds",
                                       "pixels_sampled",
                                       "coverage_samples",
                                       "stats",
                                       "tiles",
                                       NULL};
static const char *const tiles_keys[] = {"pattern", "difference", NULL};

static int decode_render(const json_t *j, proto_compare_render *r, const char *at, aa_error *err)
{
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, at, "must be an object");
    int rc = proto_check_keys(j, render_keys, err, at);
    if (!rc)
        rc = proto_result_number(j, "output_offset", &r->output_offset, at, err);
    if (!rc)
        rc = proto_result_number(j, "seconds", &r->seconds, at, err);
    if (!rc)
        rc = proto_result_count(j, "supersampled", &r->supersampled, at, err);
    if (!rc)
        rc = proto_result_count(j, "input_pixels_sampled", &r->input_pixels_sampled, at, err);
    if (!rc)
        rc = proto_result_count(j, "samples", &r->samples, at, err);
    if (!rc)
        rc = proto_result_tile(j, "tile", &r->tile, at, err);
    return rc;
}

static int decode_row(const json_t *j, proto_compare_row *r, const char *at, aa_error *err)
{
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, at, "must be an object");
    int rc = proto_check_keys(j, row_keys, err, at);
    if (!rc)
        rc = proto_result_string(j, "name", r->name, sizeof r->name, at, err);
    if (!rc)
        rc = proto_result_string(j, "family", r->family, sizeof r->family, at, err);
    if (!rc)
        rc = proto_result_number(j, "samples_per_pixel", &r->samples_per_pixel, at, err);
    if (!rc)
        rc = proto_result_number(j, "e2", &r->e2, at, err);
    if (!rc)
        rc = proto_result_number(j, "rmse", &r->rmse, at, err);
    r->predicted_rmse = NAN;
    r->subpixel_error_share = NAN;
    if (!rc && json_object_get(j, "predicted_rmse"))
        rc = proto_result_number(j, "predicted_rmse", &r->predicted_rmse, at, err);
    if (!rc && json_object_get(j, "subpixel_error_share"))
        rc = proto_result_number(j, "subpixel_error_share", &r->subpixel_error_share, at, err);
    if (!rc)
        rc = proto_result_number(j, "max_dev", &r->max_dev, at, err);
    if (!rc)
        rc = proto_result_number(j, "render_seconds", &r->render_seconds, at, err);
    if (!rc)
        rc = proto_result_count(j, "pixels_sampled", &r->pixels_sampled, at, err);
    if (!rc)
        rc = proto_result_count(j, "coverage_samples", &r->coverage_samples, at, err);
    char sub[64];
    snprintf(sub, sizeof sub, "%s.stats", at);
    if (!rc)
        rc = proto_decode_diff(json_object_get(j, "stats"), &r->stats, sub, err);
    const json_t *tiles = json_object_get(j, "tiles");
    snprintf(sub, sizeof sub, "%s.tiles", at);
    if (!rc && tiles) {
        r->have_tiles = true;
        if (!json_is_object(tiles))
            rc = aa_error_set(err, AA_EINVAL, sub, "must be an object");
        if (!rc)
            rc = proto_check_keys(tiles, tiles_keys, err, sub);
        if (!rc)
            rc = proto_result_tile(tiles, "pattern", &r->tile_pattern, sub, err);
        if (!rc)
            rc = proto_result_tile(tiles, "difference", &r->tile_difference, sub, err);
    }
    return rc;
}

int proto_decode_compare_result(const json_t *j, proto_compare_result *r, aa_error *err)
{
    memset(r, 0, sizeof *r);
    const json_t *ref = json_object_get(j, "reference");
    const json_t *renders = json_object_get(ref, "renders"), *rows = json_object_get(j, "rows");
    int rc = json_is_object(j) ? proto_check_keys(j, result_keys, err, "")
                               : aa_error_set(err, AA_EINVAL, "", "must be an object");
    if (!rc)
        rc = proto_decode_scene(json_object_get(j, "scene"), &r->scene, "scene", err);
    if (!rc && !json_is_object(ref))
        rc = aa_error_set(err, AA_EINVAL, "reference", "must be an object");
    if (!rc)
        rc = proto_check_keys(ref, reference_keys, err, "reference");
    if (!rc)
        rc = proto_result_count(ref, "spp", &r->reference_spp, "reference", err);
    if (!rc)
        rc = proto_result_count(ref, "seed", &r->reference_seed, "reference", err);
    if (!rc)
        rc = proto_result_string(ref, "filter", r->filter, sizeof r->filter, "reference", err);
    if (!rc && (!json_is_array(renders) || json_array_size(renders) > 2))
        rc = aa_error_set(err, AA_EINVAL, "reference.renders",
                          "must be an array of at most 2 renders");
    for (size_t i = 0; !rc && i < json_array_size(renders); i++) {
        char at[48];
        snprintf(at, sizeof at, "reference.renders[%zu]", i);
        rc = decode_render(json_array_get(renders, i), &r->renders[i], at, err);
        r->render_count = i + 1;
    }
    if (!rc && (!json_is_array(rows) || json_array_size(rows) > PROTO_COMPARE_MAX_PATTERNS))
        rc = aa_error_set(err, AA_EINVAL, "rows", "must be an array of at most %d rows",
                          PROTO_COMPARE_MAX_PATTERNS);
    size_t n = json_array_size(rows);
    if (!rc && n && !(r->rows = calloc(n, sizeof *r->rows)))
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t i = 0; !rc && i < n; i++) {
        char at[32];
        snprintf(at, sizeof at, "rows[%zu]", i);
        r->row_count = i + 1;
        rc = decode_row(json_array_get(rows, i), &r->rows[i], at, err);
    }
    const json_t *pred = json_object_get(j, "prediction");
    if (!rc && pred) {
        r->have_prediction = true;
        const json_t *rho = json_object_get(pred, "spearman");
        if (!json_is_object(pred))
            rc = aa_error_set(err, AA_EINVAL, "prediction", "must be an object");
        if (!rc)
            rc = proto_check_keys(pred, prediction_keys, err, "prediction");
        if (!rc && json_is_null(rho))
            r->spearman_predicted = NAN;
        else if (!rc)
            rc = proto_result_number(pred, "spearman", &r->spearman_predicted, "prediction", err);
        if (!rc)
            rc = proto_result_number(pred, "subpixel_area_share", &r->subpixel_area_share,
                                     "prediction", err);
    }
    if (!rc)
        rc = proto_acuity_ref_decode(j, r->acuity_name, sizeof r->acuity_name, &r->acuity_version,
                                     err);
    if (rc)
        proto_compare_result_free(r);
    return rc;
}

void proto_compare_result_free(proto_compare_result *r)
{
    for (size_t i = 0; i < r->render_count; i++)
        json_decref(r->renders[i].tile);
    for (size_t i = 0; i < r->row_count; i++) {
        json_decref(r->rows[i].tile_pattern);
        json_decref(r->rows[i].tile_difference);
    }
    free(r->rows);
    memset(r, 0, sizeof *r);
}
