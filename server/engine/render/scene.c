/* Analytic test scenes: names, parameters, layout and content bounds (scene.h); values and
 * the constant-box test are in scene_eval.c. */
#include "scene.h"

#include <math.h>
#include <string.h>

#include "image.h"

#define PI 3.14159265358979323846

static const char *const scene_names[AA_SCENE_SHAPE_COUNT] = {
    "half-plane", "checkerboard", "siemens-star",      "rings",
    "sliver",     "spiral",       "rotating-triangle", "translating-circle"};

int aa_scene_shape_from_name(const char *name)
{
    for (int k = 0; k < AA_SCENE_SHAPE_COUNT; k++)
        if (name && strcmp(name, scene_names[k]) == 0)
            return k;
    return -1;
}

const char *aa_scene_shape_name(aa_scene_shape shape)
{
    return (unsigned)shape < AA_SCENE_SHAPE_COUNT ? scene_names[shape] : "unknown";
}

bool aa_scene_shape_is_animation(aa_scene_shape shape)
{
    return shape == AA_SCENE_ROTATING_TRIANGLE || shape == AA_SCENE_TRANSLATING_CIRCLE;
}

aa_scene_params aa_scene_params_default(aa_scene_shape shape)
{
    aa_scene_params p = {shape, 256, 256, 1.0, 0.0, 16, 16, 0, 0.0, false, false};
    if (shape == AA_SCENE_CHECKERBOARD)
        p.angle_deg = 20;
    return p;
}

bool aa_edge_inside(const aa_edge *e, double x, double y)
{
    double v = e->a * x + e->b * y + e->c;
    if (v != 0)
        return v > 0;
    return e->a > 0 || (e->a == 0 && e->b > 0);
}

aa_edge aa_edge_from_normal(double px, double py, double nx, double ny)
{
    double len = hypot(nx, ny);
    nx /= len;
    ny /= len;
    return (aa_edge){nx, ny, -(nx * px + ny * py)};
}

aa_edge aa_edge_through(double px, double py, double qx, double qy)
{
    return aa_edge_from_normal(px, py, -(qy - py), qx - px);
}

/* Triangle with the inside on the right of every edge (clockwise on a y-down screen). */
static void set_triangle(aa_scene *s, const double v[3][2])
{
    double area =
        (v[1][0] - v[0][0]) * (v[2][1] - v[0][1]) - (v[2][0] - v[0][0]) * (v[1][1] - v[0][1]);
    int order[3] = {0, 1, 2};
    if (area < 0) {
        order[1] = 2;
        order[2] = 1;
    }
    for (int k = 0; k < 3; k++) {
        const double *p = v[order[k]], *q = v[order[(k + 1) % 3]];
        s->edge[k] = aa_edge_through(p[0], p[1], q[0], q[1]);
    }
    s->edge_count = 3;
}

/* Scene units -> pixels, rotated by angle (radians) about the image centre. */
static void to_pixels(const aa_scene *s, double ux, double uy, double angle, double out[2])
{
    double c = cos(angle), sn = sin(angle);
    out[0] = s->cx + s->unit * (c * ux - sn * uy);
    out[1] = s->cy + s->unit * (sn * ux + c * uy);
}

static int check_params(const aa_scene_params *p, aa_error *err)
{
    if ((unsigned)p->shape >= AA_SCENE_SHAPE_COUNT)
        return aa_error_set(err, AA_EINVAL, "name", "unknown scene");
    if (p->width < 1 || p->width > AA_IMAGE_MAX_SIDE)
        return aa_error_set(err, AA_EINVAL, "width", "width must be 1..%d", AA_IMAGE_MAX_SIDE);
    if (p->height < 1 || p->height > AA_IMAGE_MAX_SIDE)
        return aa_error_set(err, AA_EINVAL, "height", "height must be 1..%d", AA_IMAGE_MAX_SIDE);
    if (!(p->zoom >= 1e-3 && p->zoom <= 1e3))
        return aa_error_set(err, AA_EINVAL, "zoom", "zoom must be in [0.001, 1000]");
    if (!(fabs(p->angle_deg) <= 1e6))
        return aa_error_set(err, AA_EINVAL, "angle", "angle must be a finite number of degrees");
    if (p->wedges < 1 || p->wedges > AA_SCENE_MAX_WEDGES)
        return aa_error_set(err, AA_EINVAL, "wedges", "wedges must be 1..%d", AA_SCENE_MAX_WEDGES);
    if (p->frames < 1 || p->frames > AA_SCENE_MAX_FRAMES)
        return aa_error_set(err, AA_EINVAL, "frames", "frames must be 1..%d", AA_SCENE_MAX_FRAMES);
    if (p->frame < 0 || p->frame >= p->frames)
        return aa_error_set(err, AA_EINVAL, "frame", "frame must be 0..frames-1");
    if (!(fabs(p->offset) <= 1e6))
        return aa_error_set(err, AA_EINVAL, "offset", "offset must be finite, |offset| <= 1e6");
    return AA_OK;
}

int aa_scene_init(aa_scene *s, const aa_scene_params *p, aa_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = check_params(p, err);
    if (rc)
        return rc;
    s->p = *p;
    s->cx = p->width / 2.0;
    s->cy = p->height / 2.0;
    s->unit = p->zoom * (p->width < p->height ? p->width : p->height) / 2.0;
    s->background = 1.0;
    double a = p->angle_deg * PI / 180.0;
    switch (p->shape) {
    case AA_SCENE_HALF_PLANE: {
        /* Value 1 on the side the normal (cos a, sin a) points away from. */
        double nx = cos(a), ny = sin(a);
        s->edge[0] = aa_edge_from_normal(s->cx + p->offset * nx, s->cy + p->offset * ny, -nx, -ny);
        s->edge_count = 1;
        s->background = 0.0;
        break;
    }
    case AA_SCENE_CHECKERBOARD:
        s->horizon_y = s->cy - 0.6 * s->unit;
        s->cell = 0.25;
        s->cos_a = cos(a);
        s->sin_a = sin(a);
        break;
    case AA_SCENE_SIEMENS_STAR:
        s->radius = 0.95 * s->unit;
        s->sector = PI / p->wedges;
        s->angle0 = a;
        break;
    case AA_SCENE_RINGS:
        for (int k = 0; k < 9; k++) {
            double r_out = (0.04 + 0.032 * k) * s->unit;
            aa_ring *r = &s->ring[k];
            r->cx = s->cx + s->unit * 0.6 * (k % 3 - 1);
            r->cy = s->cy + s->unit * 0.6 * (k / 3 - 1);
            r->r_out = r_out;
            r->r_in = k % 2 ? 0.6 * r_out : 0.0;
        }
        s->ring_count = 9;
        break;
    case AA_SCENE_SLIVER: {
        const double u[3][2] = {{-0.9, 0.45}, {0.9, -0.2}, {0.9, -0.05}};
        double v[3][2];
        for (int k = 0; k < 3; k++)
            to_pixels(s, u[k][0], u[k][1], a, v[k]);
        set_triangle(s, v);
        break;
    }
    case AA_SCENE_SPIRAL:
        s->radius = 0.95 * s->unit;
        s->pitch = 0.16 * s->unit;
        break;
    case AA_SCENE_ROTATING_TRIANGLE: {
        /* One third of a turn over the animation: the loop is seamless. */
        double rot = a + (2 * PI / 3) * p->frame / p->frames;
        double v[3][2];
        for (int k = 0; k < 3; k++) {
            double t = rot + k * 2 * PI / 3 - PI / 2;
            to_pixels(s, 0.75 * cos(t), 0.75 * sin(t), 0, v[k]);
        }
        set_triangle(s, v);
        break;
    }
    case AA_SCENE_TRANSLATING_CIRCLE: {
        aa_ring *r = &s->ring[0];
        r->cx = s->cx + s->unit * (-0.5 + (double)p->frame / p->frames);
        r->cy = s->cy + 0.05 * s->unit;
        r->r_out = 0.35 * s->unit;
        r->r_in = 0;
        s->ring_count = 1;
        break;
    }
    default:
        break;
    }
    return AA_OK;
}

static bool bounds(const aa_scene *s, double box[4])
{
    switch (s->p.shape) {
    case AA_SCENE_SIEMENS_STAR:
    case AA_SCENE_SPIRAL:
        box[0] = s->cx - s->radius;
        box[1] = s->cy - s->radius;
        box[2] = s->cx + s->radius;
        box[3] = s->cy + s->radius;
        return true;
    case AA_SCENE_RINGS:
    case AA_SCENE_TRANSLATING_CIRCLE:
        box[0] = box[1] = INFINITY;
        box[2] = box[3] = -INFINITY;
        for (size_t k = 0; k < s->ring_count; k++) {
            const aa_ring *r = &s->ring[k];
            box[0] = fmin(box[0], r->cx - r->r_out);
            box[1] = fmin(box[1], r->cy - r->r_out);
            box[2] = fmax(box[2], r->cx + r->r_out);
            box[3] = fmax(box[3], r->cy + r->r_out);
        }
        return true;
    case AA_SCENE_SLIVER:
    case AA_SCENE_ROTATING_TRIANGLE: {
        /* Vertices are the pairwise intersections of the edges. */
        box[0] = box[1] = INFINITY;
        box[2] = box[3] = -INFINITY;
        for (int k = 0; k < 3; k++) {
            const aa_edge *e = &s->edge[k], *f = &s->edge[(k + 1) % 3];
            double det = e->a * f->b - e->b * f->a;
            double x = (e->b * f->c - f->b * e->c) / det, y = (f->a * e->c - e->a * f->c) / det;
            box[0] = fmin(box[0], x);
            box[1] = fmin(box[1], y);
            box[2] = fmax(box[2], x);
            box[3] = fmax(box[3], y);
        }
        return true;
    }
    default:
        return false;
    }
}

bool aa_scene_bounds(const aa_scene *s, double box[4])
{
    if (!bounds(s, box))
        return false;
    if (s->p.mirror_x) {
        double t = s->p.width - box[2];
        box[2] = s->p.width - box[0];
        box[0] = t;
    }
    if (s->p.mirror_y) {
        double t = s->p.height - box[3];
        box[3] = s->p.height - box[1];
        box[1] = t;
    }
    return true;
}
