/* Scene evaluation: the value at a point and the conservative constant-box test (scene.h). */
#include "scene.h"

#include <math.h>

#define PI 3.14159265358979323846
/* Angles and phases are compared with this margin so that the box test never calls a box
 * uniform that aa_scene_value would split by rounding. */
#define MARGIN 1e-9

static long long floor_ll(double v)
{
    return (long long)floor(v);
}

static double parity_value(long long k)
{
    return k % 2 != 0 ? 1.0 : 0.0;
}

static void ground_coords(const aa_scene *s, double x, double y, double *gx, double *gz)
{
    double v = (y - s->horizon_y) / s->unit, u = (x - s->cx) / s->unit;
    double Z = 1.0 / v, X = u / v; /* camera height 1 */
    *gx = X * s->cos_a + Z * s->sin_a;
    *gz = -X * s->sin_a + Z * s->cos_a;
}

static double polygon_value(const aa_scene *s, double x, double y, double inside, double outside)
{
    for (size_t k = 0; k < s->edge_count; k++)
        if (!aa_edge_inside(&s->edge[k], x, y))
            return outside;
    return inside;
}

static double scene_value(const aa_scene *s, double x, double y)
{
    switch (s->p.shape) {
    case AA_SCENE_HALF_PLANE:
        return polygon_value(s, x, y, 1.0, 0.0);
    case AA_SCENE_SLIVER:
    case AA_SCENE_ROTATING_TRIANGLE:
        return polygon_value(s, x, y, 0.0, 1.0);
    case AA_SCENE_CHECKERBOARD: {
        if (y <= s->horizon_y)
            return 1.0;
        double gx, gz;
        ground_coords(s, x, y, &gx, &gz);
        return parity_value(floor_ll(gx / s->cell) + floor_ll(gz / s->cell));
    }
    case AA_SCENE_SIEMENS_STAR: {
        double dx = x - s->cx, dy = y - s->cy;
        if (hypot(dx, dy) > s->radius)
            return s->background;
        return 1.0 - parity_value(floor_ll((atan2(dy, dx) - s->angle0) / s->sector));
    }
    case AA_SCENE_SPIRAL: {
        double dx = x - s->cx, dy = y - s->cy, d = hypot(dx, dy);
        if (d > s->radius)
            return s->background;
        return parity_value(floor_ll(2.0 * (d / s->pitch - atan2(dy, dx) / (2 * PI))));
    }
    case AA_SCENE_RINGS:
    case AA_SCENE_TRANSLATING_CIRCLE:
        for (size_t k = 0; k < s->ring_count; k++) {
            const aa_ring *r = &s->ring[k];
            double d = hypot(x - r->cx, y - r->cy);
            if (d <= r->r_out && d >= r->r_in)
                return 0.0;
        }
        return s->background;
    default:
        return s->background;
    }
}

/* Distance range from (cx, cy) to the closed box. */
static void box_distance(double cx, double cy, double x0, double y0, double x1, double y1,
                         double *dmin, double *dmax)
{
    double ex = fmax(fmax(x0 - cx, cx - x1), 0), ey = fmax(fmax(y0 - cy, cy - y1), 0);
    *dmin = hypot(ex, ey);
    *dmax = hypot(fmax(fabs(x0 - cx), fabs(x1 - cx)), fmax(fabs(y0 - cy), fabs(y1 - cy)));
}

/* Angle range (continuous, may leave (-pi, pi]) of a box that does not contain the centre. */
static void box_angles(double cx, double cy, double x0, double y0, double x1, double y1,
                       double *amin, double *amax)
{
    double mid = atan2((y0 + y1) / 2 - cy, (x0 + x1) / 2 - cx);
    const double xs[4] = {x0, x1, x0, x1}, ys[4] = {y0, y0, y1, y1};
    *amin = INFINITY;
    *amax = -INFINITY;
    for (int k = 0; k < 4; k++) {
        double d = atan2(ys[k] - cy, xs[k] - cx) - mid;
        if (d > PI)
            d -= 2 * PI;
        if (d < -PI)
            d += 2 * PI;
        *amin = fmin(*amin, mid + d);
        *amax = fmax(*amax, mid + d);
    }
    *amin -= MARGIN;
    *amax += MARGIN;
}

static bool polygon_box(const aa_scene *s, double x0, double y0, double x1, double y1,
                        double inside, double outside, double *value)
{
    bool all_in = true;
    for (size_t k = 0; k < s->edge_count; k++) {
        const aa_edge *e = &s->edge[k];
        double lo = e->c + fmin(e->a * x0, e->a * x1) + fmin(e->b * y0, e->b * y1);
        double hi = e->c + fmax(e->a * x0, e->a * x1) + fmax(e->b * y0, e->b * y1);
        if (hi < 0) {
            *value = outside;
            return true;
        }
        if (!(lo > 0))
            all_in = false;
    }
    if (all_in)
        *value = inside;
    return all_in;
}

/* Radial scenes: constant inside the disc of s->radius when k_lo == k_hi. */
static bool radial_box(const aa_scene *s, double dmax, long long k_lo, long long k_hi, double inner,
                       double *value)
{
    if (k_lo != k_hi)
        return false;
    if (dmax <= s->radius || inner == s->background) {
        *value = inner;
        return true;
    }
    return false;
}

static bool box_uniform(const aa_scene *s, double x0, double y0, double x1, double y1,
                        double *value)
{
    switch (s->p.shape) {
    case AA_SCENE_HALF_PLANE:
        return polygon_box(s, x0, y0, x1, y1, 1.0, 0.0, value);
    case AA_SCENE_SLIVER:
    case AA_SCENE_ROTATING_TRIANGLE:
        return polygon_box(s, x0, y0, x1, y1, 0.0, 1.0, value);
    case AA_SCENE_CHECKERBOARD: {
        if (y1 <= s->horizon_y) {
            *value = 1.0;
            return true;
        }
        if (y0 <= s->horizon_y)
            return false;
        const double xs[4] = {x0, x1, x0, x1}, ys[4] = {y0, y0, y1, y1};
        double gx_lo = INFINITY, gx_hi = -INFINITY, gz_lo = INFINITY, gz_hi = -INFINITY;
        for (int k = 0; k < 4; k++) {
            double gx, gz;
            ground_coords(s, xs[k], ys[k], &gx, &gz);
            gx_lo = fmin(gx_lo, gx);
            gx_hi = fmax(gx_hi, gx);
            gz_lo = fmin(gz_lo, gz);
            gz_hi = fmax(gz_hi, gz);
        }
        double m = MARGIN * (1 + fmax(fabs(gx_lo), fabs(gz_lo)) + fmax(fabs(gx_hi), fabs(gz_hi)));
        long long ix = floor_ll((gx_lo - m) / s->cell), iz = floor_ll((gz_lo - m) / s->cell);
        if (ix != floor_ll((gx_hi + m) / s->cell) || iz != floor_ll((gz_hi + m) / s->cell))
            return false;
        *value = parity_value(ix + iz);
        return true;
    }
    case AA_SCENE_SIEMENS_STAR:
    case AA_SCENE_SPIRAL: {
        double dmin, dmax, amin, amax;
        box_distance(s->cx, s->cy, x0, y0, x1, y1, &dmin, &dmax);
        if (dmin > s->radius) {
            *value = s->background;
            return true;
        }
        if (dmin == 0)
            return false;
        box_angles(s->cx, s->cy, x0, y0, x1, y1, &amin, &amax);
        if (s->p.shape == AA_SCENE_SIEMENS_STAR) {
            long long lo = floor_ll((amin - s->angle0) / s->sector);
            long long hi = floor_ll((amax - s->angle0) / s->sector);
            return radial_box(s, dmax, lo, hi, 1.0 - parity_value(lo), value);
        }
        double ph_lo = 2.0 * (dmin / s->pitch - amax / (2 * PI)) - MARGIN;
        double ph_hi = 2.0 * (dmax / s->pitch - amin / (2 * PI)) + MARGIN;
        long long lo = floor_ll(ph_lo), hi = floor_ll(ph_hi);
        return radial_box(s, dmax, lo, hi, parity_value(lo), value);
    }
    case AA_SCENE_RINGS:
    case AA_SCENE_TRANSLATING_CIRCLE: {
        for (size_t k = 0; k < s->ring_count; k++) {
            const aa_ring *r = &s->ring[k];
            double dmin, dmax;
            box_distance(r->cx, r->cy, x0, y0, x1, y1, &dmin, &dmax);
            if (dmax < r->r_in || dmin > r->r_out)
                continue;
            if (dmin > r->r_in && dmax < r->r_out) {
                *value = 0.0;
                return true;
            }
            return false;
        }
        *value = s->background;
        return true;
    }
    default:
        return false;
    }
}

/* Mirroring is applied here, around the scene's own geometry, so every scene mirrors. */
double aa_scene_value(const aa_scene *s, double x, double y)
{
    if (s->p.mirror_x)
        x = s->p.width - x;
    if (s->p.mirror_y)
        y = s->p.height - y;
    return scene_value(s, x, y);
}

bool aa_scene_box_uniform(const aa_scene *s, double x0, double y0, double x1, double y1,
                          double *value)
{
    if (s->p.mirror_x) {
        double t = s->p.width - x1;
        x1 = s->p.width - x0;
        x0 = t;
    }
    if (s->p.mirror_y) {
        double t = s->p.height - y1;
        y1 = s->p.height - y0;
        y0 = t;
    }
    return box_uniform(s, x0, y0, x1, y1, value);
}
