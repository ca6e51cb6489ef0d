/* Spec and result of the "compare" job kind: one scene rendered with several patterns, each
 * row against a supersampled reference (one per output grid: odd / even kernel size).
 * Spec: {"scene", "size", "reference", "acuity", "tiles", "patterns": [1..64 preset names or
 * pattern objects; a temporal pattern gives one row per phase]} (job_render_spec.h for the shared
 * fields). */
#ifndef AALAB_PROTO_JOB_COMPARE_H
#define AALAB_PROTO_JOB_COMPARE_H

#include "job_render_spec.h"

#define PROTO_COMPARE_MAX_PATTERNS 64
/* A temporal pattern in the list is one row per phase (its steady state: the phase's kernels,
 * named "<preset or temporal> phase p"); all rows together at most these. */
#define PROTO_COMPARE_MAX_ROWS 1024
#define PROTO_COMPARE_MAX_PHASE_SAMPLES (1L << 22)

typedef struct proto_compare_spec {
    proto_render_spec common;
    size_t count;
    aa_pattern *patterns;
    char (*names)[64]; /* the preset's name, the pattern's "name", or its family */
} proto_compare_spec;

int proto_decode_compare_spec(const json_t *spec, proto_compare_spec *out, aa_error *err);
void proto_compare_spec_free(proto_compare_spec *s);

/* One reference render (output grid offset 0.5 or 1). */
typedef struct proto_compare_render {
    double output_offset, seconds;
    long long supersampled, input_pixels_sampled, samples;
    json_t *tile; /* tile reference, or NULL */
} proto_compare_render;

typedef struct proto_compare_row {
    char name[64];
    char family[48];
    double samples_per_pixel, e2, rmse, max_dev, render_seconds;
    double predicted_rmse; /* the edge model's (docs/predict.md); NaN when absent */
    /* Measured share of the squared error on pixels below the pixel scale (the part the
     * prediction leaves out); NaN when absent or undefined. */
    double subpixel_error_share;
    long long pixels_sampled, coverage_samples;
    aa_diff_stats stats;
    bool have_tiles;                        /* "tiles" present (the images were stored) */
    json_t *tile_pattern, *tile_difference; /* each may be NULL */
} proto_compare_row;

typedef struct proto_compare_result {
    aa_scene_params scene;
    long long reference_spp, reference_seed;
    char filter[24];
    proto_compare_render renders[2];
    size_t render_count;
    proto_compare_row *rows;
    size_t row_count;
    /* The edge model beside the renders: Spearman rho of predicted against measured RMSE over
     * the rows (NaN: undefined) and the image share below the pixel scale it leaves out.
     * have_prediction false: an older result without them. */
    bool have_prediction;
    double spearman_predicted, subpixel_area_share;
    /* The acuity table the rows' E2 use (proto_acuity_ref_set); "" in results stored before it
     * was recorded. */
    char acuity_name[24];
    int acuity_version;
} proto_compare_result;

/* {"scene", "reference": {"spp", "seed", "filter", "renders": [{"output_offset", "seconds",
 * "supersampled", "input_pixels_sampled", "samples", "tile"?}]}, "rows": [{"name", "family",
 * "samples_per_pixel", "e2", "rmse", "predicted_rmse"?, "max_dev", "render_seconds",
 * "pixels_sampled", "coverage_samples", "stats", "tiles"?: {"pattern"?, "difference"?}}],
 * "prediction"?: {"spearman", "subpixel_area_share"}, "acuity"?: {"name", "version"}}; NULL when
 * out of memory. */
json_t *proto_encode_compare_result(const proto_compare_result *r);
int proto_decode_compare_result(const json_t *j, proto_compare_result *out, aa_error *err);
void proto_compare_result_free(proto_compare_result *r);

#endif
