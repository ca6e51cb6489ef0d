/* Analytic test scenes (intensities 0 and 1), resolution independent.
 *
 * Coordinates are image pixel coordinates: x to the right, y downwards, pixel (i, j) covers
 * [i, i+1] x [j, j+1]. A scene is laid out in units of u = zoom * min(width, height) / 2 pixels
 * around the image centre, so the same parameters give the same picture at any size.
 *
 * Tie rule (top-left style). Straight edges are edge functions E(x, y) = a x + b y + c with
 * the inside where E > 0. A point with E == 0 is inside exactly when the inward normal (a, b)
 * points right (a > 0), or points down for a horizontal edge (a == 0, b > 0): the left and top
 * edges of a shape own their boundary, as in Direct3D/OpenGL rasterisers. Two shapes sharing an
 * edge have opposite normals, so a sample on it is counted for exactly one of them. Cell and
 * sector indices (checkerboard, star, spiral) use floor(), the same rule along their own
 * coordinates; circles own their boundary (d <= r). aa_scene_value gives each point exactly one
 * value, so shared samples are never counted twice or missed.
 *
 * aa_scene_box_uniform is the conservative test that lets the renderers leave out what the
 * scene does not need: it returns true only when the scene is provably constant on the whole
 * closed box (it may say "mixed" for a box that happens to be constant). */
#ifndef AA_SCENE_H
#define AA_SCENE_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_core.h"

/* What a test scene draws, as pbrt calls its geometry a shape; the animations are shapes that
 * move. */
typedef enum aa_scene_shape {
    AA_SCENE_HALF_PLANE,
    /* Checkerboard: a ground plane seen from a pinhole camera at height 1 looking along the
     * ground. The horizon is the image row y_h = cy - 0.6 u (above it the sky, value 1); a
     * pixel below it at u_x = (x - cx) / u, v = (y - y_h) / u sees the ground point at depth
     * Z = 1 / v and lateral X = u_x / v. The board, rotated by angle about the vertical axis,
     * has square cells of 0.25 ground units: value parity(floor(gx / 0.25) + floor(gz / 0.25))
     * with gx = X cos a + Z sin a, gz = -X sin a + Z cos a. Its cell edges are two pencils of
     * straight lines meeting at vanishing points on the horizon; cells shrink towards the
     * horizon and get below the pixel scale there (edge_histogram.h). */
    AA_SCENE_CHECKERBOARD,
    AA_SCENE_SIEMENS_STAR,
    AA_SCENE_RINGS,  /* discs and rings of several radii */
    AA_SCENE_SLIVER, /* thin triangle, Hasselgren et al. Fig. 4 */
    AA_SCENE_SPIRAL,
    AA_SCENE_ROTATING_TRIANGLE,  /* animation */
    AA_SCENE_TRANSLATING_CIRCLE, /* animation */
    AA_SCENE_SHAPE_COUNT
} aa_scene_shape;

#define AA_SCENE_MAX_WEDGES 360
#define AA_SCENE_MAX_FRAMES 1000

typedef struct aa_scene_params {
    aa_scene_shape shape;
    int width, height; /* pixels */
    double zoom;       /* > 0; 1 frames the scene in the image */
    double angle_deg;  /* rotation: half-plane normal, board, star, sliver, triangle start */
    int wedges;        /* Siemens star: N dark wedges (2N sectors) */
    int frames;        /* animations: F frames */
    int frame;         /* animations: 0..F-1 */
    double offset;     /* half-plane: signed distance of the edge from the image centre, px */
    bool mirror_x;     /* evaluate the scene at (width - x, y): the scene mirrored left-right */
    bool mirror_y;     /* ... at (x, height - y) */
} aa_scene_params;

/* Defaults: 256 x 256, zoom 1, angle 0 (checkerboard 20; every other scene 0, the sliver
 * included: at 0 its short side is vertical, at x = cx + 0.9 u), 16 wedges, 16 frames, frame 0,
 * offset 0. */
aa_scene_params aa_scene_params_default(aa_scene_shape shape);

/* Name <-> shape: "half-plane", "checkerboard", "siemens-star", "rings", "sliver", "spiral",
 * "rotating-triangle", "translating-circle". Returns -1 for an unknown name. */
int aa_scene_shape_from_name(const char *name);
const char *aa_scene_shape_name(aa_scene_shape shape);
bool aa_scene_shape_is_animation(aa_scene_shape shape);

typedef struct aa_edge {
    double a, b, c; /* inside where a x + b y + c > 0 (tie rule above) */
} aa_edge;

typedef struct aa_ring {
    double cx, cy, r_in, r_out; /* r_in = 0: a disc */
} aa_ring;

#define AA_SCENE_MAX_RINGS 16

/* A prepared scene: a plain value, no free() needed, safe to share between threads. */
typedef struct aa_scene {
    aa_scene_params p;
    double cx, cy, unit; /* image centre and scene unit in pixels */
    double background;
    size_t edge_count; /* half-plane: 1; polygons: 3 */
    aa_edge edge[3];
    size_t ring_count;
    aa_ring ring[AA_SCENE_MAX_RINGS];
    double radius;       /* star, spiral: outer radius (px) */
    double sector;       /* star: sector width (rad) */
    double angle0;       /* star: rotation (rad) */
    double pitch;        /* spiral: radial distance per turn (px) */
    double horizon_y;    /* checkerboard */
    double cell;         /* checkerboard: cell size on the ground */
    double cos_a, sin_a; /* checkerboard: board rotation */
} aa_scene;

/* Validates and prepares. Errors name "width", "height", "zoom", "angle", "wedges", "frames",
 * "frame" or "offset". */
int aa_scene_init(aa_scene *s, const aa_scene_params *p, aa_error *err);

/* Intensity at a point (pixel coordinates). */
double aa_scene_value(const aa_scene *s, double x, double y);
/* True if the scene is constant on the closed box [x0, x1] x [y0, y1]; *value is then it. */
bool aa_scene_box_uniform(const aa_scene *s, double x0, double y0, double x1, double y1,
                          double *value);
/* Bounding box (x0, y0, x1, y1) of everything that is not background; false if unbounded.
 * Animations recompute only the pixels whose footprint meets the union of two frames' boxes. */
bool aa_scene_bounds(const aa_scene *s, double box[4]);

/* Edge functions with the tie rule. */
bool aa_edge_inside(const aa_edge *e, double x, double y);
/* Edge through p0 with inward unit normal (nx, ny). */
aa_edge aa_edge_from_normal(double px, double py, double nx, double ny);
/* Edge along p -> q with the inside on the right of the travel direction in y-down
 * coordinates (clockwise on screen); normalised to unit length. */
aa_edge aa_edge_through(double px, double py, double qx, double qy);

#endif
