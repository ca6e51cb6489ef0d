/* The edge model's prediction (predict.h). */
#include "predict.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "aa_metric.h"
#include "raster.h"

#define PI 3.14159265358979323846

/* Error of one kernel's step response at edge offset a (projections p[], weights). */
static double step_error(const aa_filter *f, const aa_kernel *k, bool horizontal, double a)
{
    double sum = 0;
    for (size_t n = 0; n < k->count; n++) {
        double p = horizontal ? k->samples[n].y : k->samples[n].x;
        if (p <= a)
            sum += k->samples[n].w;
    }
    return sum - aa_filter_cdf(f, a);
}

/* Largest |projection| of any sample on either axis: the footprint's half-width. */
static double kernel_reach(const aa_pattern *p)
{
    double reach = 0;
    for (size_t k = 0; k < p->kernel_count; k++)
        for (size_t n = 0; n < p->kernels[k].count; n++)
            reach = fmax(reach,
                         fmax(fabs(p->kernels[k].samples[n].x), fabs(p->kernels[k].samples[n].y)));
    return reach;
}

/* Summed squared error per unit length of an axis-aligned edge at pixel coordinate c: the
 * columns (rows) the footprint reaches, averaged over the kernels along the edge. */
static double locked_per_length(const aa_pattern *p, const aa_filter *f, const aa_locked_edge *e,
                                int across_size, double reach)
{
    double off = aa_output_offset(p->kernel_size), c = e->position, sum = 0;
    int i0 = (int)fmax(0, floor(c - off - reach - f->radius) - 1);
    int i1 = (int)fmin(across_size - 1, ceil(c - off + reach + f->radius) + 1);
    int T = p->tile;
    for (int i = i0; i <= i1; i++) {
        double a = c - (i + off), s = 0;
        if (T > 0) {
            /* Kernel (i mod T, r) for a vertical edge, (r, i mod T) for a horizontal one. */
            for (int r = 0; r < T; r++) {
                size_t k = e->horizontal ? (size_t)(i % T) * T + r : (size_t)r * T + (i % T);
                double d = step_error(f, &p->kernels[k], e->horizontal, a);
                s += d * d;
            }
            s /= T;
        } else {
            for (size_t k = 0; k < p->kernel_count; k++) {
                double d = step_error(f, &p->kernels[k], e->horizontal, a);
                s += d * d;
            }
            s /= (double)p->kernel_count;
        }
        sum += s;
    }
    return sum;
}

int aa_predict_rmse(const aa_pattern *p, const aa_filter *f, const aa_edge_histogram *h,
                    aa_prediction *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    if (!p || p->kernel_count == 0 || (p->tile > 0 && p->kernel_count != (size_t)p->tile * p->tile))
        return aa_error_set(err, AA_EINVAL, "pattern", "pattern has no usable kernels");
    aa_filter fd;
    if (!f) {
        aa_filter_default(&fd);
        f = &fd;
    }
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    /* E1 wherever the scene has edges, locked ones included (their bins report it too). */
    bool needed[AA_EDGE_BINS];
    for (int d = 0; d < AA_EDGE_BINS; d++)
        needed[d] = h->length[d] > 0;
    for (size_t k = 0; k < h->locked_count; k++)
        needed[h->locked[k].horizontal ? 90 : 0] = true;
    int rc = AA_OK;
    for (int d = 0; d < AA_EDGE_BINS && !rc; d++) {
        if (!needed[d])
            continue;
        double mean_sq = 0;
        for (size_t k = 0; k < p->kernel_count && !rc; k++) {
            double e1 = 0;
            rc = aa_e1_at_angle(f, p->kernels[k].samples, p->kernels[k].count, d * PI / 180.0, &ws,
                                &e1);
            mean_sq += e1 * e1;
        }
        mean_sq /= (double)p->kernel_count;
        out->e1_rms[d] = sqrt(mean_sq);
        out->bin_sq[d] = h->length[d] * mean_sq;
    }
    aa_metric_workspace_free(&ws);
    if (rc)
        return aa_error_set(err, rc, "pattern", "E1 evaluation failed");
    double reach = kernel_reach(p);
    for (size_t k = 0; k < h->locked_count; k++) {
        const aa_locked_edge *e = &h->locked[k];
        double part =
            e->length * locked_per_length(p, f, e, e->horizontal ? h->height : h->width, reach);
        out->bin_sq[e->horizontal ? 90 : 0] += part;
        out->locked_sq += part;
    }
    for (int d = 0; d < AA_EDGE_BINS; d++)
        out->sum_sq += out->bin_sq[d];
    out->pixels = (size_t)h->width * (size_t)h->height;
    out->rmse = 255.0 * sqrt(out->sum_sq / (double)out->pixels);
    out->subpixel_area_share = h->subpixel_area / (double)out->pixels;
    return AA_OK;
}
