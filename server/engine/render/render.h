/* One test tile: a scene rendered with a pattern beside the supersampled reference, with the
 * error statistics, the pattern's E2 and the wall time of each render. Also the
 * incremental animation renderer: frame by frame, only the pixels whose footprint meets the
 * moving content of this or the previous frame are recomputed. */
#ifndef AA_RENDER_H
#define AA_RENDER_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_metric.h"
#include "aa_core.h"
#include "aa_pattern.h"
#include "image.h"
#include "raster.h"
#include "reference.h"
#include "scene.h"

typedef struct aa_render_params {
    aa_scene_params scene;
    aa_reference_params reference; /* its filter is also the E2 reference filter */
    const aa_acuity *acuity;       /* NULL: Naiman */
    bool skip;                     /* leave out constant pixels in the pattern render */
} aa_render_params;

aa_render_params aa_render_params_default(aa_scene_shape shape);

typedef struct aa_render_result {
    aa_image pattern, reference;
    aa_diff_stats diff;
    double e2;
    double pattern_seconds, reference_seconds;
    aa_raster_stats raster;
    aa_reference_stats ref;
} aa_render_result;

/* Monotonic-enough wall clock in seconds (C11 timespec_get). */
double aa_seconds_now(void);
/* E2 of a pattern with the given filter (NULL: default) and acuity (NULL: Naiman). */
int aa_pattern_e2(const aa_pattern *p, const aa_filter *f, const aa_acuity *a, double *e2,
                  aa_error *err);

/* Renders pattern image and reference and compares them. On error *out holds nothing. */
int aa_render_tile(const aa_render_params *rp, const aa_pattern *p, aa_render_result *out,
                   aa_error *err);
void aa_render_result_free(aa_render_result *r);

/* Incremental animation. Call aa_animation_frame for frames 0, 1, ... in order; state keeps
 * the last frame's images (read them after each call). */
typedef struct aa_animation {
    aa_render_params params;
    const aa_pattern *pattern;
    aa_image pattern_img, reference_img;
    int next_frame;
    bool prev_bounded;
    double prev_box[4];
} aa_animation;

typedef struct aa_animation_frame_stats {
    int frame;
    size_t pixels_recomputed; /* pixels inside the recomputed rectangle */
    aa_raster_stats raster;
    aa_reference_stats ref;
    double pattern_seconds, reference_seconds;
    aa_diff_stats diff; /* this frame alone */
} aa_animation_frame_stats;

int aa_animation_init(aa_animation *a, const aa_render_params *rp, const aa_pattern *p,
                      aa_error *err);
int aa_animation_frame(aa_animation *a, aa_animation_frame_stats *st, aa_error *err);
void aa_animation_free(aa_animation *a);

#endif
