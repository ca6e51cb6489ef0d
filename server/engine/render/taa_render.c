/* The TAA loop on a static scene (taa_render.h). */
#include "taa_render.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "aa_metric.h"
#include "raster.h"
#include "raster_traverse.h"

int aa_taa_init(aa_taa *r, const aa_scene *s, const aa_temporal *t, bool skip, aa_error *err)
{
    memset(r, 0, sizeof *r);
    if (!t || t->phase_count == 0 || t->group_count == 0)
        return aa_error_set(err, AA_EINVAL, "pattern", "the temporal pattern has no phases");
    r->scene = *s;
    r->t = t;
    r->skip = skip;
    int T = (int)llround(sqrt((double)t->group_count));
    r->tile = (size_t)T * (size_t)T == t->group_count ? T : 0;
    double e = 0;
    for (size_t g = 0; g < t->group_count; g++)
        for (size_t n = 0; n < t->groups[g].count; n++)
            e = fmax(e, fmax(fabs(t->groups[g].pos[n].x), fabs(t->groups[g].pos[n].y)));
    r->extent = e;
    /* As aa_pattern_from_kernels: the smallest K whose closed block holds every sample. */
    double K = ceil(2 * e - 2 * AA_POSITION_EPS);
    r->kernel_size = K < 1 ? 1 : K > 1e9 ? 1000000000 : (int)K;
    r->offset = aa_output_offset(r->kernel_size);
    return AA_OK;
}

static size_t group_of(const aa_taa *r, int i, int j, int width)
{
    if (r->tile > 0) {
        int T = r->tile, a = ((i % T) + T) % T, b = ((j % T) + T) % T;
        return (size_t)b * (size_t)T + (size_t)a;
    }
    return ((size_t)j * (size_t)width + (size_t)i) % r->t->group_count;
}

/* F_f of pixel (i, j) for every f: each group sample evaluated once. */
static void pixel_frames(const aa_taa *r, int i, int j, double *frames)
{
    const aa_temporal_group *grp = &r->t->groups[group_of(r, i, j, r->scene.p.width)];
    for (size_t f = 0; f < r->t->phase_count; f++)
        frames[f] = 0;
    double x = i + r->offset, y = j + r->offset;
    for (size_t n = 0; n < grp->count; n++)
        if (grp->in_frame[n] != 0)
            frames[grp->frame[n]] +=
                grp->in_frame[n] * aa_scene_value(&r->scene, x + grp->pos[n].x, y + grp->pos[n].y);
}

/* Steady state of every phase from the frames: S_0 summed (oldest first), then the recurrence. */
static void steady_states(const aa_temporal *t, const double *frames, double *steady)
{
    size_t N = t->phase_count;
    if (t->blend.kind == AA_BLEND_BOX) {
        double m = 0;
        for (size_t f = 0; f < N; f++)
            m += frames[f];
        m /= (double)N;
        for (size_t p = 0; p < N; p++)
            steady[p] = m;
        return;
    }
    double s0 = 0;
    for (size_t j = N; j-- > 0;)
        s0 += t->age_weight[j] * frames[(N - j) % N];
    steady[0] = s0;
    double a = t->blend.alpha, b = 1 - a;
    for (size_t p = 1; p < N; p++)
        steady[p] = a * frames[p] + b * steady[p - 1];
}

/* The traversal's mask of the pixels to sample (the others get their constant in out). */
static uint8_t *footprint_mask(const aa_taa *r, aa_image *out, size_t *marked, aa_error *err)
{
    if (out->width != r->scene.p.width || out->height != r->scene.p.height) {
        aa_error_set(err, AA_EINVAL, "", "image and scene sizes differ");
        return NULL;
    }
    aa_rect reg = aa_image_rect(out);
    uint8_t *mask = malloc(aa_rect_area(reg));
    if (!mask) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    *marked = aa_traverse_footprints(&r->scene, reg, r->offset, r->extent, r->skip, out, mask);
    return mask;
}

typedef enum image_series { IMAGE_FRAME, IMAGE_PHASE } image_series;

static int render_image(const aa_taa *r, image_series series, size_t index, aa_image *out,
                        aa_error *err)
{
    size_t N = r->t->phase_count, marked;
    if (index >= N)
        return aa_error_set(err, AA_EINVAL, series == IMAGE_FRAME ? "frame" : "phase",
                            "must be below %zu", N);
    double *frames = malloc(2 * N * sizeof *frames);
    if (!frames)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    uint8_t *mask = footprint_mask(r, out, &marked, err);
    if (!mask) {
        free(frames);
        return err ? err->code : AA_ENOMEM;
    }
    int W = out->width;
    for (int j = 0; j < out->height; j++) {
        for (int i = 0; i < W; i++) {
            size_t k = (size_t)j * (size_t)W + (size_t)i;
            if (!mask[k])
                continue;
            pixel_frames(r, i, j, frames);
            if (series == IMAGE_FRAME) {
                out->px[k] = (float)frames[index];
            } else {
                steady_states(r->t, frames, frames + N);
                out->px[k] = (float)frames[N + index];
            }
        }
    }
    free(mask);
    free(frames);
    return AA_OK;
}

int aa_taa_frame_image(const aa_taa *r, size_t f, aa_image *out, aa_error *err)
{
    return render_image(r, IMAGE_FRAME, f, out, err);
}

int aa_taa_phase_image(const aa_taa *r, size_t p, aa_image *out, aa_error *err)
{
    return render_image(r, IMAGE_PHASE, p, out, err);
}

void aa_taa_stats_free(aa_taa_stats *s)
{
    if (!s)
        return;
    free(s->phase_sum_sq);
    free(s->phase_max_dev);
    free(s->cut_sum_sq);
    memset(s, 0, sizeof *s);
}

double aa_taa_rmse(const aa_taa_stats *s, double sum_sq)
{
    return s->pixels ? sqrt(sum_sq / (double)s->pixels) : 0;
}

/* Adds one pixel's errors: frames[N] its frames, steady[N] scratch for its steady states (the
 * after-cut histories are made on the fly), ref its reference value. */
static void add_pixel(const aa_temporal *t, const double *frames, double *steady, double ref,
                      aa_taa_stats *st)
{
    size_t N = t->phase_count, K = st->cut_count;
    steady_states(t, frames, steady);
    double mean = 0;
    for (size_t p = 0; p < N; p++)
        mean += steady[p];
    mean /= (double)N;
    for (size_t p = 0; p < N; p++) {
        double d = 255.0 * (steady[p] - ref);
        st->phase_sum_sq[p] += d * d;
        st->phase_max_dev[p] = fmax(st->phase_max_dev[p], fabs(d));
        double s = 255.0 * (steady[p] - steady[(p + N - 1) % N]);
        st->flicker_step_sum_sq += s * s;
        double m = 255.0 * (steady[p] - mean);
        st->flicker_mean_sum_sq += m * m;
    }
    if (t->blend.kind == AA_BLEND_BOX) {
        double sum = 0; /* the last min(k, N) frames */
        for (size_t k = 1; k <= K; k++) {
            sum += frames[(k - 1) % N];
            size_t m = k < N ? k : N;
            if (k > N)
                sum -= frames[(k - 1 - N) % N];
            double d = 255.0 * (sum / (double)m - ref);
            st->cut_sum_sq[k - 1] += d * d;
        }
        return;
    }
    double a = t->blend.alpha, b = 1 - a, h = frames[0];
    for (size_t k = 1; k <= K; k++) {
        if (k > 1)
            h = a * frames[(k - 1) % N] + b * h;
        double d = 255.0 * (h - ref);
        st->cut_sum_sq[k - 1] += d * d;
    }
}

int aa_taa_measure(const aa_taa *r, const aa_image *reference, size_t cut_count,
                   int (*progress)(void *user, double fraction), void *user, aa_taa_stats *st,
                   aa_error *err)
{
    memset(st, 0, sizeof *st);
    size_t N = r->t->phase_count;
    if (cut_count == 0 || cut_count > AA_TEMPORAL_MAX_CUT_FRAMES)
        return aa_error_set(err, AA_EINVAL, "cut_frames", "must be 1 to %d",
                            AA_TEMPORAL_MAX_CUT_FRAMES);
    if (reference->width != r->scene.p.width || reference->height != r->scene.p.height)
        return aa_error_set(err, AA_EINVAL, "", "image and scene sizes differ");
    aa_image constant;
    int rc = aa_image_init(&constant, reference->width, reference->height, err);
    if (rc)
        return rc;
    st->phase_count = N;
    st->cut_count = cut_count;
    st->pixels = (size_t)reference->width * (size_t)reference->height;
    st->phase_sum_sq = calloc(N, sizeof *st->phase_sum_sq);
    st->phase_max_dev = calloc(N, sizeof *st->phase_max_dev);
    st->cut_sum_sq = calloc(cut_count, sizeof *st->cut_sum_sq);
    double *frames = malloc(2 * N * sizeof *frames);
    uint8_t *mask = NULL;
    if (!st->phase_sum_sq || !st->phase_max_dev || !st->cut_sum_sq || !frames)
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    if (!rc && !(mask = footprint_mask(r, &constant, &st->pixels_sampled, err)))
        rc = err ? err->code : AA_ENOMEM;
    int W = reference->width, H = reference->height;
    for (int j = 0; j < H && !rc; j++) {
        for (int i = 0; i < W; i++) {
            size_t k = (size_t)j * (size_t)W + (size_t)i;
            double ref = reference->px[k];
            if (mask[k]) {
                pixel_frames(r, i, j, frames);
                st->samples_evaluated += r->t->groups[group_of(r, i, j, W)].count;
                add_pixel(r->t, frames, frames + N, ref, st);
                continue;
            }
            /* Constant footprint: every frame, phase and history is the constant. */
            double d = 255.0 * ((double)constant.px[k] - ref);
            for (size_t p = 0; p < N; p++) {
                st->phase_sum_sq[p] += d * d;
                st->phase_max_dev[p] = fmax(st->phase_max_dev[p], fabs(d));
            }
            for (size_t c = 0; c < cut_count; c++)
                st->cut_sum_sq[c] += d * d;
        }
        if (progress && progress(user, (j + 1.0) / H))
            rc = aa_error_set(err, AA_ECANCELED, "", "cancelled");
    }
    free(mask);
    free(frames);
    aa_image_free(&constant);
    if (rc)
        aa_taa_stats_free(st);
    return rc;
}

int aa_taa_phase_pattern(const aa_temporal *t, size_t p, aa_pattern *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    size_t G = t->group_count, N = t->phase_count;
    if (p >= N)
        return aa_error_set(err, AA_EINVAL, "phase", "must be below %zu", N);
    aa_sample **kernels = calloc(G, sizeof *kernels);
    size_t *counts = calloc(G, sizeof *counts);
    int rc = kernels && counts ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t g = 0; g < G && !rc; g++) {
        const aa_temporal_group *grp = &t->groups[g];
        kernels[g] = malloc((grp->count ? grp->count : 1) * sizeof **kernels);
        if (!kernels[g]) {
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
            break;
        }
        for (size_t n = 0; n < grp->count; n++) {
            size_t age = (p + N - grp->frame[n]) % N;
            kernels[g][n] =
                (aa_sample){grp->pos[n].x, grp->pos[n].y, t->age_weight[age] * grp->in_frame[n]};
        }
        counts[g] = grp->count;
    }
    if (!rc)
        rc = aa_pattern_from_kernels(out, (const aa_sample *const *)kernels, counts, G, 0, err);
    for (size_t g = 0; kernels && g < G; g++)
        free(kernels[g]);
    free(kernels);
    free(counts);
    return rc;
}

int aa_taa_predict_flicker(const aa_temporal *t, const aa_edge_histogram *h, double *mean_rmse,
                           double *step_rmse, aa_error *err)
{
    double length[AA_EDGE_BINS];
    memcpy(length, h->length, sizeof length);
    for (size_t k = 0; k < h->locked_count; k++)
        length[aa_locked_edge_bin(&h->locked[k])] += h->locked[k].length;
    double mean = 0, step = 0;
    for (int d = 0; d < AA_EDGE_BINS; d++) {
        if (!(length[d] > 0))
            continue;
        double c, s, mean_sq = 0, step_sq = 0;
        aa_metric_direction(d * 3.14159265358979323846 / 180.0, &c, &s);
        for (size_t g = 0; g < t->group_count; g++) {
            double f1, fs;
            if (aa_temporal_flicker_at_direction(t, g, c, s, &f1, NULL) ||
                aa_temporal_flicker_step_at_direction(t, g, c, s, &fs))
                return aa_error_set(err, AA_ENOMEM, "", "out of memory");
            mean_sq += f1 * f1;
            step_sq += fs * fs;
        }
        mean += length[d] * mean_sq / (double)t->group_count;
        step += length[d] * step_sq / (double)t->group_count;
    }
    double pixels = (double)h->width * (double)h->height;
    *mean_rmse = 255.0 * sqrt(mean / pixels);
    *step_rmse = 255.0 * sqrt(step / pixels);
    return AA_OK;
}
