/* Temporal patterns expanded into phase kernels (temporal.h, docs/temporal.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "temporal.h"

#define AA_TEMPORAL_MAX_GROUP_SAMPLES 65536 /* N times the frame samples one group reads */
#define AA_TEMPORAL_MAX_JITTER 16.0         /* |offset| in pixels */

static int check_blend(const aa_blend *blend, aa_error *err)
{
    if (blend->kind == AA_BLEND_BOX)
        return AA_OK;
    if (blend->kind != AA_BLEND_EXPONENTIAL)
        return aa_error_set(err, AA_EINVAL, "blend.kind", "unknown blend");
    if (!(isfinite(blend->alpha) && blend->alpha >= AA_TEMPORAL_MIN_ALPHA && blend->alpha <= 1))
        return aa_error_set(err, AA_EINVAL, "blend.alpha", "alpha must be in [%g, 1]",
                            AA_TEMPORAL_MIN_ALPHA);
    return AA_OK;
}

int aa_blend_weights(const aa_blend *blend, size_t n, double *out, aa_error *err)
{
    int rc = check_blend(blend, err);
    if (rc)
        return rc;
    if (n == 0)
        return aa_error_set(err, AA_EINVAL, "jitter", "the sequence needs at least 1 offset");
    if (blend->kind == AA_BLEND_BOX) {
        for (size_t j = 0; j < n; j++)
            out[j] = 1.0 / (double)n;
        return AA_OK;
    }
    double a = blend->alpha;
    if (a == 1) {
        for (size_t j = 0; j < n; j++)
            out[j] = j == 0 ? 1 : 0;
        return AA_OK;
    }
    /* b^j = exp(j log1p(-a)) and 1 - b^n = -expm1(n log1p(-a)): no 1 - b cancellation when a
     * is small (a = 1e-4, n = 8: 1 - b^n = 8e-4 with full precision). */
    double lb = log1p(-a), den = -expm1((double)n * lb);
    for (size_t j = 0; j < n; j++)
        out[j] = a * exp((double)j * lb) / den;
    return AA_OK;
}

int aa_blend_after_cut_weights(const aa_blend *blend, size_t n, size_t k, double *out,
                               aa_error *err)
{
    int rc = check_blend(blend, err);
    if (rc)
        return rc;
    if (n == 0 || k == 0)
        return aa_error_set(err, AA_EINVAL, "cut_frames", "need at least 1 frame and 1 offset");
    if (blend->kind == AA_BLEND_BOX) {
        size_t m = k < n ? k : n; /* the accumulation holds the last min(k, n) frames */
        for (size_t i = 0; i < k; i++)
            out[i] = i >= k - m ? 1.0 / (double)m : 0;
        return AA_OK;
    }
    double a = blend->alpha;
    if (a == 1) {
        for (size_t i = 0; i < k; i++)
            out[i] = i == k - 1 ? 1 : 0;
        return AA_OK;
    }
    double lb = log1p(-a);
    out[0] = exp((double)(k - 1) * lb);
    for (size_t i = 2; i <= k; i++)
        out[i - 1] = a * exp((double)(k - i) * lb);
    return AA_OK;
}

double aa_effective_samples(const double *w, size_t n)
{
    double s = 0;
    for (size_t i = 0; i < n; i++)
        s += w[i] * w[i];
    return 1 / s;
}

void aa_temporal_free(aa_temporal *t)
{
    if (!t)
        return;
    for (size_t g = 0; g < t->group_count && t->groups; g++) {
        free(t->groups[g].pos);
        free(t->groups[g].frame);
        free(t->groups[g].in_frame);
    }
    free(t->groups);
    free(t->age_weight);
    memset(t, 0, sizeof *t);
}

static int group_alloc(aa_temporal_group *grp, size_t cap, aa_error *err)
{
    if (cap > AA_TEMPORAL_MAX_GROUP_SAMPLES)
        return aa_error_set(err, AA_ERANGE, "jitter",
                            "offsets times frame samples must be at most %d per pixel",
                            AA_TEMPORAL_MAX_GROUP_SAMPLES);
    grp->pos = malloc(cap * sizeof *grp->pos);
    grp->frame = malloc(cap * sizeof *grp->frame);
    grp->in_frame = malloc(cap * sizeof *grp->in_frame);
    if (!grp->pos || !grp->frame || !grp->in_frame)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    return AA_OK;
}

/* Without a resolve: frame kernel k shifted by each offset. */
static int build_from_kernels(aa_temporal *t, const aa_temporal_spec *spec, const aa_pattern *fp,
                              aa_error *err)
{
    for (size_t k = 0; k < fp->kernel_count; k++) {
        const aa_kernel *ker = &fp->kernels[k];
        aa_temporal_group *grp = &t->groups[k];
        int rc = group_alloc(grp, spec->count * ker->count, err);
        if (rc)
            return rc;
        for (size_t f = 0; f < spec->count; f++) {
            for (size_t i = 0; i < ker->count; i++) {
                size_t s = grp->count++;
                grp->pos[s].x = ker->samples[i].x + spec->jitter[f].x;
                grp->pos[s].y = ker->samples[i].y + spec->jitter[f].y;
                grp->frame[s] = f;
                grp->in_frame[s] = ker->samples[i].w;
            }
        }
    }
    return AA_OK;
}

/* With a resolve: every shifted tile sample of the pixels within radius of output pixel
 * (i, j), weighed h(dx) h(dy) about the pixel's centre and normalised per frame. A sample
 * belongs to the pixel it was taken for (its position before the shift). Samples outside the
 * filter's support are kept with weight 0 (phase kernels leave them out), so that the group's
 * samples do not depend on the offsets (the optimizer moves them). */
static int build_resolved(aa_temporal *t, const aa_temporal_spec *spec, const aa_pattern *fp,
                          aa_error *err)
{
    const aa_temporal_resolve *rs = spec->resolve;
    int T = fp->tile, R = rs->radius;
    size_t reach = (size_t)((2 * R + 1 + T - 1) / T + 1); /* tile copies per axis, at most */
    for (int j = 0; j < T; j++) {
        for (int i = 0; i < T; i++) {
            aa_temporal_group *grp = &t->groups[(size_t)j * T + i];
            int rc = group_alloc(grp, spec->count * fp->tile_count * reach * reach, err);
            if (rc)
                return rc;
            double cx = i + 0.5, cy = j + 0.5;
            for (size_t f = 0; f < spec->count; f++) {
                size_t first = grp->count;
                double sum = 0;
                for (size_t s = 0; s < fp->tile_count; s++) {
                    double px = floor(fp->tile_samples[s].x), py = floor(fp->tile_samples[s].y);
                    int a0 = (int)ceil((i - R - px) / T), a1 = (int)floor((i + R - px) / T);
                    int b0 = (int)ceil((j - R - py) / T), b1 = (int)floor((j + R - py) / T);
                    for (int b = b0; b <= b1; b++) {
                        for (int a = a0; a <= a1; a++) {
                            double dx = fp->tile_samples[s].x + a * T + spec->jitter[f].x - cx;
                            double dy = fp->tile_samples[s].y + b * T + spec->jitter[f].y - cy;
                            double w =
                                aa_filter_eval(&rs->filter, dx) * aa_filter_eval(&rs->filter, dy);
                            size_t n = grp->count++;
                            grp->pos[n] = (aa_point){dx, dy};
                            grp->frame[n] = f;
                            grp->in_frame[n] = w;
                            sum += w;
                        }
                    }
                }
                if (!(fabs(sum) > 1e-12)) {
                    char field[32];
                    snprintf(field, sizeof field, "jitter[%zu]", f);
                    return aa_error_set(err, AA_EINVAL, field,
                                        "the resolve filter gives this frame no weight");
                }
                for (size_t n = first; n < grp->count; n++)
                    grp->in_frame[n] /= sum;
            }
        }
    }
    return AA_OK;
}

int aa_temporal_build(aa_temporal *t, const aa_temporal_spec *spec, aa_error *err)
{
    memset(t, 0, sizeof *t);
    if (spec->count == 0 || spec->count > AA_TEMPORAL_MAX_PHASES)
        return aa_error_set(err, AA_ERANGE, "jitter", "the sequence needs 1 to %d offsets",
                            AA_TEMPORAL_MAX_PHASES);
    for (size_t f = 0; f < spec->count; f++) {
        if (!(isfinite(spec->jitter[f].x) && isfinite(spec->jitter[f].y) &&
              fabs(spec->jitter[f].x) <= AA_TEMPORAL_MAX_JITTER &&
              fabs(spec->jitter[f].y) <= AA_TEMPORAL_MAX_JITTER)) {
            char field[32];
            snprintf(field, sizeof field, "jitter[%zu]", f);
            return aa_error_set(err, AA_EINVAL, field, "an offset must be finite, |x|, |y| <= %g",
                                AA_TEMPORAL_MAX_JITTER);
        }
    }
    if (spec->resolve &&
        (spec->resolve->radius < 0 || spec->resolve->radius > AA_TEMPORAL_MAX_RESOLVE_RADIUS))
        return aa_error_set(err, AA_EINVAL, "resolve.radius", "radius must be in [0, %d]",
                            AA_TEMPORAL_MAX_RESOLVE_RADIUS);
    t->phase_count = spec->count;
    t->blend = spec->blend;
    t->age_weight = malloc(spec->count * sizeof *t->age_weight);
    if (!t->age_weight)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    int rc = aa_blend_weights(&spec->blend, spec->count, t->age_weight, err);
    if (rc) {
        aa_temporal_free(t);
        return rc;
    }

    aa_pattern centre = {0};
    const aa_pattern *fp = spec->frame;
    if (!fp) {
        const aa_sample one = {0, 0, 1};
        const aa_sample *kernels[1] = {&one};
        size_t counts[1] = {1};
        rc = aa_pattern_from_kernels(&centre, kernels, counts, 1, 0, err);
        fp = &centre;
    }
    if (!rc && spec->resolve && fp->tile < 1)
        rc = aa_error_set(err, AA_EINVAL, "frame_pattern",
                          "a resolve needs a frame pattern that repeats over a tile");
    if (!rc) {
        t->group_count = spec->resolve ? (size_t)fp->tile * fp->tile : fp->kernel_count;
        t->groups = calloc(t->group_count, sizeof *t->groups);
        if (!t->groups)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    if (!rc)
        rc =
            spec->resolve ? build_resolved(t, spec, fp, err) : build_from_kernels(t, spec, fp, err);
    t->cost_spp = fp->cost_spp;
    aa_pattern_free(&centre);
    if (rc)
        aa_temporal_free(t);
    return rc;
}

size_t aa_temporal_phase_kernel(const aa_temporal *t, size_t g, size_t p, aa_sample *out)
{
    const aa_temporal_group *grp = &t->groups[g];
    size_t n = 0, N = t->phase_count;
    for (size_t s = 0; s < grp->count; s++) {
        size_t age = (p + N - grp->frame[s]) % N; /* the newest frame of phase p is f = p */
        double w = t->age_weight[age] * grp->in_frame[s];
        if (w != 0)
            out[n++] = (aa_sample){grp->pos[s].x, grp->pos[s].y, w};
    }
    return n;
}

size_t aa_temporal_cut_kernel(const aa_temporal *t, size_t g, size_t k, double *weights,
                              double *frame_sum, aa_sample *out)
{
    size_t N = t->phase_count;
    if (aa_blend_after_cut_weights(&t->blend, N, k, weights, NULL))
        return 0;
    for (size_t f = 0; f < N; f++)
        frame_sum[f] = 0;
    /* Oldest first: the small weights of old periods are added before the large recent ones. */
    for (size_t i = 0; i < k; i++)
        frame_sum[i % N] += weights[i];
    const aa_temporal_group *grp = &t->groups[g];
    size_t n = 0;
    for (size_t s = 0; s < grp->count; s++) {
        double w = frame_sum[grp->frame[s]] * grp->in_frame[s];
        if (w != 0)
            out[n++] = (aa_sample){grp->pos[s].x, grp->pos[s].y, w};
    }
    return n;
}
