/* The edge model's prediction (predict.h). */
#include "predict.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "aa_core.h"
#include "aa_metric.h"
#include "edge_profile.h"
#include "raster.h"

#define PI 3.14159265358979323846

/* The render's reference at a pixel whose output point is at offset a from a straight edge with
 * unit normal (c, s) is g_θ(a) (edge_profile.h): for an axis-aligned edge g(a), the profile E1
 * compares against; at other angles not (docs/predict.md). */
/* Error of one kernel at edge offset a: its step response (projections on the normal (nx, ny))
 * minus the reference's, ref. */
static double step_error(const aa_kernel *k, double nx, double ny, double a, double ref)
{
    double sum = 0;
    for (size_t n = 0; n < k->count; n++)
        if (nx * k->samples[n].x + ny * k->samples[n].y <= a)
            sum += k->samples[n].w;
    return sum - ref;
}

/* Largest distance of any sample from its output point: the footprint's half-width. */
static double kernel_reach(const aa_pattern *p)
{
    double reach = 0;
    for (size_t k = 0; k < p->kernel_count; k++)
        for (size_t n = 0; n < p->kernels[k].count; n++)
            reach = fmax(reach, hypot(p->kernels[k].samples[n].x, p->kernels[k].samples[n].y));
    return reach;
}

static long long floor_mod(long long v, long long m)
{
    long long r = v % m;
    return r < 0 ? r + m : r;
}

/* Squared error of output point (i, j) at offset a from the edge: its tile's kernel, or the
 * mean over the kernels of a pattern without a tile. */
static double pixel_sq_error(const aa_pattern *p, int T, long long i, long long j, double nx,
                             double ny, double a, double ref)
{
    if (p->tile > 0) {
        size_t k = (size_t)(floor_mod(j, T) * T + floor_mod(i, T));
        double err = step_error(&p->kernels[k], nx, ny, a, ref);
        return err * err;
    }
    double s = 0;
    for (size_t k = 0; k < p->kernel_count; k++) {
        double err = step_error(&p->kernels[k], nx, ny, a, ref);
        s += err * err;
    }
    return s / (double)p->kernel_count;
}

/* Summed squared error per unit length of the locked line p x + q y = c. The output points
 * (i + off, j + off) meet it at offsets a = (c - p x - q y) / |(p, q)| and along-line integer
 * coordinates m = p j - q i; the lattice step T (-q, p) (T the tile, keeping every pixel's
 * kernel) advances m by T (p² + q²) and the along-line position by T |(p, q)|. So one period is
 * the pixels with m in [m0, m0 + T (p² + q²)), exactly, and the sum over it divided by
 * T |(p, q)| is the sum per unit length. */
static double locked_per_length(const aa_pattern *p, const aa_filter *f, const aa_locked_edge *e,
                                double reach)
{
    double norm = hypot(e->p, e->q), nx = e->p / norm, ny = e->q / norm, d = e->c / norm;
    int T = p->tile > 0 ? p->tile : 1;
    long long span = (long long)T * (e->p * e->p + e->q * e->q);
    double period = T * norm, off = aa_output_offset(p->kernel_size);
    double band = reach + f->radius + 1;
    /* The period's parallelogram: from the foot of the perpendicular b along t = (-ny, nx). */
    double bx = nx * d, by = ny * d, tx = -ny, ty = nx;
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int cs = 0; cs < 2; cs++)
        for (int ca = -1; ca <= 1; ca += 2) {
            double x = bx + tx * (cs ? period + 1 : -1) + nx * ca * band;
            double y = by + ty * (cs ? period + 1 : -1) + ny * ca * band;
            x0 = fmin(x0, x);
            x1 = fmax(x1, x);
            y0 = fmin(y0, y);
            y1 = fmax(y1, y);
        }
    long long i0 = (long long)floor(x0 - off) - 1, i1 = (long long)ceil(x1 - off) + 1;
    long long j0 = (long long)floor(y0 - off) - 1, j1 = (long long)ceil(y1 - off) + 1;
    /* m0: the along-line coordinate of the base point, rounded down. */
    long long m0 = (long long)floor(e->p * (by - off) - e->q * (bx - off));
    double sum = 0;
    for (long long j = j0; j <= j1; j++)
        for (long long i = i0; i <= i1; i++) {
            long long m = (long long)e->p * j - (long long)e->q * i;
            if (m < m0 || m >= m0 + span)
                continue;
            double a = d - (nx * (i + off) + ny * (j + off));
            if (fabs(a) > band)
                continue;
            sum += pixel_sq_error(p, T, i, j, nx, ny, a, aa_edge_profile_exact(f, nx, ny, a));
        }
    return sum / period;
}

/* Summed squared error of the segment g's pixels (contrast² included): the output points of
 * the width x height image whose foot on g's line falls within the segment (or beyond an end
 * the image border cut, where the line goes on) and whose footprint reaches the line, each with
 * its tile's kernel, against the reference's g_θ (prof, at the segment's angle). */
static double segment_sum(const aa_pattern *p, const aa_edge_profile *prof,
                          const aa_edge_segment *g, int width, int height, double reach)
{
    double dx = g->x1 - g->x0, dy = g->y1 - g->y0, len = hypot(dx, dy);
    if (!(len > 0))
        return 0;
    double tx = dx / len, ty = dy / len, nx = -ty, ny = tx, d = nx * g->x0 + ny * g->y0;
    double band = reach + prof->reach + 1, off = aa_output_offset(p->kernel_size);
    double t0 = g->open0 ? -INFINITY : 0, t1 = g->open1 ? INFINITY : len;
    int i0 = (int)fmax(0, floor(fmin(g->x0, g->x1) - band - off));
    int i1 = (int)fmin(width - 1, ceil(fmax(g->x0, g->x1) + band - off));
    int j0 = (int)fmax(0, floor(fmin(g->y0, g->y1) - band - off));
    int j1 = (int)fmin(height - 1, ceil(fmax(g->y0, g->y1) + band - off));
    int T = p->tile > 0 ? p->tile : 1;
    double sum = 0;
    for (int j = j0; j <= j1; j++)
        for (int i = i0; i <= i1; i++) {
            double ox = i + off, oy = j + off, a = d - (nx * ox + ny * oy);
            double t = tx * (ox - g->x0) + ty * (oy - g->y0);
            if (fabs(a) > band || t < t0 || t >= t1)
                continue;
            sum += pixel_sq_error(p, T, i, j, nx, ny, a, aa_edge_profile_eval(prof, a));
        }
    return sum * g->length / len;
}

/* The bin of a segment's normal (−dy, dx). */
static int segment_bin(const aa_edge_segment *g)
{
    return aa_edge_bin(atan2(g->x1 - g->x0, -(g->y1 - g->y0)) * 180 / PI);
}

/* f, or the default filter in *fd when f is NULL. */
static const aa_filter *filter_or_default(const aa_filter *f, aa_filter *fd)
{
    if (f)
        return f;
    aa_filter_default(fd);
    return fd;
}

#define PROFILE_BINS 46

/* The profile bin 0..45 sharing bin d's g_θ (it depends on |cos θ| and |sin θ| only). */
static int profile_bin(int d)
{
    d %= 180;
    if (d > 90)
        d = 180 - d;
    return d > 45 ? 90 - d : d;
}

/* The g_θ tables: one per distinct bin profile, one per kept segment (at its exact angle). */
struct aa_predict_tables {
    bool built[PROFILE_BINS];
    aa_edge_profile bin[PROFILE_BINS];
    size_t segment_count;
    aa_edge_profile segment[AA_EDGE_MAX_SEGMENTS];
};

/* Marks the profile bins (0..45) the tables need: where want[d] (NULL: where h has length),
 * and the bins of h's locked edges. Returns how many. */
static size_t needed_profile_bins(const aa_edge_histogram *h, const bool *want,
                                  bool need[PROFILE_BINS])
{
    memset(need, 0, PROFILE_BINS * sizeof need[0]);
    for (int d = 0; d < AA_EDGE_BINS; d++)
        if (want ? want[d] : !h || h->length[d] > 0)
            need[profile_bin(d)] = true;
    for (size_t k = 0; h && k < h->locked_count; k++)
        need[profile_bin(aa_locked_edge_bin(&h->locked[k]))] = true;
    size_t n = 0;
    for (int b = 0; b < PROFILE_BINS; b++)
        n += need[b];
    return n;
}

size_t aa_predict_tables_count(const aa_edge_histogram *h, const bool *want)
{
    bool need[PROFILE_BINS];
    return needed_profile_bins(h, want, need) + (h ? h->segment_count : 0);
}

int aa_predict_tables_new(const aa_filter *f, const aa_edge_histogram *h, const bool *want,
                          aa_predict_tables **out, aa_error *err)
{
    *out = NULL;
    aa_filter fd;
    f = filter_or_default(f, &fd);
    aa_predict_tables *t = calloc(1, sizeof *t);
    if (!t)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    needed_profile_bins(h, want, t->built);
    for (int b = 0; b < PROFILE_BINS; b++)
        if (t->built[b])
            aa_edge_profile_init(&t->bin[b], f, b * PI / 180.0);
    for (size_t k = 0; h && k < h->segment_count; k++) {
        const aa_edge_segment *g = &h->segment[k];
        aa_edge_profile_init(&t->segment[k], f, atan2(g->x1 - g->x0, -(g->y1 - g->y0)));
    }
    t->segment_count = h ? h->segment_count : 0;
    *out = t;
    return AA_OK;
}

void aa_predict_tables_free(aa_predict_tables *t)
{
    free(t);
}

/* mean_k E1_k(θ_d)² at the bins d where want[d] (every bin when want is NULL), 0 elsewhere, E1
 * measured against g, or against g_θ from the tables t when not NULL. */
static int e1_mean_sq(const aa_pattern *p, const aa_filter *f, const bool *want,
                      const aa_predict_tables *tables, double mean_sq[AA_EDGE_BINS], aa_error *err)
{
    memset(mean_sq, 0, AA_EDGE_BINS * sizeof mean_sq[0]);
    for (int d = 0; tables && d < AA_EDGE_BINS; d++)
        if ((!want || want[d]) && !tables->built[profile_bin(d)])
            return aa_error_set(err, AA_EINVAL, "tables", "no g_theta table for bin %d", d);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    /* Directions once; each kernel then runs through the bins in order, so its sort starts from
     * the previous bin's order (as aa_evaluate). */
    double dir_c[AA_EDGE_BINS], dir_s[AA_EDGE_BINS];
    for (int d = 0; d < AA_EDGE_BINS; d++)
        aa_metric_direction(d * PI / 180.0, &dir_c[d], &dir_s[d]);
    int rc = AA_OK;
    for (size_t k = 0; k < p->kernel_count && !rc; k++) {
        for (int d = 0; d < AA_EDGE_BINS && !rc; d++) {
            if (want && !want[d])
                continue;
            double e1 = 0;
            if (tables)
                rc = aa_edge_profile_e1(&tables->bin[profile_bin(d)], p->kernels[k].samples,
                                        p->kernels[k].count, dir_c[d], dir_s[d], &e1);
            else
                rc = aa_e1_at_direction(f, p->kernels[k].samples, p->kernels[k].count, dir_c[d],
                                        dir_s[d], AA_E1_AUTO, &ws, &e1);
            mean_sq[d] += e1 * e1;
        }
    }
    aa_metric_workspace_free(&ws);
    if (rc)
        return aa_error_set(err, rc, "pattern", "E1 evaluation failed");
    for (int d = 0; d < AA_EDGE_BINS; d++)
        mean_sq[d] /= (double)p->kernel_count;
    return AA_OK;
}

int aa_predict_e1_rms(const aa_pattern *p, const aa_filter *f, const bool *want,
                      double e1_rms[AA_EDGE_BINS], aa_error *err)
{
    return aa_predict_e1_rms_with(p, f, want, 0, e1_rms, err);
}

int aa_predict_e1_rms_with(const aa_pattern *p, const aa_filter *f, const bool *want,
                           unsigned model, double e1_rms[AA_EDGE_BINS], aa_error *err)
{
    return aa_predict_e1_rms_tables(p, f, want, model, NULL, e1_rms, err);
}

int aa_predict_e1_rms_tables(const aa_pattern *p, const aa_filter *f, const bool *want,
                             unsigned model, const aa_predict_tables *tables,
                             double e1_rms[AA_EDGE_BINS], aa_error *err)
{
    memset(e1_rms, 0, AA_EDGE_BINS * sizeof e1_rms[0]);
    if (!p || p->kernel_count == 0)
        return aa_error_set(err, AA_EINVAL, "pattern", "pattern has no usable kernels");
    aa_filter fd;
    f = filter_or_default(f, &fd);
    aa_predict_tables *own = NULL;
    int rc = model & AA_PREDICT_REFERENCE_PROFILE && !tables
                 ? aa_predict_tables_new(f, NULL, want, &own, err)
                 : AA_OK;
    if (own)
        tables = own;
    double mean_sq[AA_EDGE_BINS];
    if (!rc)
        rc = e1_mean_sq(p, f, want, model & AA_PREDICT_REFERENCE_PROFILE ? tables : NULL, mean_sq,
                        err);
    for (int d = 0; d < AA_EDGE_BINS && !rc; d++)
        e1_rms[d] = sqrt(mean_sq[d]);
    aa_predict_tables_free(own);
    return rc;
}

int aa_predict_rmse(const aa_pattern *p, const aa_filter *f, const aa_edge_histogram *h,
                    aa_prediction *out, aa_error *err)
{
    return aa_predict_rmse_tables(p, f, h, 0, NULL, out, err);
}

int aa_predict_rmse_with(const aa_pattern *p, const aa_filter *f, const aa_edge_histogram *h,
                         unsigned model, aa_prediction *out, aa_error *err)
{
    return aa_predict_rmse_tables(p, f, h, model, NULL, out, err);
}

int aa_predict_rmse_tables(const aa_pattern *p, const aa_filter *f, const aa_edge_histogram *h,
                           unsigned model, const aa_predict_tables *tables, aa_prediction *out,
                           aa_error *err)
{
    memset(out, 0, sizeof *out);
    if (!p || p->kernel_count == 0 || (p->tile > 0 && p->kernel_count != (size_t)p->tile * p->tile))
        return aa_error_set(err, AA_EINVAL, "pattern", "pattern has no usable kernels");
    aa_filter fd;
    f = filter_or_default(f, &fd);
    aa_predict_tables *own = NULL;
    if (model && !tables) {
        int rc = aa_predict_tables_new(f, h, NULL, &own, err);
        if (rc)
            return rc;
        tables = own;
    }
    if (model & AA_PREDICT_SEGMENT_SUMS && tables->segment_count != h->segment_count) {
        aa_predict_tables_free(own);
        return aa_error_set(err, AA_EINVAL, "tables", "tables made for another histogram");
    }
    /* E1 wherever the scene has edges, locked ones included (their bins report it too). */
    bool needed[AA_EDGE_BINS];
    for (int d = 0; d < AA_EDGE_BINS; d++)
        needed[d] = h->length[d] > 0;
    for (size_t k = 0; k < h->locked_count; k++)
        needed[aa_locked_edge_bin(&h->locked[k])] = true;
    double mean_sq[AA_EDGE_BINS];
    int rc = e1_mean_sq(p, f, needed, model & AA_PREDICT_REFERENCE_PROFILE ? tables : NULL, mean_sq,
                        err);
    if (rc) {
        aa_predict_tables_free(own);
        return rc;
    }
    for (int d = 0; d < AA_EDGE_BINS; d++) {
        out->e1_rms[d] = sqrt(mean_sq[d]);
        out->bin_sq[d] = h->length[d] * mean_sq[d];
    }
    double reach = kernel_reach(p);
    if (model & AA_PREDICT_SEGMENT_SUMS && h->segment_count > 0) {
        /* The segments' lengths leave their bins (other edges of a bin stay) for exact sums. */
        double kept[AA_EDGE_BINS];
        memcpy(kept, h->length, sizeof kept);
        for (size_t k = 0; k < h->segment_count; k++)
            kept[segment_bin(&h->segment[k])] -= h->segment[k].length;
        for (int d = 0; d < AA_EDGE_BINS; d++)
            out->bin_sq[d] = fmax(0, kept[d]) * mean_sq[d];
        for (size_t k = 0; k < h->segment_count; k++) {
            double part =
                segment_sum(p, &tables->segment[k], &h->segment[k], h->width, h->height, reach);
            out->bin_sq[segment_bin(&h->segment[k])] += part;
            out->segment_sq += part;
        }
    }
    aa_predict_tables_free(own);
    for (size_t k = 0; k < h->locked_count; k++) {
        const aa_locked_edge *e = &h->locked[k];
        double part = e->length * locked_per_length(p, f, e, reach);
        out->bin_sq[aa_locked_edge_bin(e)] += part;
        out->locked_sq += part;
    }
    for (int d = 0; d < AA_EDGE_BINS; d++)
        out->sum_sq += out->bin_sq[d];
    out->pixels = (size_t)h->width * (size_t)h->height;
    out->rmse = 255.0 * sqrt(out->sum_sq / (double)out->pixels);
    out->subpixel_area_share = h->subpixel_area / (double)out->pixels;
    return AA_OK;
}

/* Rank of v[i] among v[0..n): 1 + the number below it + half the others equal to it. */
static double rank_of(const double *v, size_t n, size_t i)
{
    double below = 0, equal = 0;
    for (size_t j = 0; j < n; j++) {
        below += v[j] < v[i];
        equal += v[j] == v[i] && j != i;
    }
    return 1 + below + equal / 2;
}

double aa_spearman(const double *a, const double *b, size_t n)
{
    if (n < 2)
        return NAN;
    double mean = (n + 1) / 2.0, cov = 0, va = 0, vb = 0;
    for (size_t i = 0; i < n; i++) {
        double ra = rank_of(a, n, i) - mean, rb = rank_of(b, n, i) - mean;
        cov += ra * rb;
        va += ra * ra;
        vb += rb * rb;
    }
    return va > 0 && vb > 0 ? cov / sqrt(va * vb) : NAN;
}
