/* Edge histograms of the built-in scenes (edge_histogram.h). */
#include "edge_histogram.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)
/* Arc and curve integration resolution: sub-arcs per degree, largest step along a curve (px). */
#define ARC_SUBSTEPS 16
#define CURVE_STEP 0.25
/* |component| of a unit normal below which an edge counts as axis-aligned. */
#define AXIS_EPS 1e-9

int aa_edge_bin(double theta_deg)
{
    double d = fmod(floor(theta_deg + 0.5), 180.0);
    if (d < 0)
        d += 180.0;
    return (int)d % AA_EDGE_BINS;
}

static void add_angle(aa_edge_histogram *h, double nx, double ny, double length)
{
    h->length[aa_edge_bin(atan2(ny, nx) / DEG)] += length;
    h->total += length;
}

static int gcd(int a, int b)
{
    a = abs(a);
    b = abs(b);
    while (b) {
        int t = a % b;
        a = b;
        b = t;
    }
    return a;
}

/* The integer direction (p, q), |p|, |q| <= AA_EDGE_LOCK_MAX, of the unit normal (nx, ny), if
 * it has one. */
static bool lattice_direction(double nx, double ny, int *p, int *q)
{
    for (int a = -AA_EDGE_LOCK_MAX; a <= AA_EDGE_LOCK_MAX; a++)
        for (int b = -AA_EDGE_LOCK_MAX; b <= AA_EDGE_LOCK_MAX; b++) {
            if ((a == 0 && b == 0) || gcd(a, b) != 1)
                continue;
            double n = hypot(a, b);
            if (fabs(nx - a / n) < AXIS_EPS && fabs(ny - b / n) < AXIS_EPS) {
                *p = a;
                *q = b;
                return true;
            }
        }
    return false;
}

int aa_locked_edge_bin(const aa_locked_edge *e)
{
    return aa_edge_bin(atan2(e->q, e->p) / DEG);
}

/* A straight piece with unit-free normal (nx, ny) and a point (px, py) on its line. */
static void add_straight(aa_edge_histogram *h, double nx, double ny, double px, double py,
                         double length)
{
    if (!(length > 0))
        return;
    double n = hypot(nx, ny);
    nx /= n;
    ny /= n;
    int p, q;
    bool lattice = lattice_direction(nx, ny, &p, &q);
    if (lattice && h->locked_count < AA_EDGE_MAX_LOCKED) {
        h->locked[h->locked_count++] = (aa_locked_edge){p, q, p * px + q * py, length};
        h->total += length;
        return;
    }
    if (lattice)
        h->locked_excess += length;
    add_angle(h, nx, ny, length);
}

/* Liang-Barsky: clips p + t d, t in [*t0, *t1], to the box; false if nothing is left. */
static bool clip(double px, double py, double dx, double dy, const double box[4], double *t0,
                 double *t1)
{
    const double p[4] = {-dx, dx, -dy, dy};
    const double q[4] = {px - box[0], box[2] - px, py - box[1], box[3] - py};
    for (int k = 0; k < 4; k++) {
        if (p[k] == 0) {
            if (q[k] < 0)
                return false;
            continue;
        }
        double r = q[k] / p[k];
        if (p[k] < 0)
            *t0 = fmax(*t0, r);
        else
            *t1 = fmin(*t1, r);
    }
    return *t0 < *t1;
}

static void image_box(const aa_edge_histogram *h, double box[4])
{
    box[0] = 0;
    box[1] = 0;
    box[2] = h->width;
    box[3] = h->height;
}

/* The segment (x0, y0)-(x1, y1) of an edge with normal (nx, ny), contrast² c2. */
static void add_segment(aa_edge_histogram *h, double nx, double ny, double x0, double y0, double x1,
                        double y1, double c2)
{
    double box[4], t0 = 0, t1 = 1;
    image_box(h, box);
    if (clip(x0, y0, x1 - x0, y1 - y0, box, &t0, &t1))
        add_straight(h, nx, ny, x0, y0, c2 * (t1 - t0) * hypot(x1 - x0, y1 - y0));
}

/* add_segment, and the clipped segment kept in segment[] when it went into the bins. */
static void add_kept_segment(aa_edge_histogram *h, double nx, double ny, double x0, double y0,
                             double x1, double y1, double c2)
{
    size_t locked = h->locked_count;
    add_segment(h, nx, ny, x0, y0, x1, y1, c2);
    double box[4], t0 = 0, t1 = 1, dx = x1 - x0, dy = y1 - y0;
    image_box(h, box);
    if (h->locked_count != locked || h->segment_count >= AA_EDGE_MAX_SEGMENTS ||
        !clip(x0, y0, dx, dy, box, &t0, &t1))
        return;
    double length = c2 * (t1 - t0) * hypot(dx, dy); /* as add_segment computed it */
    if (!(length > 0))
        return;
    int p, q;
    double n = hypot(nx, ny);
    if (lattice_direction(nx / n, ny / n, &p, &q))
        return; /* locked_excess: in the bins, not kept */
    h->segment[h->segment_count++] = (aa_edge_segment){
        x0 + t0 * dx, y0 + t0 * dy, x0 + t1 * dx, y0 + t1 * dy, t0 > 0, t1 < 1, length};
}

/* The whole line a x + b y + c = 0. */
static void add_line(aa_edge_histogram *h, const aa_edge *e, double c2)
{
    double n2 = e->a * e->a + e->b * e->b, far = 4.0 * (h->width + h->height) + 1e7;
    double px = -e->c * e->a / n2, py = -e->c * e->b / n2, dx = -e->b, dy = e->a;
    add_kept_segment(h, e->a, e->b, px - far * dx, py - far * dy, px + far * dx, py + far * dy, c2);
}

static bool in_image(const aa_edge_histogram *h, double x, double y)
{
    return x >= 0 && x <= h->width && y >= 0 && y <= h->height;
}

typedef bool (*arc_filter)(const aa_scene *s, double phi);

/* Circle of radius r about (cx, cy); the normal of the point at angle phi is phi itself. Sub-arcs
 * are split at half degrees so that each falls in one bin. keep (may be NULL) selects arcs. */
static void add_circle(aa_edge_histogram *h, const aa_scene *s, double cx, double cy, double r,
                       arc_filter keep)
{
    if (!(r > 0))
        return;
    double dphi = DEG / ARC_SUBSTEPS;
    for (int d = 0; d < 360; d++)
        for (int k = 0; k < ARC_SUBSTEPS; k++) {
            double phi = (d - 0.5) * DEG + (k + 0.5) * dphi;
            if (!in_image(h, cx + r * cos(phi), cy + r * sin(phi)))
                continue;
            if (keep && !keep(s, phi))
                continue;
            h->length[d % AA_EDGE_BINS] += r * dphi;
            h->total += r * dphi;
        }
}

static long long floor_ll(double v)
{
    return (long long)floor(v);
}

/* Star: the rim is an edge where the sector is dark (value 0 against the background 1). */
static bool star_rim_dark(const aa_scene *s, double phi)
{
    double a = atan2(sin(phi), cos(phi));
    return floor_ll((a - s->angle0) / s->sector) % 2 != 0;
}

static void star(aa_edge_histogram *h, const aa_scene *s)
{
    size_t rays = 2 * (size_t)s->p.wedges;
    /* Neighbouring rays are r * sector apart: closer than the pixel scale inside r_c. */
    double r_c = fmin(AA_EDGE_SUBPIXEL_SPACING / s->sector, s->radius);
    for (size_t k = 0; k < rays; k++) {
        double phi = s->angle0 + k * s->sector, c = cos(phi), sn = sin(phi);
        add_segment(h, -sn, c, s->cx + r_c * c, s->cy + r_c * sn, s->cx + s->radius * c,
                    s->cy + s->radius * sn, 1.0);
    }
    add_circle(h, s, s->cx, s->cy, s->radius, star_rim_dark);
    int x0 = (int)fmax(0, floor(s->cx - r_c)), x1 = (int)fmin(h->width, ceil(s->cx + r_c));
    int y0 = (int)fmax(0, floor(s->cy - r_c)), y1 = (int)fmin(h->height, ceil(s->cy + r_c));
    for (int j = y0; j < y1; j++)
        for (int i = x0; i < x1; i++)
            if (hypot(i + 0.5 - s->cx, j + 0.5 - s->cy) < r_c)
                h->subpixel_area += 1;
}

/* Spiral: value parity(floor(2 (d / pitch - phi / 2 pi))), so the edges are the curves
 * d = b (pi m + phi), b = pitch / 2 pi, phi in (-pi, pi], d in (0, R], and the rim where the
 * value inside is 0. */
static bool spiral_rim_dark(const aa_scene *s, double phi)
{
    double a = atan2(sin(phi), cos(phi));
    return floor_ll(2.0 * (s->radius / s->pitch - a / (2 * PI))) % 2 == 0;
}

static void spiral(aa_edge_histogram *h, const aa_scene *s)
{
    /* Only the arcs within the image's reach from the centre are visible: this bounds the work
     * by the image, whatever the zoom. */
    double reach = hypot(fmax(s->cx, h->width - s->cx), fmax(s->cy, h->height - s->cy));
    double b = s->pitch / (2 * PI), R = fmin(s->radius, reach);
    int steps = (int)ceil(2 * PI * hypot(R, b) / CURVE_STEP);
    double dphi = 2 * PI / steps;
    int m_max = (int)ceil(R / (b * PI)) + 1;
    for (int m = -1; m <= m_max; m++)
        for (int k = 0; k < steps; k++) {
            double phi = -PI + (k + 0.5) * dphi, d = b * (PI * m + phi);
            if (!(d > 0 && d <= R))
                continue;
            double c = cos(phi), sn = sin(phi);
            double x = s->cx + d * c, y = s->cy + d * sn;
            if (!in_image(h, x, y))
                continue;
            double tx = b * c - d * sn, ty = b * sn + d * c;
            add_angle(h, -ty, tx, hypot(tx, ty) * dphi);
        }
    add_circle(h, s, s->cx, s->cy, s->radius, spiral_rim_dark);
}

/* Checkerboard. With u = (x - cx) / unit, v = (y - horizon) / unit the ground coordinates are
 * gx = (u cos a + sin a) / v and gz = (-u sin a + cos a) / v (scene_eval.c), so the cell
 * boundaries gx = m cell and gz = m cell are two pencils of straight lines through vanishing
 * points on the horizon. Near a point the lines of one pencil are
 * cell v unit / sqrt(cos² a + gx²) px apart (the other: sin² a + gz²); a line counts where both
 * spacings are at least AA_EDGE_SUBPIXEL_SPACING. */
static void board_spacings(const aa_scene *s, double x, double y, double *s1, double *s2)
{
    double v = (y - s->horizon_y) / s->unit, u = (x - s->cx) / s->unit;
    double gx = (u * s->cos_a + s->sin_a) / v, gz = (-u * s->sin_a + s->cos_a) / v;
    double k = s->cell * v * s->unit;
    *s1 = k / sqrt(s->cos_a * s->cos_a + gx * gx);
    *s2 = k / sqrt(s->sin_a * s->sin_a + gz * gz);
}

static void board_line(aa_edge_histogram *h, const aa_scene *s, double A, double B, double C)
{
    /* A u + B v + C = 0 in pixels: A x + B y + (C unit - A cx - B horizon) = 0. */
    double c = C * s->unit - A * s->cx - B * s->horizon_y;
    double nl = hypot(A, B);
    /* Own pencil spacing >= 1 px needs v >= nl / (cell unit). */
    double y_min = s->horizon_y + s->unit * (AA_EDGE_SUBPIXEL_SPACING * nl / (s->cell * s->unit));
    double box[4] = {0, fmax(0, y_min), h->width, h->height};
    if (!(box[1] < box[3]))
        return;
    double px = -c * A / (nl * nl), py = -c * B / (nl * nl), dx = -B / nl, dy = A / nl;
    double far = 4.0 * (h->width + h->height) + fabs(px) + fabs(py);
    double t0 = -far, t1 = far;
    if (!clip(px, py, dx, dy, box, &t0, &t1))
        return;
    int steps = (int)ceil((t1 - t0) / CURVE_STEP);
    double dt = (t1 - t0) / steps, kept = 0;
    for (int k = 0; k < steps; k++) {
        double t = t0 + (k + 0.5) * dt, s1, s2;
        board_spacings(s, px + t * dx, py + t * dy, &s1, &s2);
        if (fmin(s1, s2) >= AA_EDGE_SUBPIXEL_SPACING)
            kept += dt;
    }
    add_straight(h, A, B, px, py, kept);
}

static void checkerboard(aa_edge_histogram *h, const aa_scene *s)
{
    double v_max = (h->height - s->horizon_y) / s->unit;
    if (v_max <= 0)
        return;
    int M = (int)ceil(v_max * s->unit / (AA_EDGE_SUBPIXEL_SPACING)) + 1;
    for (int m = -M; m <= M; m++) {
        board_line(h, s, s->cos_a, -m * s->cell, s->sin_a);
        board_line(h, s, -s->sin_a, -m * s->cell, s->cos_a);
    }
    /* The horizon: sky (1) against a board that averages 1/2 there, contrast 1/2. */
    if (s->horizon_y > 0 && s->horizon_y < h->height)
        add_segment(h, 0, 1, 0, s->horizon_y, h->width, s->horizon_y, 0.25);
    int j0 = (int)fmax(0, floor(s->horizon_y));
    for (int j = j0; j < h->height; j++)
        for (int i = 0; i < h->width; i++) {
            double y = j + 0.5, s1, s2;
            if (y <= s->horizon_y)
                continue;
            board_spacings(s, i + 0.5, y, &s1, &s2);
            if (fmin(s1, s2) < AA_EDGE_SUBPIXEL_SPACING)
                h->subpixel_area += 1;
        }
}

static void intersect(const aa_edge *e, const aa_edge *f, double *x, double *y)
{
    double det = e->a * f->b - e->b * f->a;
    *x = (e->b * f->c - f->b * e->c) / det;
    *y = (f->a * e->c - e->a * f->c) / det;
}

static void triangle(aa_edge_histogram *h, const aa_scene *s)
{
    double vx[3], vy[3];
    for (int k = 0; k < 3; k++)
        intersect(&s->edge[k], &s->edge[(k + 1) % 3], &vx[k], &vy[k]);
    /* Edge k runs from its intersection with edge k-1 to the one with edge k+1. */
    for (int k = 0; k < 3; k++) {
        int prev = (k + 2) % 3;
        add_kept_segment(h, s->edge[k].a, s->edge[k].b, vx[prev], vy[prev], vx[k], vy[k], 1.0);
    }
}

static void mirror(aa_edge_histogram *h, bool mx, bool my)
{
    if (mx != my) {
        /* theta -> 180 - theta (x mirrored) or -theta (y mirrored): the same bin map. */
        double tmp[AA_EDGE_BINS];
        for (int d = 0; d < AA_EDGE_BINS; d++)
            tmp[(AA_EDGE_BINS - d) % AA_EDGE_BINS] = h->length[d];
        memcpy(h->length, tmp, sizeof tmp);
    }
    for (size_t k = 0; k < h->segment_count; k++) {
        aa_edge_segment *g = &h->segment[k];
        if (mx) {
            g->x0 = h->width - g->x0;
            g->x1 = h->width - g->x1;
        }
        if (my) {
            g->y0 = h->height - g->y0;
            g->y1 = h->height - g->y1;
        }
    }
    /* p x + q y = c with x -> W - x is (-p) x + q y = c - p W; likewise for y. */
    for (size_t k = 0; k < h->locked_count; k++) {
        aa_locked_edge *e = &h->locked[k];
        if (mx) {
            e->c -= e->p * (double)h->width;
            e->p = -e->p;
        }
        if (my) {
            e->c -= e->q * (double)h->height;
            e->q = -e->q;
        }
    }
}

int aa_edge_histogram_of_scene(const aa_scene *s, aa_edge_histogram *h, aa_error *err)
{
    memset(h, 0, sizeof *h);
    h->width = s->p.width;
    h->height = s->p.height;
    switch (s->p.shape) {
    case AA_SCENE_HALF_PLANE:
        add_line(h, &s->edge[0], 1.0);
        break;
    case AA_SCENE_SLIVER:
    case AA_SCENE_ROTATING_TRIANGLE:
        triangle(h, s);
        break;
    case AA_SCENE_RINGS:
    case AA_SCENE_TRANSLATING_CIRCLE:
        for (size_t k = 0; k < s->ring_count; k++) {
            const aa_ring *r = &s->ring[k];
            add_circle(h, s, r->cx, r->cy, r->r_out, NULL);
            add_circle(h, s, r->cx, r->cy, r->r_in, NULL);
        }
        break;
    case AA_SCENE_SIEMENS_STAR:
        star(h, s);
        break;
    case AA_SCENE_SPIRAL:
        spiral(h, s);
        break;
    case AA_SCENE_CHECKERBOARD:
        checkerboard(h, s);
        break;
    default:
        return aa_error_set(err, AA_EINVAL, "name", "unknown scene");
    }
    mirror(h, s->p.mirror_x, s->p.mirror_y);
    return AA_OK;
}

/* Separable Gaussian blur (sigma BLUR_SIGMA px, clamped at the borders) of img into out. */
#define BLUR_SIGMA 1.5
#define BLUR_RADIUS 5

static void blur(const aa_image *img, double *out, double *tmp)
{
    int W = img->width, H = img->height;
    double k[2 * BLUR_RADIUS + 1], sum = 0;
    for (int t = -BLUR_RADIUS; t <= BLUR_RADIUS; t++)
        sum += k[t + BLUR_RADIUS] = exp(-t * t / (2 * BLUR_SIGMA * BLUR_SIGMA));
    for (int t = 0; t <= 2 * BLUR_RADIUS; t++)
        k[t] /= sum;
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            double v = 0;
            for (int t = -BLUR_RADIUS; t <= BLUR_RADIUS; t++) {
                int x = i + t < 0 ? 0 : i + t >= W ? W - 1 : i + t;
                v += k[t + BLUR_RADIUS] * img->px[(size_t)j * W + x];
            }
            tmp[(size_t)j * W + i] = v;
        }
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            double v = 0;
            for (int t = -BLUR_RADIUS; t <= BLUR_RADIUS; t++) {
                int y = j + t < 0 ? 0 : j + t >= H ? H - 1 : j + t;
                v += k[t + BLUR_RADIUS] * tmp[(size_t)y * W + i];
            }
            out[(size_t)j * W + i] = v;
        }
}

int aa_edge_histogram_from_image(const aa_image *img, aa_edge_histogram *h, aa_error *err)
{
    memset(h, 0, sizeof *h);
    int W = img->width, H = img->height;
    if (W < 3 || H < 3)
        return aa_error_set(err, AA_EINVAL, "", "the image must be at least 3 x 3");
    h->width = W;
    h->height = H;
    size_t n = (size_t)W * H;
    double *smooth = malloc(n * sizeof *smooth), *tmp = malloc(n * sizeof *tmp);
    if (!smooth || !tmp) {
        free(smooth);
        free(tmp);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    /* Central differences of a sharp step are biased towards the diagonals; the direction is
     * taken from the blurred image, the magnitude from the image itself. */
    blur(img, smooth, tmp);
    for (int j = 1; j < H - 1; j++)
        for (int i = 1; i < W - 1; i++) {
            size_t at = (size_t)j * W + i;
            const float *c = &img->px[at];
            double gx = (c[1] - c[-1]) / 2.0, gy = (c[W] - c[-W]) / 2.0, m = hypot(gx, gy);
            double sx = (smooth[at + 1] - smooth[at - 1]) / 2.0;
            double sy = (smooth[at + W] - smooth[at - W]) / 2.0;
            if (m > 0 && (sx != 0 || sy != 0))
                add_angle(h, sx, sy, m);
        }
    free(smooth);
    free(tmp);
    return AA_OK;
}

bool aa_scene_below_pixel(const aa_scene *s, double x, double y)
{
    if (s->p.mirror_x)
        x = s->p.width - x;
    if (s->p.mirror_y)
        y = s->p.height - y;
    if (s->p.shape == AA_SCENE_SIEMENS_STAR)
        return hypot(x - s->cx, y - s->cy) < fmin(AA_EDGE_SUBPIXEL_SPACING / s->sector, s->radius);
    if (s->p.shape == AA_SCENE_CHECKERBOARD && y > s->horizon_y) {
        double s1, s2;
        board_spacings(s, x, y, &s1, &s2);
        return fmin(s1, s2) < AA_EDGE_SUBPIXEL_SPACING;
    }
    return false;
}

double aa_subpixel_error_share(const aa_scene *s, const aa_image *approx, const aa_image *ref)
{
    int W = s->p.width, H = s->p.height;
    if (approx->width != W || approx->height != H || ref->width != W || ref->height != H)
        return NAN;
    double all = 0, below = 0;
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            double d = (double)approx->px[(size_t)j * W + i] - ref->px[(size_t)j * W + i];
            all += d * d;
            if (d != 0 && aa_scene_below_pixel(s, i + 0.5, j + 0.5))
                below += d * d;
        }
    return all > 0 ? below / all : NAN;
}
