#include "optimizer_state.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void opt_point_clamp(opt_point *p)
{
    assert(p->lo_x <= p->hi_x && p->lo_y <= p->hi_y); /* set_box: never an empty box */
    p->x = fmin(fmax(p->x, p->lo_x), p->hi_x);
    p->y = fmin(fmax(p->y, p->lo_y), p->hi_y);
}

void opt_state_free(opt_state *st)
{
    if (st->refs)
        for (size_t k = 0; k < st->work.kernel_count; k++)
            free(st->refs[k]);
    free(st->refs);
    free(st->points);
    free(st->weights);
    free(st->weight_group);
    aa_pattern_free(&st->work);
    memset(st, 0, sizeof *st);
}

/* Box for a point on the pixel grid: a fixed coordinate where the site says so, otherwise the
 * open interval of its pixel (lo is the pixel's lower edge). */
static void set_box(opt_point *p, double px, double py, double size)
{
    double m = OPT_SITE_MARGIN;
    bool fix_x = p->site == AA_SITE_CORNER || p->site == AA_SITE_VERTICAL_EDGE;
    bool fix_y = p->site == AA_SITE_CORNER || p->site == AA_SITE_HORIZONTAL_EDGE;
    p->lo_x = fix_x ? p->x : px + m;
    p->hi_x = fix_x ? p->x : px + size - m;
    p->lo_y = fix_y ? p->y : py + m;
    p->hi_y = fix_y ? p->y : py + size - m;
}

static int init_mirrored(opt_state *st, aa_error *err)
{
    aa_pattern *w = &st->work;
    size_t n = w->source_count;
    st->point_count = n;
    st->weight_count = n;
    st->group_count = 1;
    st->points = calloc(n, sizeof *st->points);
    st->weights = calloc(n, sizeof *st->weights);
    st->weight_group = calloc(n, sizeof *st->weight_group);
    if (!st->points || !st->weights || !st->weight_group)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t m = 0; m < n; m++) {
        opt_point *p = &st->points[m];
        p->x = w->source[m].x;
        p->y = w->source[m].y;
        bool ex = fabs(fabs(p->x) - 0.5) <= AA_POSITION_EPS;
        bool ey = fabs(fabs(p->y) - 0.5) <= AA_POSITION_EPS;
        p->site = ex && ey ? AA_SITE_CORNER
                  : ex     ? AA_SITE_VERTICAL_EDGE
                  : ey     ? AA_SITE_HORIZONTAL_EDGE
                           : AA_SITE_INTERIOR;
        set_box(p, -0.5, -0.5, 1.0);
        st->weights[m] = w->source[m].w;
    }
    for (size_t k = 0; k < w->kernel_count; k++) {
        /* Kernel (i, j) of the 2x2 tile mirrors x when i = 1 and y when j = 1 (pattern.c). */
        double sx = (k % 2) ? -1 : 1, sy = (k / 2) ? -1 : 1;
        for (size_t i = 0; i < w->kernels[k].count; i++)
            st->refs[k][i] = (opt_ref){i, i, sx, sy, 0, 0};
    }
    return AA_OK;
}

static int init_shared(opt_state *st, aa_error *err)
{
    aa_pattern *w = &st->work;
    size_t total = aa_pattern_total_kernel_samples(w);
    bool shared = w->tile > 0;
    st->point_count = shared ? w->tile_count : total;
    st->weight_count = total;
    st->group_count = w->kernel_count;
    st->points = calloc(st->point_count, sizeof *st->points);
    st->weights = calloc(total, sizeof *st->weights);
    st->weight_group = calloc(total, sizeof *st->weight_group);
    if (!st->points || !st->weights || !st->weight_group)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    if (shared) {
        for (size_t t = 0; t < w->tile_count; t++) {
            opt_point *p = &st->points[t];
            p->x = w->tile_samples[t].x;
            p->y = w->tile_samples[t].y;
            p->site = w->tile_site[t];
            set_box(p, floor(p->x + AA_POSITION_EPS), floor(p->y + AA_POSITION_EPS), 1.0);
        }
    }
    size_t slot = 0, free_point = 0;
    for (size_t k = 0; k < w->kernel_count; k++) {
        aa_kernel *ker = &w->kernels[k];
        double half = w->kernel_size / 2.0;
        for (size_t i = 0; i < ker->count; i++, slot++) {
            opt_ref *r = &st->refs[k][i];
            r->weight = slot;
            r->sx = r->sy = 1;
            st->weights[slot] = ker->samples[i].w;
            st->weight_group[slot] = k;
            if (shared) {
                r->point = ker->tile_index[i];
                r->ox = ker->samples[i].x - st->points[r->point].x;
                r->oy = ker->samples[i].y - st->points[r->point].y;
            } else {
                /* No known repetition: each sample moves alone within the kernel's block. */
                opt_point *p = &st->points[free_point];
                p->x = ker->samples[i].x;
                p->y = ker->samples[i].y;
                p->site = AA_SITE_INTERIOR;
                p->lo_x = p->lo_y = -half;
                p->hi_x = p->hi_y = half;
                r->point = free_point++;
                r->ox = r->oy = 0;
            }
        }
    }
    return AA_OK;
}

int opt_state_init(opt_state *st, const aa_pattern *seed, aa_error *err)
{
    memset(st, 0, sizeof *st);
    if (aa_pattern_copy(&st->work, seed))
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    st->refs = calloc(st->work.kernel_count, sizeof *st->refs);
    int rc = st->refs ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t k = 0; k < st->work.kernel_count && !rc; k++) {
        st->refs[k] =
            calloc(st->work.kernels[k].count ? st->work.kernels[k].count : 1, sizeof **st->refs);
        if (!st->refs[k])
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    if (!rc)
        rc = st->work.form == AA_FORM_MIRRORED ? init_mirrored(st, err) : init_shared(st, err);
    if (rc)
        opt_state_free(st);
    return rc;
}

void opt_state_apply(opt_state *st)
{
    for (size_t k = 0; k < st->work.kernel_count; k++) {
        aa_kernel *ker = &st->work.kernels[k];
        for (size_t i = 0; i < ker->count; i++) {
            const opt_ref *r = &st->refs[k][i];
            assert(r->point < st->point_count && r->weight < st->weight_count);
            const opt_point *p = &st->points[r->point];
            ker->samples[i].x = r->sx * p->x + r->ox;
            ker->samples[i].y = r->sy * p->y + r->oy;
            ker->samples[i].w = st->weights[r->weight];
        }
    }
}

void opt_state_normalize_weights(opt_state *st)
{
    double sums[AA_MAX_KERNELS] = {0};
    assert(st->group_count <= AA_MAX_KERNELS); /* a group is a kernel, or the one mirrored */
    for (size_t s = 0; s < st->weight_count; s++) {
        assert(st->weight_group[s] < st->group_count);
        sums[st->weight_group[s]] += st->weights[s];
    }
    for (size_t s = 0; s < st->weight_count; s++) {
        double sum = sums[st->weight_group[s]];
        if (fabs(sum) > 1e-12)
            st->weights[s] /= sum;
    }
}

/* The tile pattern of the current variables. pattern.c takes weights in its canonical (y, then x)
 * order of each kernel's samples, so the pattern is built twice: once to learn that order, then
 * with each weight in place. A weight follows its sample by identity (the tile sample, and among
 * a wide kernel's copies of it, which are T >= 1 px apart, the nearest), never by sorting the
 * work positions: samples clamped to the same pixel edge have equal y up to the last bit, and
 * the two computations of a relative position can order such a pair differently. Sorting did
 * that on P(16,16,4), handing two weights 1.6 px apart to each other's samples (E2 0.78 for a
 * pattern whose own E2 was 0.169; 2 of 13 search rounds, and one seed's first descent). */
static int tile_to_pattern(const opt_state *st, aa_pattern *out, aa_error *err)
{
    const aa_pattern *w = &st->work;
    size_t s = w->kernel_count, total = aa_pattern_total_kernel_samples(w);
    memset(out, 0, sizeof *out);
    aa_point *pts = malloc(w->tile_count * sizeof *pts);
    double *wbuf = malloc((total ? total : 1) * sizeof *wbuf);
    const double **wk = malloc(s * sizeof *wk);
    size_t *counts = malloc(s * sizeof *counts);
    /* Per kernel, the copies of each point: head[point], then next[copy] down to SIZE_MAX. */
    size_t *head = malloc(st->point_count * sizeof *head);
    size_t *next = malloc((total ? total : 1) * sizeof *next);
    int rc = AA_OK;
    if (!pts || !wbuf || !wk || !counts || !head || !next) {
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
        goto done;
    }
    for (size_t t = 0; t < w->tile_count; t++)
        pts[t] = (aa_point){st->points[t].x, st->points[t].y};
    size_t off = 0;
    for (size_t k = 0; k < s; k++) {
        counts[k] = w->kernels[k].count;
        wk[k] = wbuf + off;
        for (size_t i = 0; i < counts[k]; i++)
            wbuf[off + i] = 1.0 / (double)counts[k]; /* placeholders: the order is what counts */
        off += counts[k];
    }
    aa_tile_spec spec = {w->tile, w->kernel_size, w->border, w->tile_count, pts, wk, counts, NULL};
    if ((rc = aa_pattern_from_tile(out, &spec, AA_PATTERN_NORMALIZE, err)))
        goto done;
    off = 0;
    for (size_t k = 0; k < s && !rc; k++) {
        const aa_kernel *ker = &w->kernels[k], *built = &out->kernels[k];
        if (built->count != ker->count) {
            rc = aa_error_set(err, AA_EINVAL, "tile.weights",
                              "kernel %zu reads %zu samples after the move, %zu before", k,
                              built->count, ker->count);
            break;
        }
        for (size_t t = 0; t < st->point_count; t++)
            head[t] = SIZE_MAX;
        for (size_t i = 0; i < ker->count; i++) {
            size_t t = st->refs[k][i].point;
            next[i] = head[t];
            head[t] = i;
        }
        for (size_t m = 0; m < built->count; m++) {
            size_t t = built->tile_index[m], match = SIZE_MAX;
            double nearest = INFINITY;
            for (size_t i = t < st->point_count ? head[t] : SIZE_MAX; i != SIZE_MAX; i = next[i]) {
                double dx = ker->samples[i].x - built->samples[m].x;
                double dy = ker->samples[i].y - built->samples[m].y;
                if (dx * dx + dy * dy < nearest) {
                    nearest = dx * dx + dy * dy;
                    match = i;
                }
            }
            if (match == SIZE_MAX) {
                rc =
                    aa_error_set(err, AA_EINVAL, "tile.weights",
                                 "kernel %zu reads tile sample %zu, which it did not before", k, t);
                break;
            }
            wbuf[off + m] = ker->samples[match].w; /* the weight the metric saw */
        }
        off += ker->count;
    }
    aa_pattern_free(out);
    if (!rc)
        rc = aa_pattern_from_tile(out, &spec, AA_PATTERN_NORMALIZE, err);
done:
    free(pts);
    free(wbuf);
    free(wk);
    free(counts);
    free(head);
    free(next);
    return rc;
}

int opt_state_to_pattern(const opt_state *st, aa_pattern *out, aa_error *err)
{
    const aa_pattern *w = &st->work;
    if (w->form == AA_FORM_MIRRORED) {
        aa_sample *s = malloc(st->point_count * sizeof *s);
        if (!s)
            return aa_error_set(err, AA_ENOMEM, "", "out of memory");
        for (size_t m = 0; m < st->point_count; m++)
            s[m] = (aa_sample){st->points[m].x, st->points[m].y, st->weights[m]};
        int rc = aa_pattern_from_mirrored(out, s, st->point_count, AA_PATTERN_NORMALIZE, err);
        free(s);
        return rc;
    }
    if (w->form == AA_FORM_TILE)
        return tile_to_pattern(st, out, err);
    const aa_sample **ks = malloc(w->kernel_count * sizeof *ks);
    size_t *counts = malloc(w->kernel_count * sizeof *counts);
    int rc;
    if (!ks || !counts) {
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    } else {
        for (size_t k = 0; k < w->kernel_count; k++) {
            ks[k] = w->kernels[k].samples;
            counts[k] = w->kernels[k].count;
        }
        rc = aa_pattern_from_kernels(out, (const aa_sample *const *)ks, counts, w->kernel_count,
                                     AA_PATTERN_NORMALIZE, err);
    }
    free(ks);
    free(counts);
    return rc;
}
