/* Edge histograms of the built-in scenes: how much edge of each orientation a scene shows in the
 * image, the input of the edge model (predict.h).
 *
 * Angle convention: the metric's (metric.h). θ is the angle of the edge's normal in pixel
 * coordinates (x right, y down), p = x cos θ + y sin θ, taken modulo 180° because
 * E1(θ + 180°) = E1(θ). Bin d (0..179) holds the normals with θ in [d − 0.5°, d + 0.5°) mod 180°,
 * so axis-aligned edges fall on the centres of bins 0 and 90 and the model evaluates E1 at the
 * bin centre d.
 *
 * Lengths are in pixels of unit-contrast edge: a step of contrast c counts c² times its length
 * (the squared error of an edge scales with c²). Only the part inside the image counts.
 *
 * Every built-in scene is analytic: straight edges (half-plane, sliver, triangle) are clipped to
 * the image exactly; arcs (rings, circle, star rim) are summed per degree of arc, 16 sub-arcs per
 * degree tested against the image; the spiral's Archimedean arcs and the checkerboard's
 * perspective grid lines are integrated along the curve in steps of at most 1/4 px.
 *
 * What the edge model does not cover:
 *  - pixel-locked edges. A straight edge whose normal is an integer direction (p, q) with
 *    |p|, |q| <= AA_EDGE_LOCK_MAX (0°, 90°, 45°, 26.57°, ...) meets the pixel grid at only a
 *    lattice of offsets, spaced 1/sqrt(p² + q²) and repeating along the edge; its summed squared
 *    error is a sampled sum, not L·E1². Such edges are listed in `locked` (up to
 *    AA_EDGE_MAX_LOCKED; any beyond go into the bins and are counted in locked_excess) and the
 *    prediction evaluates their sampled sums exactly (predict.h).
 *  - detail below the pixel scale: where neighbouring edges are closer than 1 px (the star's
 *    centre, the checkerboard towards its horizon) the edges are left out of the bins and the
 *    area is reported in subpixel_area (px²); its error is not estimated.
 * Mirroring (mirror_x, mirror_y) maps θ to 180° − θ and −θ and mirrors the locked lines. */
#ifndef AA_EDGE_HISTOGRAM_H
#define AA_EDGE_HISTOGRAM_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_core.h"
#include "image.h"
#include "scene.h"

#define AA_EDGE_BINS 180
#define AA_EDGE_MAX_LOCKED 256
/* Spacing (px) between neighbouring edges below which a scene's detail is "below the pixel". */
#define AA_EDGE_SUBPIXEL_SPACING 1.0

#define AA_EDGE_LOCK_MAX 5

/* The line p x + q y = c (pixel coordinates); (p, q) coprime integers, the normal's direction. */
typedef struct aa_locked_edge {
    int p, q;
    double c;
    double length; /* px × contrast² */
} aa_locked_edge;

/* A straight edge of the bins (not locked), clipped to the image, kept with its geometry so
 * that the prediction can sum its pixels' errors exactly (predict.h, AA_PREDICT_SEGMENT_SUMS):
 * the half-plane's line and the triangles' sides. open0 / open1: that end was cut by the image
 * border (the edge goes on), else it is a corner. */
#define AA_EDGE_MAX_SEGMENTS 8
typedef struct aa_edge_segment {
    double x0, y0, x1, y1;
    bool open0, open1;
    double length; /* px × contrast², exactly as added to its bin */
} aa_edge_segment;

typedef struct aa_edge_histogram {
    double length[AA_EDGE_BINS]; /* unit-contrast px per bin, locked edges excluded */
    double total;                /* sum of length[] plus the locked lengths */
    size_t locked_count;
    aa_locked_edge locked[AA_EDGE_MAX_LOCKED];
    double locked_excess; /* locked length that did not fit in locked[] and went into the bins */
    double subpixel_area; /* px² of image with detail below AA_EDGE_SUBPIXEL_SPACING */
    int width, height;
    size_t segment_count; /* straight edges also kept as segments; their length stays in length[] */
    aa_edge_segment segment[AA_EDGE_MAX_SEGMENTS];
} aa_edge_histogram;

/* Bin of a normal angle in degrees (any real): round to the nearest degree, modulo 180. */
int aa_edge_bin(double theta_deg);
/* The bin of a locked edge's normal. */
int aa_locked_edge_bin(const aa_locked_edge *e);

/* The histogram measured on an image (the reference) from its gradients, as a check of the
 * analytic ones: central differences at the interior pixels, |∇I| added to the bin of the
 * gradient's direction (the edge normal) taken from the image blurred by a Gaussian of 1.5 px
 * (central differences of a sharp step are biased towards the diagonals). For an isolated edge of
 * contrast c the sum over the pixels it crosses is c·L·∫|g'|, slightly above c·L where the filter
 * has negative lobes (Mitchell 1/3, 1/3), and a step of contrast c counts c, not c², times its
 * length; neighbouring edges closer than the filter cancel. No locked edges, no sub-pixel area.
 * Errors: AA_EINVAL (image smaller than 3 x 3). */
int aa_edge_histogram_from_image(const aa_image *img, aa_edge_histogram *h, aa_error *err);

/* True where the scene has detail below the pixel scale at (x, y) (pixel coordinates, mirroring
 * applied): the criterion of subpixel_area, i.e. the star within r_c of its centre, the
 * checkerboard where a cell spacing is below AA_EDGE_SUBPIXEL_SPACING. */
bool aa_scene_below_pixel(const aa_scene *s, double x, double y);
/* The share of the squared error (approx - reference)² that falls on pixels whose centre is
 * below the pixel scale: the part of a render's error the edge model leaves out, measured. NaN
 * when the images are equal or their sizes differ from the scene's. */
double aa_subpixel_error_share(const aa_scene *s, const aa_image *approx, const aa_image *ref);

/* The histogram of a prepared scene. Errors: AA_EINVAL (an animation scene's parameters are
 * per frame: the current frame is used, so none here beyond a bad scene shape). */
int aa_edge_histogram_of_scene(const aa_scene *s, aa_edge_histogram *h, aa_error *err);

/* length[] with the locked edges added to their bins: the histogram as the scene objective
 * (objective_scene.h) sees it, every edge treated as spread over offsets. */
void aa_edge_histogram_folded(const aa_edge_histogram *h, double out[AA_EDGE_BINS]);

#endif
