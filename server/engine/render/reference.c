/* Sparse jittered supersampling with the reference filter (reference.h). */
#include "reference.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raster_traverse.h"

aa_reference_params aa_reference_params_default(void)
{
    aa_reference_params p = {1024, 1, NULL, true, NULL, NULL};
    return p;
}

static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double uniform01(uint64_t *state)
{
    return (double)(splitmix64(state) >> 11) * (1.0 / 9007199254740992.0);
}

static uint64_t pixel_seed(uint64_t seed, int px, int py)
{
    uint64_t st = seed ^ 0x5851F42D4C957F2Dull;
    uint64_t h = splitmix64(&st);
    st = h ^ ((uint64_t)(uint32_t)px << 32 | (uint32_t)py);
    return splitmix64(&st);
}

/* The 1-D filter: the Mitchell-Netravali cubic directly (hot loop), other kinds through
 * aa_filter_eval, both scaled to unit integral (the estimator is not renormalised). */
typedef struct filter_1d {
    const aa_filter *f;   /* NULL: the Mitchell-Netravali fast path below */
    double B, C, to_unit; /* Mitchell: t = |x| * to_unit in [0, 2) */
    double norm;          /* factor for unit integral */
} filter_1d;

static double filter_h(const filter_1d *f, double x)
{
    if (!f->f) {
        double t = fabs(x) * f->to_unit, B = f->B, C = f->C;
        if (t >= 2)
            return 0;
        if (t < 1)
            return f->norm *
                   ((12 - 9 * B - 6 * C) * t * t * t + (-18 + 12 * B + 6 * C) * t * t +
                    (6 - 2 * B)) /
                   6;
        return f->norm *
               ((-B - 6 * C) * t * t * t + (6 * B + 30 * C) * t * t + (-12 * B - 48 * C) * t +
                (8 * B + 24 * C)) /
               6;
    }
    return f->norm * aa_filter_eval(f->f, x);
}

/* 1 / integral of aa_filter_eval over [-R, R] (composite Simpson, 4096 intervals), so that
 * the sampled part of the estimator matches the exact CDF part whatever scale the filter's
 * impulse response is stored with. */
static double impulse_norm(const aa_filter *f)
{
    const int n = 4096;
    double R = f->radius, h = 2 * R / n, sum = 0;
    for (int k = 0; k <= n; k++) {
        double w = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
        sum += w * aa_filter_eval(f, -R + k * h);
    }
    sum *= h / 3;
    return sum > 0 ? 1.0 / sum : 1.0;
}

typedef struct accumulator {
    aa_rect reg;
    size_t rw;
    const uint8_t *mask;
    double *num;
    const aa_filter *cdf;
    double off, R;
} accumulator;

/* An input pixel the scene is constant on adds v times the exact filter mass over it. */
static void add_uniform_pixel(accumulator *acc, int px, int py, double v)
{
    double wx[20], wy[20];
    int i0 = (int)floor(px - acc->off - acc->R) + 1, i1 = (int)ceil(px + 1 - acc->off + acc->R) - 1;
    int j0 = (int)floor(py - acc->off - acc->R) + 1, j1 = (int)ceil(py + 1 - acc->off + acc->R) - 1;
    if (i0 < acc->reg.x0)
        i0 = acc->reg.x0;
    if (i1 > acc->reg.x1 - 1)
        i1 = acc->reg.x1 - 1;
    if (j0 < acc->reg.y0)
        j0 = acc->reg.y0;
    if (j1 > acc->reg.y1 - 1)
        j1 = acc->reg.y1 - 1;
    if (i0 > i1 || j0 > j1 || v == 0)
        return;
    for (int i = i0; i <= i1; i++)
        wx[i - i0] = aa_filter_cdf(acc->cdf, px + 1 - (i + acc->off)) -
                     aa_filter_cdf(acc->cdf, px - (i + acc->off));
    for (int j = j0; j <= j1; j++)
        wy[j - j0] = aa_filter_cdf(acc->cdf, py + 1 - (j + acc->off)) -
                     aa_filter_cdf(acc->cdf, py - (j + acc->off));
    for (int j = j0; j <= j1; j++) {
        size_t row = (size_t)(j - acc->reg.y0) * acc->rw;
        for (int i = i0; i <= i1; i++)
            if (acc->mask[row + (size_t)(i - acc->reg.x0)])
                acc->num[row + (size_t)(i - acc->reg.x0)] += v * wx[i - i0] * wy[j - j0];
    }
}

/* spp jittered samples of one input pixel, each weighted h(dx) h(dy) / spp. */
static void add_sampled_pixel(accumulator *acc, const aa_scene *s, const filter_1d *h, int m,
                              uint64_t seed, int px, int py)
{
    double hx[20], hy[20], inv = 1.0 / ((double)m * m), off = acc->off, R = acc->R;
    const aa_rect reg = acc->reg;
    uint64_t rng = pixel_seed(seed, px, py);
    for (int b = 0; b < m; b++) {
        for (int a = 0; a < m; a++) {
            double sx = px + (a + uniform01(&rng)) / m;
            double sy = py + (b + uniform01(&rng)) / m;
            double v = aa_scene_value(s, sx, sy) * inv;
            if (v == 0)
                continue;
            /* Output pixels with |s - o| < R. */
            int i0 = (int)floor(sx - off - R) + 1, i1 = (int)ceil(sx - off + R) - 1;
            int j0 = (int)floor(sy - off - R) + 1, j1 = (int)ceil(sy - off + R) - 1;
            if (i0 < reg.x0)
                i0 = reg.x0;
            if (i1 > reg.x1 - 1)
                i1 = reg.x1 - 1;
            if (j0 < reg.y0)
                j0 = reg.y0;
            if (j1 > reg.y1 - 1)
                j1 = reg.y1 - 1;
            if (i0 > i1 || j0 > j1)
                continue;
            for (int i = i0; i <= i1; i++)
                hx[i - i0] = filter_h(h, sx - (i + off));
            for (int j = j0; j <= j1; j++)
                hy[j - j0] = v * filter_h(h, sy - (j + off));
            for (int j = j0; j <= j1; j++) {
                size_t row = (size_t)(j - reg.y0) * acc->rw;
                for (int i = i0; i <= i1; i++) {
                    size_t k = row + (size_t)(i - reg.x0);
                    if (acc->mask[k])
                        acc->num[k] += hx[i - i0] * hy[j - j0];
                }
            }
        }
    }
}

int aa_render_reference(const aa_scene *s, const aa_reference_params *rp, double off, aa_image *out,
                        const aa_rect *region, aa_reference_stats *st, aa_error *err)
{
    aa_reference_stats local;
    if (!st)
        st = &local;
    memset(st, 0, sizeof *st);
    aa_reference_params defaults = aa_reference_params_default();
    if (!rp)
        rp = &defaults;
    int m = (int)lround(sqrt((double)rp->spp));
    if (rp->spp < 1 || rp->spp > AA_REFERENCE_MAX_SPP || m * m != rp->spp)
        return aa_error_set(err, AA_EINVAL, "spp",
                            "spp must be a square in 1..%d (16, 64, 256, "
                            "1024, 4096)",
                            AA_REFERENCE_MAX_SPP);
    if (out->width != s->p.width || out->height != s->p.height)
        return aa_error_set(err, AA_EINVAL, "", "image and scene sizes differ");
    aa_filter fdef;
    const aa_filter *f = rp->filter;
    if (!f) {
        aa_filter_default(&fdef);
        f = &fdef;
    }
    double R = f->radius;
    if (!(R > 0 && R <= 8))
        return aa_error_set(err, AA_EINVAL, "filter", "reference filter radius must be in (0, 8]");
    filter_1d h = {f, 0, 0, 0, 1};
    if (f->formula != AA_FILTER_MITCHELL)
        h.norm = impulse_norm(f);
    if (f->formula == AA_FILTER_MITCHELL) {
        /* The classic cubic has support 2 and unit integral; scale it to the radius. */
        h.f = NULL;
        h.B = f->B;
        h.C = f->C;
        h.to_unit = 2.0 / R;
        h.norm = 2.0 / R;
    }
    aa_rect reg = aa_image_rect(out);
    if (region)
        reg = aa_rect_intersect(reg, *region);
    size_t area = aa_rect_area(reg);
    st->pixels = area;
    if (area == 0)
        return AA_OK;

    /* Input pixels [ix0, ix1) x [iy0, iy1) cover every footprint of the region. */
    int pad = (int)ceil(R) + 1;
    int ix0 = reg.x0 - pad, iy0 = reg.y0 - pad, ix1 = reg.x1 + pad, iy1 = reg.y1 + pad;
    size_t iw = (size_t)(ix1 - ix0), ih = (size_t)(iy1 - iy0);
    accumulator acc = {reg, (size_t)(reg.x1 - reg.x0), NULL, NULL, f, off, R};
    uint8_t *mask = malloc(area), *need = calloc(iw * ih, 1);
    acc.num = calloc(area, sizeof *acc.num);
    int rc = AA_OK;
    if (!mask || !need || !acc.num) {
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
        goto done;
    }
    acc.mask = mask;
    st->pixels_supersampled = aa_traverse_footprints(s, reg, off, R, rp->skip, out, mask);
    if (st->pixels_supersampled == 0)
        goto done;
    /* Mark the input pixels that meet the open footprint (o - R, o + R)^2 of a marked pixel. */
    for (int j = reg.y0; j < reg.y1; j++) {
        for (int i = reg.x0; i < reg.x1; i++) {
            if (!mask[(size_t)(j - reg.y0) * acc.rw + (size_t)(i - reg.x0)])
                continue;
            int px0 = (int)floor(i + off - R), px1 = (int)ceil(i + off + R);
            int py0 = (int)floor(j + off - R), py1 = (int)ceil(j + off + R);
            for (int py = py0; py < py1; py++)
                memset(need + (size_t)(py - iy0) * iw + (size_t)(px0 - ix0), 1,
                       (size_t)(px1 - px0));
        }
    }
    unsigned since_check = 0;
    for (int py = iy0; py < iy1; py++) {
        if (rp->progress && rp->progress(rp->user, (double)(py - iy0) / (double)ih)) {
            rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
            goto done;
        }
        for (int px = ix0; px < ix1; px++) {
            if (!need[(size_t)(py - iy0) * iw + (size_t)(px - ix0)])
                continue;
            double v;
            if (rp->skip && aa_scene_box_uniform(s, px, py, px + 1, py + 1, &v)) {
                add_uniform_pixel(&acc, px, py, v);
                continue;
            }
            /* Also every 16 supersampled pixels: a row of a wide tile at a high spp can take
             * seconds, and a time budget checked per row overran by that much. */
            if (rp->progress && ++since_check == 16) {
                since_check = 0;
                if (rp->progress(rp->user, ((double)(py - iy0) + (double)(px - ix0) / (double)iw) /
                                               (double)ih)) {
                    rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
                    goto done;
                }
            }
            add_sampled_pixel(&acc, s, &h, m, rp->seed, px, py);
            st->input_pixels++;
            st->samples += (size_t)rp->spp;
        }
    }
    for (int j = reg.y0; j < reg.y1; j++)
        for (int i = reg.x0; i < reg.x1; i++) {
            size_t k = (size_t)(j - reg.y0) * acc.rw + (size_t)(i - reg.x0);
            if (mask[k])
                out->px[(size_t)j * out->width + i] = (float)acc.num[k];
        }
done:
    free(mask);
    free(need);
    free(acc.num);
    return rc;
}
