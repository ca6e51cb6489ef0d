/* Pattern construction: weight-sum errors naming the field (unless AA_PATTERN_NORMALIZE), sum 0
 * always an error, NaN/inf, out-of-range coordinates, too many samples or kernels, negative
 * weights accepted; tile forms P(1,4,n) and P(16,16,4) (jittered, weights from the filter,
 * checked against the independent h of reference_metric.c); copies; sites. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "aa_metric.h"
#include "aa_pattern.h"
#include "reference_metric.h"

static int kernels1(aa_pattern *p, const aa_sample *s, size_t n, unsigned flags, aa_error *err)
{
    const aa_sample *ks[1] = {s};
    size_t counts[1] = {n};
    memset(err, 0, sizeof *err);
    return aa_pattern_from_kernels(p, ks, counts, 1, flags, err);
}

static bool starts_with(const char *s, const char *prefix)
{
    return strncmp(s, prefix, strlen(prefix)) == 0;
}

static void test_weight_sum(void **state)
{
    (void)state;
    aa_pattern p;
    aa_error err;
    aa_sample s[3] = {{-0.25, 0, 0.5}, {0.25, 0, 0.4}, {0, 0.25, 0.2}}; /* sum 1.1 */
    assert_int_equal(kernels1(&p, s, 3, 0, &err), AA_EINVAL);
    assert_true(starts_with(err.field, "kernels[0]"));
    aa_pattern_free(&p); /* safe after an error */

    /* kernel 1 of 2 is the bad one */
    aa_sample good[2] = {{-0.25, 0, 0.5}, {0.25, 0, 0.5}};
    const aa_sample *ks[2] = {good, s};
    size_t counts[2] = {2, 3};
    memset(&err, 0, sizeof err);
    assert_int_equal(aa_pattern_from_kernels(&p, ks, counts, 2, 0, &err), AA_EINVAL);
    assert_true(starts_with(err.field, "kernels[1]"));

    /* within the 1e-9 tolerance is accepted */
    aa_sample near[2] = {{-0.25, 0, 0.5}, {0.25, 0, 0.5 + 5e-10}};
    assert_int_equal(kernels1(&p, near, 2, 0, &err), AA_OK);
    aa_pattern_free(&p);

    /* normalisation divides by the sum */
    assert_int_equal(kernels1(&p, s, 3, AA_PATTERN_NORMALIZE, &err), AA_OK);
    assert_true(fabs(p.kernels[0].samples[0].w - 0.5 / 1.1) < 1e-15);
    assert_true(fabs(p.kernels[0].samples[2].w - 0.2 / 1.1) < 1e-15);
    aa_pattern_free(&p);

    /* sum 0 is an error either way */
    aa_sample zero[2] = {{-0.25, 0, 0.5}, {0.25, 0, -0.5}};
    assert_int_equal(kernels1(&p, zero, 2, 0, &err), AA_EINVAL);
    assert_true(starts_with(err.field, "kernels[0]"));
    assert_int_equal(kernels1(&p, zero, 2, AA_PATTERN_NORMALIZE, &err), AA_EINVAL);
    assert_true(starts_with(err.field, "kernels[0]"));
    aa_sample tiny[2] = {{-0.25, 0, 1e-13}, {0.25, 0, 0}};
    assert_int_equal(kernels1(&p, tiny, 2, AA_PATTERN_NORMALIZE, &err), AA_EINVAL);

    /* mirrored form */
    aa_sample m[2] = {{-0.5, 0.1, 0.5}, {0.5, -0.1, 0.6}};
    memset(&err, 0, sizeof err);
    assert_int_equal(aa_pattern_from_mirrored(&p, m, 2, 0, &err), AA_EINVAL);
    assert_true(starts_with(err.field, "mirrored"));
    assert_int_equal(aa_pattern_from_mirrored(&p, m, 2, AA_PATTERN_NORMALIZE, &err), AA_OK);
    for (size_t k = 0; k < p.kernel_count; k++) {
        double sum = 0;
        for (size_t i = 0; i < p.kernels[k].count; i++)
            sum += p.kernels[k].samples[i].w;
        assert_true(fabs(sum - 1.0) < 1e-15);
    }
    aa_pattern_free(&p);
}

static void test_non_finite_and_range(void **state)
{
    (void)state;
    aa_pattern p;
    aa_error err;
    const char *fields[3] = {"kernels[0][1][0]", "kernels[0][1][1]", "kernels[0][1][2]"};
    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int c = 0; c < 3; c++) {
        for (int b = 0; b < 3; b++) {
            aa_sample s[2] = {{-0.25, 0, 0.5}, {0.25, 0, 0.5}};
            double *v = c == 0 ? &s[1].x : c == 1 ? &s[1].y : &s[1].w;
            *v = bad[b];
            int rc = kernels1(&p, s, 2, AA_PATTERN_NORMALIZE, &err);
            assert_true(rc < 0);
            assert_string_equal(err.field, fields[c]);
            aa_pattern_free(&p);
        }
    }
    /* coordinates beyond AA_MAX_COORD */
    aa_sample far[2] = {{-0.25, 0, 0.5}, {0.25, 2e6, 0.5}};
    assert_true(kernels1(&p, far, 2, 0, &err) < 0);
    assert_string_equal(err.field, "kernels[0][1][1]");
    /* exactly 1e6 is allowed */
    aa_sample edge[2] = {{-1e6, 0, 0.5}, {0.25, 1e6, 0.5}};
    assert_int_equal(kernels1(&p, edge, 2, 0, &err), AA_OK);
    aa_pattern_free(&p);
    /* NaN in the mirrored form */
    aa_sample m[2] = {{-0.5, NAN, 0.5}, {0.5, -0.1, 0.5}};
    memset(&err, 0, sizeof err);
    assert_true(aa_pattern_from_mirrored(&p, m, 2, 0, &err) < 0);
    assert_string_equal(err.field, "mirrored[0][1]");
    /* mirrored samples must be in the pixel */
    aa_sample out[2] = {{-0.5, 0.1, 0.5}, {0.7, -0.1, 0.5}};
    memset(&err, 0, sizeof err);
    assert_true(aa_pattern_from_mirrored(&p, out, 2, 0, &err) < 0);
    assert_true(starts_with(err.field, "mirrored[1]"));
}

static void test_too_many(void **state)
{
    (void)state;
    aa_pattern p;
    aa_error err;
    size_t n = AA_MAX_KERNEL_SAMPLES + 1;
    aa_sample *s = calloc(n, sizeof *s);
    for (size_t i = 0; i < n; i++)
        s[i] = (aa_sample){(double)i / n - 0.5, 0.1, 1.0 / (double)(n - 1)};
    assert_int_equal(kernels1(&p, s, n, AA_PATTERN_NORMALIZE, &err), AA_ERANGE);
    assert_int_equal(err.code, AA_ERANGE);
    assert_true(starts_with(err.field, "kernels[0]"));
    /* the maximum itself is fine */
    assert_int_equal(kernels1(&p, s, n - 1, AA_PATTERN_NORMALIZE, &err), AA_OK);
    aa_pattern_free(&p);
    /* too many kernels */
    size_t nk = AA_MAX_KERNELS + 1;
    const aa_sample **ks = calloc(nk, sizeof *ks);
    size_t *counts = calloc(nk, sizeof *counts);
    aa_sample one = {0, 0, 1};
    for (size_t k = 0; k < nk; k++)
        ks[k] = &one, counts[k] = 1;
    memset(&err, 0, sizeof err);
    assert_int_equal(aa_pattern_from_kernels(&p, ks, counts, nk, 0, &err), AA_ERANGE);
    assert_int_equal(aa_pattern_from_kernels(&p, ks, counts, nk - 1, 0, &err), AA_OK);
    aa_pattern_free(&p);
    /* no kernels / empty kernel */
    assert_true(aa_pattern_from_kernels(&p, ks, counts, 0, 0, &err) < 0);
    counts[0] = 0;
    assert_true(aa_pattern_from_kernels(&p, ks, counts, 1, 0, &err) < 0);
    free(ks);
    free(counts);
    free(s);
}

static void test_negative_weights_accepted(void **state)
{
    (void)state;
    aa_pattern p;
    aa_error err;
    aa_sample s[3] = {{-0.3, 0.1, 1.5}, {0.3, -0.1, -0.75}, {0.0, 0.4, 0.25}};
    assert_int_equal(kernels1(&p, s, 3, 0, &err), AA_OK);
    assert_true(p.kernels[0].samples[1].w == -0.75);
    aa_filter f;
    aa_acuity a;
    aa_filter_default(&f);
    aa_acuity_naiman(&a);
    aa_metric_params mp = {.filter = &f, .acuity = &a};
    aa_evaluation ev;
    assert_int_equal(aa_evaluate(&p, &mp, &ev, &err), AA_OK);
    /* every E1 equals the independent reference */
    ref_filter rf;
    ref_filter_mitchell(&rf, 1.0L / 3, 1.0L / 3, 2.0L);
    double x[3] = {-0.3, 0.3, 0.0}, y[3] = {0.1, -0.1, 0.4}, w[3] = {1.5, -0.75, 0.25};
    for (size_t i = 0; i < ev.angle_count; i++) {
        long double r = ref_e1_at_angle(&rf, x, y, w, 3, ev.angles_deg[i] * (REF_PI / 180.0L));
        assert_true(fabsl(ev.e1[i] - r) <= 1e-12L * r);
    }
    aa_evaluation_free(&ev);
    aa_pattern_free(&p);
    aa_sample m[2] = {{-0.5, 0.1, 1.25}, {0.5, -0.1, -0.25}};
    assert_int_equal(aa_pattern_from_mirrored(&p, m, 2, 0, &err), AA_OK);
    aa_pattern_free(&p);
}

static void test_tile_errors(void **state)
{
    (void)state;
    aa_pattern p;
    aa_error err;
    aa_point pts[2] = {{0.25, 0.25}, {0.75, 0.75}};
    double w0[2] = {0.5, 0.5};
    const double *wp[1] = {w0};
    size_t wc[1] = {2};
    aa_tile_spec ok = {.tile = 1,
                       .kernel_size = 1,
                       .border = false,
                       .count = 2,
                       .samples = pts,
                       .weights = wp,
                       .weight_counts = wc};
    memset(&err, 0, sizeof err);
    assert_int_equal(aa_pattern_from_tile(&p, &ok, 0, &err), AA_OK);
    assert_string_equal(p.family, "P(1,1,2)");
    aa_pattern_free(&p);

    aa_tile_spec bad = ok;
    size_t wrong[1] = {3};
    bad.weight_counts = wrong;
    memset(&err, 0, sizeof err);
    assert_true(aa_pattern_from_tile(&p, &bad, 0, &err) < 0);
    assert_true(starts_with(err.field, "tile.weights[0]"));

    double w1[2] = {0.5, 0.6};
    const double *wp1[1] = {w1};
    bad = ok;
    bad.weights = wp1;
    memset(&err, 0, sizeof err);
    assert_int_equal(aa_pattern_from_tile(&p, &bad, 0, &err), AA_EINVAL);
    assert_true(starts_with(err.field, "tile.weights[0]"));
    assert_int_equal(aa_pattern_from_tile(&p, &bad, AA_PATTERN_NORMALIZE, &err), AA_OK);
    aa_pattern_free(&p);

    aa_point nanpt[2] = {{0.25, NAN}, {0.75, 0.75}};
    bad = ok;
    bad.samples = nanpt;
    memset(&err, 0, sizeof err);
    assert_true(aa_pattern_from_tile(&p, &bad, 0, &err) < 0);
    assert_true(starts_with(err.field, "tile.samples[0]"));

    bad = ok;
    bad.weights = NULL;
    bad.weight_filter = NULL;
    memset(&err, 0, sizeof err);
    assert_true(aa_pattern_from_tile(&p, &bad, 0, &err) < 0);
    assert_true(starts_with(err.field, "tile"));

    const int bad_t[3] = {0, -1, AA_MAX_TILE + 1};
    for (int i = 0; i < 3; i++) {
        bad = ok;
        bad.tile = bad_t[i];
        memset(&err, 0, sizeof err);
        assert_true(aa_pattern_from_tile(&p, &bad, 0, &err) < 0);
        assert_true(starts_with(err.field, "tile"));
        bad = ok;
        bad.kernel_size = i == 2 ? AA_MAX_KERNEL_SIZE + 1 : bad_t[i];
        memset(&err, 0, sizeof err);
        assert_true(aa_pattern_from_tile(&p, &bad, 0, &err) < 0);
        assert_true(starts_with(err.field, "tile"));
    }
}

/* P(1,4,n): T = 1, K = 2, output at the pixel corner, four copies of each sample. */
static void test_tile_p14(void **state)
{
    (void)state;
    aa_pattern p;
    aa_error err;
    aa_point pts[2] = {{0.25, 0.75}, {0.75, 0.25}};
    aa_filter f;
    aa_filter_default(&f);
    aa_tile_spec spec = {
        .tile = 1, .kernel_size = 2, .count = 2, .samples = pts, .weight_filter = &f};
    memset(&err, 0, sizeof err);
    assert_int_equal(aa_pattern_from_tile(&p, &spec, 0, &err), AA_OK);
    assert_string_equal(p.family, "P(1,4,2)");
    assert_true(fabs(p.cost_spp - 2.0) < 1e-15);
    assert_int_equal(p.kernel_count, 1);
    assert_int_equal(p.kernels[0].count, 8);
    double sum = 0.0;
    for (size_t i = 0; i < 8; i++) {
        const aa_sample *s = &p.kernels[0].samples[i];
        assert_true(fabs(s->x) < 1.0 && fabs(s->y) < 1.0);
        /* offsets from the corner are +-0.25 or +-0.75 */
        assert_true(fabs(fabs(s->x) - 0.25) < 1e-12 || fabs(fabs(s->x) - 0.75) < 1e-12);
        sum += s->w;
    }
    assert_true(fabs(sum - 1.0) < 1e-14);
    aa_pattern_free(&p);
}

static uint64_t rng_state = 2024;
static double rng_uniform(double lo, double hi)
{
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return lo + (hi - lo) * ((double)(z >> 11) * 0x1.0p-53);
}

/* P(16,16,4): 4x4 tile, 4 jittered samples per pixel, 4x4 kernels, weights h(x) h(y). */
static void test_tile_p16_16_4(void **state)
{
    (void)state;
    aa_point pts[64];
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++)
            for (int q = 0; q < 4; q++)
                pts[(j * 4 + i) * 4 + q] = (aa_point){i + 0.5 * (q % 2) + rng_uniform(0.01, 0.49),
                                                      j + 0.5 * (q / 2) + rng_uniform(0.01, 0.49)};
    aa_filter f;
    aa_filter_default(&f);
    ref_filter rf;
    ref_filter_mitchell(&rf, 1.0L / 3, 1.0L / 3, 2.0L);
    aa_tile_spec spec = {
        .tile = 4, .kernel_size = 4, .count = 64, .samples = pts, .weight_filter = &f};
    aa_pattern p;
    aa_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(aa_pattern_from_tile(&p, &spec, 0, &err), AA_OK);
    assert_string_equal(p.family, "P(16,16,4)");
    assert_true(fabs(p.cost_spp - 4.0) < 1e-15);
    assert_int_equal(p.tile, 4);
    assert_int_equal(p.tile_count, 64);
    assert_int_equal(p.kernel_count, 16);
    assert_int_equal(aa_pattern_total_kernel_samples(&p), 16 * 64);
    for (int j = 0; j < 4; j++) {
        for (int i = 0; i < 4; i++) {
            const aa_kernel *k = &p.kernels[j * 4 + i];
            assert_int_equal(k->count, 64);
            /* block lower-left (i - 1, j - 1), output at its centre (a pixel corner) */
            assert_true(fabs(k->out_x - (i + 1.0)) < 1e-15 && fabs(k->out_y - (j + 1.0)) < 1e-15);
            long double hsum = 0.0L;
            for (size_t s = 0; s < 64; s++)
                hsum += ref_filter_h(&rf, k->samples[s].x) * ref_filter_h(&rf, k->samples[s].y);
            double wsum = 0.0;
            for (size_t s = 0; s < 64; s++) {
                const aa_sample *sm = &k->samples[s];
                assert_true(sm->x > -2.0 && sm->x < 2.0 && sm->y > -2.0 && sm->y < 2.0);
                /* the sample is a tile sample, wrapped */
                const aa_point *tp = &p.tile_samples[k->tile_index[s]];
                double ax = fmod(k->out_x + sm->x + 8.0, 4.0),
                       ay = fmod(k->out_y + sm->y + 8.0, 4.0);
                assert_true(fabs(ax - tp->x) < 1e-12 && fabs(ay - tp->y) < 1e-12);
                long double want = ref_filter_h(&rf, sm->x) * ref_filter_h(&rf, sm->y) / hsum;
                assert_true(fabsl(sm->w - want) < 1e-14L);
                wsum += sm->w;
            }
            assert_true(fabs(wsum - 1.0) < 1e-13);
        }
    }
    /* every tile sample is read by exactly 16 kernels (4x4 blocks, 4x4 tile) */
    size_t reads[64] = {0};
    for (size_t k = 0; k < 16; k++)
        for (size_t s = 0; s < 64; s++)
            reads[p.kernels[k].tile_index[s]]++;
    for (size_t t = 0; t < 64; t++)
        assert_int_equal(reads[t], 16);
    aa_pattern q;
    assert_int_equal(aa_pattern_copy(&q, &p), AA_OK);
    aa_pattern_free(&p);
    assert_string_equal(q.family, "P(16,16,4)");
    assert_int_equal(q.kernels[5].count, 64);
    aa_pattern_free(&q);
}

static void test_sites(void **state)
{
    (void)state;
    assert_int_equal(aa_site_of(0.3, 0.4), AA_SITE_INTERIOR);
    assert_int_equal(aa_site_of(1.0, 0.3), AA_SITE_VERTICAL_EDGE);
    assert_int_equal(aa_site_of(0.3, 2.0), AA_SITE_HORIZONTAL_EDGE);
    assert_int_equal(aa_site_of(1.0, 1.0), AA_SITE_CORNER);
    assert_int_equal(aa_site_of(0.0, 0.0), AA_SITE_CORNER);
    assert_int_equal(aa_site_of(1.0 + 1e-11, 0.5), AA_SITE_VERTICAL_EDGE);
    assert_int_equal(aa_site_of(1.0 + 1e-6, 0.5), AA_SITE_INTERIOR);
    /* FLIPQUAD-like mirrored pattern: every tile sample on an edge, cost 4 x 0.5 */
    aa_sample m[4] = {{-0.5, 0.2, 0.25}, {0.5, -0.2, 0.25}, {0.2, 0.5, 0.25}, {-0.2, -0.5, 0.25}};
    aa_pattern p;
    aa_error err;
    assert_int_equal(aa_pattern_from_mirrored(&p, m, 4, 0, &err), AA_OK);
    assert_int_equal(p.tile, 2);
    assert_int_equal(p.tile_count, 8);
    for (size_t t = 0; t < p.tile_count; t++)
        assert_true(p.tile_site[t] == AA_SITE_VERTICAL_EDGE ||
                    p.tile_site[t] == AA_SITE_HORIZONTAL_EDGE);
    assert_true(fabs(p.cost_spp - 2.0) < 1e-15);
    assert_string_equal(p.family, "P(4,1+,2)");
    aa_pattern_free(&p);
    /* interior + corner: 1 + 0.25 */
    aa_sample c[2] = {{0.1, 0.2, 0.6}, {-0.5, -0.5, 0.4}};
    assert_int_equal(aa_pattern_from_mirrored(&p, c, 2, 0, &err), AA_OK);
    assert_true(fabs(p.cost_spp - 1.25) < 1e-15);
    assert_string_equal(p.family, "P(4,1+,1.25)");
    aa_pattern_free(&p);
}

/* ---------- tile form against an independent enumeration of periodic images ---------- */

typedef struct img {
    double x, y; /* absolute position of the image */
    double w;
} img;

static int cmp_img_yx(const void *a, const void *b)
{
    const img *u = a, *v = b;
    if (fabs(u->y - v->y) > 1e-9)
        return u->y < v->y ? -1 : 1;
    if (fabs(u->x - v->x) > 1e-9)
        return u->x < v->x ? -1 : 1;
    return 0;
}

static bool in_block(double v, double lo, int K, bool border)
{
    const double e = 1e-9;
    return border ? (v >= lo - e && v <= lo + K + e) : (v >= lo - e && v < lo + K - e);
}

/* Images of the tile samples inside pixel (i, j)'s block, in canonical order (y, then x). */
static size_t block_images(const aa_point *pts, size_t count, int T, int K, bool border, int i,
                           int j, img *out)
{
    double lx = i - (K - 1) / 2, ly = j - (K - 1) / 2;
    size_t n = 0;
    for (size_t t = 0; t < count; t++)
        for (int a = -3; a <= 3; a++)
            for (int b = -3; b <= 3; b++) {
                double x = pts[t].x + a * T, y = pts[t].y + b * T;
                if (in_block(x, lx, K, border) && in_block(y, ly, K, border))
                    out[n++] = (img){x, y, 0.0};
            }
    qsort(out, n, sizeof *out, cmp_img_yx);
    return n;
}

static void test_tile_form_against_enumeration(void **state)
{
    (void)state;
    rng_state = 99;
    int cases = 0;
    for (int T = 1; T <= 4; T++) {
        for (int K = 1; K <= 4; K++) {
            for (int border = 0; border <= 1; border++) {
                /* 2 jittered samples per pixel, plus an edge and a corner sample per tile */
                aa_point pts[40];
                size_t count = 0;
                for (int j = 0; j < T; j++)
                    for (int i = 0; i < T; i++)
                        for (int q = 0; q < 2; q++)
                            pts[count++] = (aa_point){i + rng_uniform(0.05, 0.95),
                                                      j + rng_uniform(0.05, 0.95)};
                pts[count++] = (aa_point){0.0, rng_uniform(0.1, 0.9)};
                pts[count++] = (aa_point){0.0, 0.0};
                int s = T * T;
                static img blocks[16][2048];
                static double wbuf[16][2048];
                const double *wp[16];
                size_t wc[16];
                for (int j = 0; j < T; j++)
                    for (int i = 0; i < T; i++) {
                        int k = j * T + i;
                        wc[k] = block_images(pts, count, T, K, border, i, j, blocks[k]);
                        for (size_t m = 0; m < wc[k]; m++)
                            wbuf[k][m] = blocks[k][m].w = 1.0 + m + 0.01 * k; /* distinct */
                        wp[k] = wbuf[k];
                    }
                aa_tile_spec spec = {.tile = T,
                                     .kernel_size = K,
                                     .border = border,
                                     .count = count,
                                     .samples = pts,
                                     .weights = wp,
                                     .weight_counts = wc};
                aa_pattern p;
                aa_error err;
                memset(&err, 0, sizeof err);
                int rc = aa_pattern_from_tile(&p, &spec, AA_PATTERN_NORMALIZE, &err);
                if (rc != AA_OK) {
                    print_error("T=%d K=%d border=%d: %d %s (%s)\n", T, K, border, rc, err.message,
                                err.field);
                    fail();
                }
                assert_int_equal(p.kernel_count, (size_t)s);
                assert_int_equal(p.tile_count, count);
                assert_true(fabs(p.cost_spp - (double)count / s) < 1e-12);
                char label[48];
                aa_family_label(label, sizeof label, (size_t)s, K, border, (double)count / s);
                /* '+' only matters when a border sample is actually read twice: compare the
                 * rest of the label */
                assert_true(strncmp(p.family, label, 4) == 0);
                for (int j = 0; j < T; j++)
                    for (int i = 0; i < T; i++) {
                        int k = j * T + i;
                        const aa_kernel *ker = &p.kernels[k];
                        double ox = i - (K - 1) / 2 + K / 2.0, oy = j - (K - 1) / 2 + K / 2.0;
                        assert_true(fabs(ker->out_x - ox) < 1e-12 && fabs(ker->out_y - oy) < 1e-12);
                        if (ker->count != wc[k]) {
                            print_error("T=%d K=%d border=%d kernel %d: %zu samples, expected "
                                        "%zu\n",
                                        T, K, border, k, ker->count, wc[k]);
                            fail();
                        }
                        double wsum = 0.0;
                        for (size_t m = 0; m < wc[k]; m++)
                            wsum += wbuf[k][m];
                        /* each engine sample is one of my images, with that image's weight */
                        for (size_t m = 0; m < ker->count; m++) {
                            double ax = ox + ker->samples[m].x, ay = oy + ker->samples[m].y;
                            bool found = false;
                            for (size_t q = 0; q < wc[k] && !found; q++)
                                found = fabs(blocks[k][q].x - ax) < 1e-9 &&
                                        fabs(blocks[k][q].y - ay) < 1e-9 &&
                                        fabs(blocks[k][q].w / wsum - ker->samples[m].w) < 1e-12;
                            if (!found) {
                                print_error("T=%d K=%d border=%d kernel %d: sample (%g, %g) w %g "
                                            "not expected\n",
                                            T, K, border, k, ax, ay, ker->samples[m].w);
                                fail();
                            }
                        }
                    }
                aa_pattern_free(&p);
                cases++;
            }
        }
    }
    assert_int_equal(cases, 32);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_weight_sum),
        cmocka_unit_test(test_non_finite_and_range),
        cmocka_unit_test(test_too_many),
        cmocka_unit_test(test_negative_weights_accepted),
        cmocka_unit_test(test_tile_errors),
        cmocka_unit_test(test_tile_p14),
        cmocka_unit_test(test_tile_p16_16_4),
        cmocka_unit_test(test_sites),
        cmocka_unit_test(test_tile_form_against_enumeration),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
