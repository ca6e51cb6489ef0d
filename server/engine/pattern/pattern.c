/* Pattern forms -> tile samples, kernels, cost and family label (pattern.h). */
#include "pattern.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void aa_pattern_free(aa_pattern *p)
{
    if (!p)
        return;
    for (size_t k = 0; k < p->kernel_count && p->kernels; k++) {
        free(p->kernels[k].samples);
        free(p->kernels[k].tile_index);
    }
    free(p->kernels);
    free(p->tile_samples);
    free(p->tile_site);
    free(p->source);
    memset(p, 0, sizeof *p);
}

size_t aa_pattern_total_kernel_samples(const aa_pattern *p)
{
    size_t n = 0;
    for (size_t k = 0; k < p->kernel_count; k++)
        n += p->kernels[k].count;
    return n;
}

static bool near_integer(double v)
{
    return fabs(v - round(v)) <= AA_POSITION_EPS;
}

aa_site aa_site_of(double x, double y)
{
    bool ix = near_integer(x), iy = near_integer(y);
    if (ix && iy)
        return AA_SITE_CORNER;
    if (ix)
        return AA_SITE_VERTICAL_EDGE;
    if (iy)
        return AA_SITE_HORIZONTAL_EDGE;
    return AA_SITE_INTERIOR;
}

void aa_family_label(char *out, size_t cap, size_t s, int kernel_size, bool border, double n)
{
    snprintf(out, cap, "P(%zu,%lld%s,%.6g)", s, (long long)kernel_size * kernel_size,
             border ? "+" : "", n);
}

/* Wraps v into [0, T), snapping values within eps of the grid onto it so that sites and
 * sharing are decided exactly. */
static double wrap(double v, int T)
{
    assert(T >= 1); /* the tile size every constructor has settled (2 for mirrored) */
    if (near_integer(v))
        v = round(v);
    v = fmod(v, (double)T);
    if (v < 0)
        v += T;
    if (v >= T - AA_POSITION_EPS)
        v = 0;
    return v;
}

static bool same_point(aa_point a, aa_point b, int T)
{
    /* Periodic distance, so that 0 and T - tiny are recognised as one sample. */
    double dx = fabs(a.x - b.x), dy = fabs(a.y - b.y);
    if (T > 0) {
        dx = fmin(dx, T - dx);
        dy = fmin(dy, T - dy);
    }
    return dx <= AA_POSITION_EPS && dy <= AA_POSITION_EPS;
}

/* Finds q among the tile samples or appends it; returns its index. */
static size_t intern_point(aa_pattern *p, aa_point q)
{
    for (size_t i = 0; i < p->tile_count; i++)
        if (same_point(p->tile_samples[i], q, p->tile))
            return i;
    p->tile_samples[p->tile_count] = q;
    return p->tile_count++;
}

static int alloc_kernels(aa_pattern *p, size_t s, aa_error *err)
{
    p->kernels = calloc(s, sizeof *p->kernels);
    if (!p->kernels)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    p->kernel_count = s;
    return AA_OK;
}

static int alloc_kernel(aa_kernel *k, size_t n, bool with_index, aa_error *err)
{
    k->samples = calloc(n ? n : 1, sizeof *k->samples);
    k->tile_index = with_index ? calloc(n ? n : 1, sizeof *k->tile_index) : NULL;
    if (!k->samples || (with_index && !k->tile_index))
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    k->count = n;
    return AA_OK;
}

static int fill_sites(aa_pattern *p, aa_error *err)
{
    p->tile_site = calloc(p->tile_count ? p->tile_count : 1, sizeof *p->tile_site);
    if (!p->tile_site)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t i = 0; i < p->tile_count; i++)
        p->tile_site[i] = aa_site_of(p->tile_samples[i].x, p->tile_samples[i].y);
    return AA_OK;
}

/* Checks or normalises one kernel's weights. */
static int check_weights(aa_kernel *k, unsigned flags, const char *field, aa_error *err)
{
    double sum = 0;
    for (size_t i = 0; i < k->count; i++)
        sum += k->samples[i].w;
    if (!(fabs(sum) >= 1e-12))
        return aa_error_set(err, AA_EINVAL, field, "weights sum to %.3g; they must sum to 1", sum);
    if (flags & AA_PATTERN_NORMALIZE) {
        for (size_t i = 0; i < k->count; i++)
            k->samples[i].w /= sum;
    } else if (fabs(sum - 1) > AA_WEIGHT_SUM_TOLERANCE) {
        return aa_error_set(err, AA_EINVAL, field,
                            "weights sum to %.12g, not 1 (ask for normalisation to rescale)", sum);
    }
    return AA_OK;
}

static int check_sample(const aa_sample *s, const char *prefix, size_t k, size_t i, bool kernels,
                        aa_error *err)
{
    char field[96];
    const double v[3] = {s->x, s->y, s->w};
    for (int c = 0; c < 3; c++) {
        if (kernels)
            snprintf(field, sizeof field, "%s[%zu][%zu][%d]", prefix, k, i, c);
        else
            snprintf(field, sizeof field, "%s[%zu][%d]", prefix, i, c);
        if (!isfinite(v[c]))
            return aa_error_set(err, AA_EINVAL, field, "must be a finite number");
        if (c < 2 && fabs(v[c]) > AA_MAX_COORD)
            return aa_error_set(err, AA_ERANGE, field, "coordinate beyond +-%g pixels",
                                AA_MAX_COORD);
        if (c == 2 && fabs(v[c]) > AA_MAX_WEIGHT)
            return aa_error_set(err, AA_ERANGE, field, "weight beyond +-%g", AA_MAX_WEIGHT);
    }
    return AA_OK;
}

/* Output point of tile pixel (i, j) for a K x K kernel, in tile coordinates. */
static double output_coord(int i, int K)
{
    return (double)(i - (K - 1) / 2) + K / 2.0;
}

int aa_pattern_copy(aa_pattern *dst, const aa_pattern *src)
{
    memset(dst, 0, sizeof *dst);
    *dst = *src;
    dst->kernels = NULL;
    dst->tile_samples = NULL;
    dst->tile_site = NULL;
    dst->source = NULL;
    dst->kernel_count = 0;
    size_t tc = src->tile_count ? src->tile_count : 1;
    dst->tile_samples = malloc(tc * sizeof *dst->tile_samples);
    dst->tile_site = malloc(tc * sizeof *dst->tile_site);
    dst->kernels = calloc(src->kernel_count, sizeof *dst->kernels);
    if (!dst->tile_samples || !dst->tile_site || !dst->kernels)
        goto fail;
    if (src->tile_count) {
        memcpy(dst->tile_samples, src->tile_samples, src->tile_count * sizeof *src->tile_samples);
        memcpy(dst->tile_site, src->tile_site, src->tile_count * sizeof *src->tile_site);
    }
    dst->kernel_count = src->kernel_count;
    for (size_t k = 0; k < src->kernel_count; k++) {
        const aa_kernel *s = &src->kernels[k];
        aa_kernel *d = &dst->kernels[k];
        *d = *s;
        d->samples = NULL;
        d->tile_index = NULL;
        if (alloc_kernel(d, s->count, s->tile_index != NULL, NULL))
            goto fail;
        memcpy(d->samples, s->samples, s->count * sizeof *s->samples);
        if (s->tile_index)
            memcpy(d->tile_index, s->tile_index, s->count * sizeof *s->tile_index);
    }
    if (src->source_count) {
        dst->source = malloc(src->source_count * sizeof *dst->source);
        if (!dst->source)
            goto fail;
        memcpy(dst->source, src->source, src->source_count * sizeof *src->source);
    }
    return AA_OK;
fail:
    aa_pattern_free(dst);
    return AA_ENOMEM;
}

/* --- explicit kernels ------------------------------------------------------------------ */

int aa_pattern_from_kernels(aa_pattern *p, const aa_sample *const *kernels, const size_t *counts,
                            size_t s, unsigned flags, aa_error *err)
{
    memset(p, 0, sizeof *p);
    p->form = AA_FORM_KERNELS;
    if (s == 0)
        return aa_error_set(err, AA_EINVAL, "kernels", "a pattern needs at least one kernel");
    if (s > AA_MAX_KERNELS)
        return aa_error_set(err, AA_ERANGE, "kernels", "at most %d kernels", AA_MAX_KERNELS);
    size_t total = 0;
    double extent = 0;
    char field[64];
    for (size_t k = 0; k < s; k++) {
        snprintf(field, sizeof field, "kernels[%zu]", k);
        if (counts[k] == 0)
            return aa_error_set(err, AA_EINVAL, field, "a kernel needs at least one sample");
        if (counts[k] > AA_MAX_KERNEL_SAMPLES)
            return aa_error_set(err, AA_ERANGE, field, "at most %d samples per kernel",
                                AA_MAX_KERNEL_SAMPLES);
        for (size_t i = 0; i < counts[k]; i++) {
            int rc = check_sample(&kernels[k][i], "kernels", k, i, true, err);
            if (rc)
                return rc;
            extent = fmax(extent, fmax(fabs(kernels[k][i].x), fabs(kernels[k][i].y)));
        }
        total += counts[k];
    }
    int rc = alloc_kernels(p, s, err);
    for (size_t k = 0; k < s && !rc; k++) {
        rc = alloc_kernel(&p->kernels[k], counts[k], true, err);
        if (!rc) {
            memcpy(p->kernels[k].samples, kernels[k], counts[k] * sizeof(aa_sample));
            snprintf(field, sizeof field, "kernels[%zu]", k);
            rc = check_weights(&p->kernels[k], flags, field, err);
        }
    }
    if (rc) {
        aa_pattern_free(p);
        return rc;
    }

    /* The smallest K whose closed block [-K/2, K/2]^2 holds every sample. */
    double K_real = ceil(2 * extent - 2 * AA_POSITION_EPS);
    int K = K_real < 1 ? 1 : K_real > 1e9 ? 1000000000 : (int)K_real;
    p->kernel_size = K;
    int T = (int)llround(sqrt((double)s));
    if ((size_t)T * (size_t)T != s) {
        /* No known repetition: nothing is shared; '+' when a sample lies on the block border. */
        p->tile = 0;
        for (size_t k = 0; k < s; k++) {
            free(p->kernels[k].tile_index);
            p->kernels[k].tile_index = NULL;
            for (size_t i = 0; i < counts[k]; i++)
                if (fmax(fabs(kernels[k][i].x), fabs(kernels[k][i].y)) >= K / 2.0 - AA_POSITION_EPS)
                    p->border = true;
        }
        p->cost_spp = (double)total / (double)s;
        aa_family_label(p->family, sizeof p->family, s, K, p->border, p->cost_spp);
        return AA_OK;
    }
    p->tile = T;
    p->tile_samples = malloc(total * sizeof *p->tile_samples);
    size_t *reads = calloc(total, sizeof *reads);
    if (!p->tile_samples || !reads) {
        free(reads);
        aa_pattern_free(p);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    for (int j = 0; j < T; j++) {
        for (int i = 0; i < T; i++) {
            aa_kernel *ker = &p->kernels[(size_t)j * T + i];
            ker->out_x = output_coord(i, K);
            ker->out_y = output_coord(j, K);
            for (size_t n = 0; n < ker->count; n++) {
                aa_point q = {wrap(ker->out_x + ker->samples[n].x, T),
                              wrap(ker->out_y + ker->samples[n].y, T)};
                ker->tile_index[n] = intern_point(p, q);
                reads[ker->tile_index[n]]++;
            }
        }
    }
    /* '+' (L&A sec. 3): samples on pixel borders are shared by more kernels than the K^2 that
     * read any sample of a K x K block; decided by counting, so it is invariant under the
     * square's symmetries (a sample on a border read by one kernel does not make it '+'). */
    for (size_t t = 0; t < p->tile_count; t++)
        if (reads[t] > (size_t)K * (size_t)K)
            p->border = true;
    free(reads);
    p->cost_spp = (double)p->tile_count / ((double)T * T);
    aa_family_label(p->family, sizeof p->family, s, K, p->border, p->cost_spp);
    rc = fill_sites(p, err);
    if (rc)
        aa_pattern_free(p);
    return rc;
}

/* --- mirrored P(4,1+,n) ------------------------------------------------------------------ */

int aa_pattern_from_mirrored(aa_pattern *p, const aa_sample *samples, size_t n, unsigned flags,
                             aa_error *err)
{
    memset(p, 0, sizeof *p);
    p->form = AA_FORM_MIRRORED;
    if (n == 0)
        return aa_error_set(err, AA_EINVAL, "mirrored", "a pattern needs at least one sample");
    if (n > AA_MAX_KERNEL_SAMPLES)
        return aa_error_set(err, AA_ERANGE, "mirrored", "at most %d samples",
                            AA_MAX_KERNEL_SAMPLES);
    char field[64];
    for (size_t i = 0; i < n; i++) {
        int rc = check_sample(&samples[i], "mirrored", 0, i, false, err);
        if (rc)
            return rc;
        for (int c = 0; c < 2; c++) {
            double v = c == 0 ? samples[i].x : samples[i].y;
            if (fabs(v) > 0.5 + AA_POSITION_EPS) {
                snprintf(field, sizeof field, "mirrored[%zu][%d]", i, c);
                return aa_error_set(err, AA_EINVAL, field,
                                    "a mirrored pattern's samples lie in the pixel [-0.5, 0.5]^2");
            }
        }
        for (size_t j = 0; j < i; j++) {
            if (fabs(samples[i].x - samples[j].x) <= AA_POSITION_EPS &&
                fabs(samples[i].y - samples[j].y) <= AA_POSITION_EPS) {
                snprintf(field, sizeof field, "mirrored[%zu]", i);
                return aa_error_set(err, AA_EINVAL, field, "sample %zu is at the same position", j);
            }
        }
    }
    p->source = malloc(n * sizeof *p->source);
    int rc = p->source ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
    if (!rc) {
        memcpy(p->source, samples, n * sizeof *samples);
        p->source_count = n;
        /* Snap to the pixel border so that edge and corner samples are shared exactly. */
        for (size_t i = 0; i < n; i++) {
            if (fabs(fabs(p->source[i].x) - 0.5) <= AA_POSITION_EPS)
                p->source[i].x = copysign(0.5, p->source[i].x);
            if (fabs(fabs(p->source[i].y) - 0.5) <= AA_POSITION_EPS)
                p->source[i].y = copysign(0.5, p->source[i].y);
        }
        aa_kernel tmp = {n, p->source, NULL, 0, 0};
        rc = check_weights(&tmp, flags, "mirrored", err);
    }
    if (!rc)
        rc = alloc_kernels(p, 4, err);
    if (!rc) {
        p->tile = 2;
        p->kernel_size = 1;
        p->border = true;
        p->tile_samples = malloc(4 * n * sizeof *p->tile_samples);
        if (!p->tile_samples)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    for (int j = 0; j < 2 && !rc; j++) {
        for (int i = 0; i < 2 && !rc; i++) {
            aa_kernel *ker = &p->kernels[j * 2 + i];
            rc = alloc_kernel(ker, n, true, err);
            if (rc)
                break;
            double sx = i == 0 ? 1 : -1, sy = j == 0 ? 1 : -1;
            ker->out_x = i + 0.5;
            ker->out_y = j + 0.5;
            for (size_t m = 0; m < n; m++) {
                aa_sample s = {sx * p->source[m].x, sy * p->source[m].y, p->source[m].w};
                ker->samples[m] = s;
                aa_point q = {wrap(ker->out_x + s.x, 2), wrap(ker->out_y + s.y, 2)};
                ker->tile_index[m] = intern_point(p, q);
            }
        }
    }
    if (!rc) {
        p->cost_spp = (double)p->tile_count / 4.0;
        aa_family_label(p->family, sizeof p->family, 4, 1, true, p->cost_spp);
        rc = fill_sites(p, err);
    }
    if (rc)
        aa_pattern_free(p);
    return rc;
}

/* --- general tile form -------------------------------------------------------------------- */

static int point_yx_cmp(const void *pa, const void *pb)
{
    const aa_sample *a = pa, *b = pb;
    if (a->y != b->y)
        return (a->y > b->y) - (a->y < b->y);
    return (a->x > b->x) - (a->x < b->x);
}

/* Collects the samples kernel (i, j) reads, in canonical (y, x) order, relative to its output
 * point, with their tile indices carried in w (as a double) until weights are assigned. */
static int collect_block(aa_pattern *p, int i, int j, aa_kernel *ker, aa_error *err)
{
    int T = p->tile, K = p->kernel_size;
    double lx = i - (K - 1) / 2, ly = j - (K - 1) / 2;
    ker->out_x = output_coord(i, K);
    ker->out_y = output_coord(j, K);
    size_t cap = p->tile_count * (size_t)((K / T + 2) * (K / T + 2)), n = 0;
    aa_sample *tmp = malloc(cap * sizeof *tmp);
    if (!tmp)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    int lo_x = (int)floor((lx - T) / T) - 1, hi_x = (int)ceil((lx + K) / T) + 1;
    int lo_y = (int)floor((ly - T) / T) - 1, hi_y = (int)ceil((ly + K) / T) + 1;
    double e = AA_POSITION_EPS;
    for (size_t t = 0; t < p->tile_count; t++) {
        for (int oy = lo_y; oy <= hi_y; oy++) {
            for (int ox = lo_x; ox <= hi_x; ox++) {
                double x = p->tile_samples[t].x + ox * T, y = p->tile_samples[t].y + oy * T;
                bool in_x =
                    p->border ? (x >= lx - e && x <= lx + K + e) : (x >= lx - e && x < lx + K - e);
                bool in_y =
                    p->border ? (y >= ly - e && y <= ly + K + e) : (y >= ly - e && y < ly + K - e);
                if (in_x && in_y && n < cap)
                    tmp[n++] = (aa_sample){x - ker->out_x, y - ker->out_y, (double)t};
            }
        }
    }
    qsort(tmp, n, sizeof *tmp, point_yx_cmp);
    int rc = alloc_kernel(ker, n, true, err);
    if (!rc) {
        for (size_t m = 0; m < n; m++) {
            ker->samples[m] = tmp[m];
            ker->tile_index[m] = (size_t)tmp[m].w;
            ker->samples[m].w = 0;
        }
    }
    free(tmp);
    return rc;
}

int aa_pattern_from_tile(aa_pattern *p, const aa_tile_spec *spec, unsigned flags, aa_error *err)
{
    memset(p, 0, sizeof *p);
    p->form = AA_FORM_TILE;
    char field[64];
    if (spec->tile < 1 || spec->tile > AA_MAX_TILE)
        return aa_error_set(err, AA_EINVAL, "tile.size", "tile size must be 1..%d", AA_MAX_TILE);
    if (spec->kernel_size < 1 || spec->kernel_size > AA_MAX_KERNEL_SIZE)
        return aa_error_set(err, AA_EINVAL, "tile.kernel", "kernel size must be 1..%d",
                            AA_MAX_KERNEL_SIZE);
    if (spec->count == 0)
        return aa_error_set(err, AA_EINVAL, "tile.samples", "a tile needs at least one sample");
    if (spec->count > AA_MAX_KERNEL_SAMPLES)
        return aa_error_set(err, AA_ERANGE, "tile.samples", "at most %d samples per tile",
                            AA_MAX_KERNEL_SAMPLES);
    if (!spec->weights && !spec->weight_filter)
        return aa_error_set(err, AA_EINVAL, "tile.weights", "weights are required");
    int T = spec->tile;
    p->tile = T;
    p->kernel_size = spec->kernel_size;
    p->border = spec->border;
    p->tile_samples = malloc(spec->count * sizeof *p->tile_samples);
    if (!p->tile_samples)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    int rc = AA_OK;
    for (size_t i = 0; i < spec->count && !rc; i++) {
        aa_point q = spec->samples[i];
        snprintf(field, sizeof field, "tile.samples[%zu]", i);
        if (!isfinite(q.x) || !isfinite(q.y) || fabs(q.x) > AA_MAX_COORD ||
            fabs(q.y) > AA_MAX_COORD) {
            rc = aa_error_set(err, AA_EINVAL, field, "sample position must be finite");
            break;
        }
        q.x = wrap(q.x, T);
        q.y = wrap(q.y, T);
        size_t before = p->tile_count;
        if (intern_point(p, q) != before)
            rc = aa_error_set(err, AA_EINVAL, field, "two samples at the same tile position");
    }
    if (!rc)
        rc = alloc_kernels(p, (size_t)T * T, err);
    for (int j = 0; j < T && !rc; j++) {
        for (int i = 0; i < T && !rc; i++) {
            size_t k = (size_t)j * T + i;
            aa_kernel *ker = &p->kernels[k];
            rc = collect_block(p, i, j, ker, err);
            if (rc)
                break;
            snprintf(field, sizeof field, "tile.weights[%zu]", k);
            if (ker->count == 0) {
                rc = aa_error_set(err, AA_EINVAL, field, "kernel %zu reads no sample", k);
                break;
            }
            if (spec->weights) {
                if (spec->weight_counts[k] != ker->count) {
                    rc = aa_error_set(err, AA_EINVAL, field,
                                      "kernel %zu reads %zu samples but %zu weights were given", k,
                                      ker->count, spec->weight_counts[k]);
                    break;
                }
                for (size_t m = 0; m < ker->count; m++) {
                    if (!isfinite(spec->weights[k][m]) ||
                        fabs(spec->weights[k][m]) > AA_MAX_WEIGHT) {
                        snprintf(field, sizeof field, "tile.weights[%zu][%zu]", k, m);
                        rc = aa_error_set(err, AA_EINVAL, field,
                                          "must be a finite number within +-%g", AA_MAX_WEIGHT);
                        break;
                    }
                    ker->samples[m].w = spec->weights[k][m];
                }
                if (!rc)
                    rc = check_weights(ker, flags, field, err);
            } else {
                for (size_t m = 0; m < ker->count; m++)
                    ker->samples[m].w = aa_filter_eval(spec->weight_filter, ker->samples[m].x) *
                                        aa_filter_eval(spec->weight_filter, ker->samples[m].y);
                rc = check_weights(ker, flags | AA_PATTERN_NORMALIZE, field, err);
            }
        }
    }
    if (!rc) {
        p->cost_spp = (double)p->tile_count / ((double)T * T);
        aa_family_label(p->family, sizeof p->family, (size_t)T * T, p->kernel_size, p->border,
                        p->cost_spp);
        rc = fill_sites(p, err);
    }
    if (rc)
        aa_pattern_free(p);
    return rc;
}
