/* Internal to the optimizer: the free variables of a pattern (movable points and weights) and
 * how every kernel sample is derived from them, so that sharing, sites and mirroring hold by
 * construction. Not part of the public API. */
#ifndef AA_OPTIMIZER_STATE_H
#define AA_OPTIMIZER_STATE_H

#include <stddef.h>

#include "aa_core.h"
#include "aa_pattern.h"

typedef struct opt_point {
    double x, y;
    double lo_x, hi_x, lo_y, hi_y; /* box the point may move in (degenerate on a fixed axis) */
    aa_site site;
} opt_point;

typedef struct opt_ref {
    size_t point;  /* movable point this kernel sample follows */
    size_t weight; /* weight slot */
    double sx, sy; /* mirror signs */
    double ox, oy; /* fixed offset: sample = (sx * point.x + ox, sy * point.y + oy) */
} opt_ref;

typedef struct opt_state {
    aa_pattern work;    /* kernels hold the current samples */
    size_t point_count; /* movable points */
    opt_point *points;
    size_t weight_count; /* weight slots */
    double *weights;
    size_t *weight_group; /* slot -> normalisation group (a kernel, or 0 for mirrored) */
    size_t group_count;
    opt_ref **refs; /* refs[k][i] for kernel sample i of kernel k */
} opt_state;

#define OPT_SITE_MARGIN 1e-6

int opt_state_init(opt_state *st, const aa_pattern *seed, aa_error *err);
void opt_state_free(opt_state *st);
/* Writes the variables into the kernels' samples. */
void opt_state_apply(opt_state *st);
/* Builds a standalone pattern of the current variables (same form as the seed). */
int opt_state_to_pattern(const opt_state *st, aa_pattern *out, aa_error *err);
/* Clamps a point into its box (sites: corner fixed, edges slide, interior inside its pixel). */
void opt_point_clamp(opt_point *p);
/* Divides each group's weights by their sum (skipped if the sum is ~0). */
void opt_state_normalize_weights(opt_state *st);

#endif
