/* Pattern rasterisation with shared global samples (raster.h). */
#include "raster.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "raster_traverse.h"

#define AA_RASTER_MAX_CACHE (1 << 26) /* coverage cache entries (256 MiB of floats) */

double aa_output_offset(int kernel_size)
{
    return kernel_size / 2.0 - (kernel_size - 1) / 2;
}

/* Largest |x|, |y| of any kernel sample: half the side of the kernel footprint box. */
static double kernel_extent(const aa_pattern *p)
{
    double e = 0;
    for (size_t k = 0; k < p->kernel_count; k++)
        for (size_t n = 0; n < p->kernels[k].count; n++)
            e = fmax(e, fmax(fabs(p->kernels[k].samples[n].x), fabs(p->kernels[k].samples[n].y)));
    return e;
}

static int floor_div(int a, int b)
{
    assert(b > 0); /* a tile size */
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}

/* Kernels read global samples through a per-sample tile-cell offset (da, db) relative to the
 * output pixel's cell. */
typedef struct shared_render {
    const aa_scene *scene;
    const aa_pattern *p;
    int T;
    int *da, *db;  /* [total kernel samples], kernel-major */
    size_t *first; /* [kernel_count]: index of each kernel's first sample in da/db */
    int cx0, cy0, ncx, ncy;
    float *cache; /* [ncy][ncx][tile_count], NaN = not evaluated */
    size_t evaluated;
} shared_render;

static double shared_pixel(shared_render *r, int i, int j)
{
    int T = r->T, ci = floor_div(i, T), cj = floor_div(j, T);
    size_t k = (size_t)(j - cj * T) * T + (size_t)(i - ci * T);
    assert(k < r->p->kernel_count); /* a tile pattern has T*T kernels, one per tile pixel */
    const aa_kernel *ker = &r->p->kernels[k];
    double sum = 0;
    for (size_t n = 0; n < ker->count; n++) {
        size_t t = ker->tile_index[n];
        int a = ci + r->da[r->first[k] + n], b = cj + r->db[r->first[k] + n];
        /* render_shared sized the cache to the cells every pixel of the region reads */
        assert(!r->cache ||
               (a >= r->cx0 && a < r->cx0 + r->ncx && b >= r->cy0 && b < r->cy0 + r->ncy));
        size_t idx = ((size_t)(b - r->cy0) * r->ncx + (size_t)(a - r->cx0)) * r->p->tile_count + t;
        float v = r->cache ? r->cache[idx] : NAN;
        if (isnan(v)) {
            v = (float)aa_scene_value(r->scene, r->p->tile_samples[t].x + (double)T * a,
                                      r->p->tile_samples[t].y + (double)T * b);
            if (r->cache)
                r->cache[idx] = v;
            r->evaluated++;
        }
        sum += ker->samples[n].w * v;
    }
    return sum;
}

static int render_shared(const aa_scene *s, const aa_pattern *p, aa_image *out, aa_rect reg,
                         const uint8_t *mask, aa_raster_stats *st, aa_error *err)
{
    shared_render r = {s, p, p->tile, NULL, NULL, NULL, 0, 0, 0, 0, NULL, 0};
    size_t total = aa_pattern_total_kernel_samples(p);
    r.da = malloc((total ? total : 1) * sizeof *r.da);
    r.db = malloc((total ? total : 1) * sizeof *r.db);
    r.first = malloc(p->kernel_count * sizeof *r.first);
    int rc = AA_OK;
    if (!r.da || !r.db || !r.first) {
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
        goto done;
    }
    int amin = 0, amax = 0, bmin = 0, bmax = 0;
    size_t m = 0;
    for (size_t k = 0; k < p->kernel_count; k++) {
        const aa_kernel *ker = &p->kernels[k];
        r.first[k] = m;
        for (size_t n = 0; n < ker->count; n++, m++) {
            const aa_point *ts = &p->tile_samples[ker->tile_index[n]];
            r.da[m] = (int)lround((ker->out_x + ker->samples[n].x - ts->x) / r.T);
            r.db[m] = (int)lround((ker->out_y + ker->samples[n].y - ts->y) / r.T);
            amin = r.da[m] < amin ? r.da[m] : amin;
            amax = r.da[m] > amax ? r.da[m] : amax;
            bmin = r.db[m] < bmin ? r.db[m] : bmin;
            bmax = r.db[m] > bmax ? r.db[m] : bmax;
        }
    }
    r.cx0 = floor_div(reg.x0, r.T) + amin;
    r.cy0 = floor_div(reg.y0, r.T) + bmin;
    r.ncx = floor_div(reg.x1 - 1, r.T) + amax - r.cx0 + 1;
    r.ncy = floor_div(reg.y1 - 1, r.T) + bmax - r.cy0 + 1;
    /* Kernels reaching far beyond the region would need a huge cache: evaluate those samples
     * per read instead (same values, only shared evaluation is lost). */
    double cells_d = (double)r.ncx * (double)r.ncy * (double)p->tile_count;
    size_t cells = cells_d <= AA_RASTER_MAX_CACHE ? (size_t)cells_d : 0;
    r.cache = cells ? malloc(cells * sizeof *r.cache) : NULL;
    for (size_t c = 0; r.cache && c < cells; c++)
        r.cache[c] = NAN;
    size_t rw = (size_t)(reg.x1 - reg.x0);
    for (int j = reg.y0; j < reg.y1; j++)
        for (int i = reg.x0; i < reg.x1; i++)
            if (mask[(size_t)(j - reg.y0) * rw + (size_t)(i - reg.x0)])
                out->px[(size_t)j * out->width + i] = (float)shared_pixel(&r, i, j);
    st->samples_evaluated = r.evaluated;
done:
    free(r.da);
    free(r.db);
    free(r.first);
    free(r.cache);
    return rc;
}

/* No known repetition: every pixel evaluates its own samples. */
static void render_unshared(const aa_scene *s, const aa_pattern *p, aa_image *out, aa_rect reg,
                            const uint8_t *mask, aa_raster_stats *st)
{
    double off = aa_output_offset(p->kernel_size);
    size_t rw = (size_t)(reg.x1 - reg.x0);
    for (int j = reg.y0; j < reg.y1; j++) {
        for (int i = reg.x0; i < reg.x1; i++) {
            if (!mask[(size_t)(j - reg.y0) * rw + (size_t)(i - reg.x0)])
                continue;
            const aa_kernel *ker =
                &p->kernels[((size_t)j * (size_t)out->width + (size_t)i) % p->kernel_count];
            double sum = 0;
            for (size_t n = 0; n < ker->count; n++)
                sum += ker->samples[n].w *
                       aa_scene_value(s, i + off + ker->samples[n].x, j + off + ker->samples[n].y);
            st->samples_evaluated += ker->count;
            out->px[(size_t)j * out->width + i] = (float)sum;
        }
    }
}

int aa_render_pattern(const aa_scene *s, const aa_pattern *p, bool skip, aa_image *out,
                      const aa_rect *region, aa_raster_stats *st, aa_error *err)
{
    aa_raster_stats local;
    if (!st)
        st = &local;
    memset(st, 0, sizeof *st);
    if (out->width != s->p.width || out->height != s->p.height)
        return aa_error_set(err, AA_EINVAL, "", "image and scene sizes differ");
    if (p->kernel_count == 0 || (p->tile > 0 && p->kernel_count != (size_t)p->tile * p->tile))
        return aa_error_set(err, AA_EINVAL, "pattern", "pattern has no usable kernels");
    aa_rect reg = aa_image_rect(out);
    if (region)
        reg = aa_rect_intersect(reg, *region);
    size_t area = aa_rect_area(reg);
    st->pixels = area;
    if (area == 0)
        return AA_OK;
    uint8_t *mask = malloc(area);
    if (!mask)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    double off = aa_output_offset(p->kernel_size);
    st->pixels_sampled = aa_traverse_footprints(s, reg, off, kernel_extent(p), skip, out, mask);
    int rc = AA_OK;
    if (p->tile > 0)
        rc = render_shared(s, p, out, reg, mask, st, err);
    else
        render_unshared(s, p, out, reg, mask, st);
    free(mask);
    return rc;
}
