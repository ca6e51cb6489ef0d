/* Presets: cost and family of every preset against its paper; the four mirrored kernels of every
 * P(4,1+,n) preset give the same E2 one by one; a pattern rotated by 90 degrees gives the same E2
 * on the symmetric default angle set; the tile form, explicit kernels and the mirrored form of
 * the same pattern agree (kernels as sets, E2, cost, family).
 *
 * Expected costs (Hasselgren et al. 2005, Table 1 costs: corner 0.25, edge 0.5, interior 1):
 *   A 1.25, B 1.5, C 1.5, D 1.75, E 1.75, F 2; FLIPQUAD 4 x 0.5 = 2; FLIPTRI 0.25 + 2 x 0.5 =
 *   1.25; Quincunx 1 + 4 x 0.25 = 2 (Laine & Aila Table 1); grids and RGSS 4; Kyro/diagonal 2;
 *   centroid 1; D3D standard N-sample patterns N. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aa_metric.h"
#include "aa_pattern.h"

typedef struct expected_preset {
    const char *name;
    double cost;
    const char *family;
} expected_preset;

static const expected_preset expected[] = {
    {"centroid", 1, "P(1,1,1)"},
    {"kyro-horizontal", 2, "P(1,1,2)"},
    {"kyro-vertical", 2, "P(1,1,2)"},
    {"diagonal", 2, "P(1,1,2)"},
    {"grid-2x2", 4, "P(1,1,4)"},
    {"rgss", 4, "P(1,1,4)"},
    {"quincunx", 2, "P(1,1+,2)"},
    {"flipquad", 2, "P(4,1+,2)"},
    {"fliptri", 1.25, "P(4,1+,1.25)"},
    {"hasselgren-a", 1.25, "P(4,1+,1.25)"},
    {"hasselgren-b", 1.5, "P(4,1+,1.5)"},
    {"hasselgren-c", 1.5, "P(4,1+,1.5)"},
    {"hasselgren-d", 1.75, "P(4,1+,1.75)"},
    {"hasselgren-e", 1.75, "P(4,1+,1.75)"},
    {"hasselgren-f", 2, "P(4,1+,2)"},
    {"d3d-1x", 1, "P(1,1,1)"},
    {"d3d-2x", 2, "P(1,1,2)"},
    {"d3d-4x", 4, "P(1,1,4)"},
    {"d3d-8x", 8, "P(1,1,8)"},
    {"d3d-16x", 16, "P(1,1,16)"},
};
#define N_EXPECTED (sizeof expected / sizeof expected[0])

static aa_filter filter;
static aa_acuity acuity;

static int setup(void **state)
{
    (void)state;
    aa_filter_default(&filter);
    aa_acuity_naiman(&acuity);
    return 0;
}

static double e2_of(const aa_pattern *p)
{
    aa_metric_params mp = {.filter = &filter, .acuity = &acuity};
    aa_evaluation ev;
    aa_error err = {0};
    assert_int_equal(aa_evaluate(p, &mp, &ev, &err), AA_OK);
    double e2 = ev.e2;
    aa_evaluation_free(&ev);
    return e2;
}

static void test_every_preset_cost_and_family(void **state)
{
    (void)state;
    assert_int_equal(aa_preset_count(), N_EXPECTED);
    for (size_t i = 0; i < N_EXPECTED; i++) {
        const aa_preset *pr = aa_preset_find(expected[i].name);
        if (!pr) {
            print_error("preset %s missing\n", expected[i].name);
            fail();
        }
        assert_ptr_equal(pr, aa_preset_at(i));
        assert_non_null(pr->source);
        assert_true(pr->cost_spp == expected[i].cost);
        assert_string_equal(pr->family, expected[i].family);
        aa_pattern p;
        aa_error err = {0};
        assert_int_equal(aa_pattern_from_preset(&p, pr, &err), AA_OK);
        /* the cost and label the engine derives from the coordinates, not the table's */
        if (fabs(p.cost_spp - expected[i].cost) > 1e-12 ||
            strcmp(p.family, expected[i].family) != 0) {
            print_error("%s: derived cost %.17g family %s, expected %g %s\n", pr->name, p.cost_spp,
                        p.family, expected[i].cost, expected[i].family);
            fail();
        }
        double w = 0.0;
        for (size_t k = 0; k < p.kernel_count; k++) {
            w = 0.0;
            for (size_t j = 0; j < p.kernels[k].count; j++)
                w += p.kernels[k].samples[j].w;
            assert_true(fabs(w - 1.0) <= 1e-9);
        }
        aa_pattern_free(&p);
    }
    assert_null(aa_preset_find("no-such-preset"));
}

static void test_family_label_format(void **state)
{
    (void)state;
    char buf[48];
    aa_family_label(buf, sizeof buf, 4, 1, true, 1.25);
    assert_string_equal(buf, "P(4,1+,1.25)");
    aa_family_label(buf, sizeof buf, 1, 1, true, 2);
    assert_string_equal(buf, "P(1,1+,2)");
    aa_family_label(buf, sizeof buf, 16, 4, false, 4);
    assert_string_equal(buf, "P(16,16,4)");
    aa_family_label(buf, sizeof buf, 1, 2, false, 3.5);
    assert_string_equal(buf, "P(1,4,3.5)");
    aa_family_label(buf, sizeof buf, 4, 2, true, 1.75);
    assert_string_equal(buf, "P(4,4+,1.75)");
}

/* Kernels form with one kernel from samples. */
static void one_kernel_pattern(aa_pattern *p, const aa_sample *s, size_t n)
{
    const aa_sample *ks[1] = {s};
    size_t counts[1] = {n};
    aa_error err = {0};
    int rc = aa_pattern_from_kernels(p, ks, counts, 1, 0, &err);
    if (rc != AA_OK) {
        print_error("from_kernels: %d %s (%s)\n", rc, err.message, err.field);
        fail();
    }
}

static void mirror(const aa_sample *src, size_t n, int m, aa_sample *out)
{
    for (size_t i = 0; i < n; i++) {
        out[i] = src[i];
        if (m & 1)
            out[i].x = -out[i].x;
        if (m & 2)
            out[i].y = -out[i].y;
    }
}

static void test_mirrored_kernels_same_e2(void **state)
{
    (void)state;
    size_t checked = 0;
    for (size_t i = 0; i < aa_preset_count(); i++) {
        const aa_preset *pr = aa_preset_at(i);
        if (pr->form != AA_FORM_MIRRORED)
            continue;
        aa_sample k[16];
        double e2[4];
        for (int m = 0; m < 4; m++) {
            mirror(pr->samples, pr->sample_count, m, k);
            aa_pattern p;
            one_kernel_pattern(&p, k, pr->sample_count);
            e2[m] = e2_of(&p);
            aa_pattern_free(&p);
        }
        for (int m = 1; m < 4; m++)
            assert_true(fabs(e2[m] - e2[0]) <= 1e-12 * e2[0]);
        /* inside the mirrored pattern: every kernel's own maximum is the same */
        aa_pattern p;
        aa_error err = {0};
        assert_int_equal(aa_pattern_from_preset(&p, pr, &err), AA_OK);
        assert_int_equal(p.kernel_count, 4);
        aa_metric_params mp = {.filter = &filter, .acuity = &acuity};
        aa_evaluation ev;
        assert_int_equal(aa_evaluate(&p, &mp, &ev, &err), AA_OK);
        for (size_t kk = 0; kk < 4; kk++) {
            double best = 0.0;
            for (size_t a = 0; a < ev.angle_count; a++)
                best = fmax(best, ev.weight[a] * ev.e1[kk * ev.angle_count + a]);
            assert_true(fabs(best - e2[0]) <= 1e-12 * e2[0]);
        }
        assert_true(fabs(ev.e2 - e2[0]) <= 1e-12 * e2[0]);
        aa_evaluation_free(&ev);
        aa_pattern_free(&p);
        checked++;
    }
    assert_int_equal(checked, 8); /* flipquad, fliptri, hasselgren a-f */
}

static void test_rotation_by_90_same_e2(void **state)
{
    (void)state;
    for (size_t i = 0; i < aa_preset_count(); i++) {
        const aa_preset *pr = aa_preset_at(i);
        aa_pattern p, q;
        aa_error err = {0};
        assert_int_equal(aa_pattern_from_preset(&p, pr, &err), AA_OK);
        aa_sample rot[32];
        for (size_t j = 0; j < pr->sample_count; j++)
            rot[j] = (aa_sample){-pr->samples[j].y, pr->samples[j].x, pr->samples[j].w};
        if (pr->form == AA_FORM_MIRRORED)
            assert_int_equal(aa_pattern_from_mirrored(&q, rot, pr->sample_count, 0, &err), AA_OK);
        else
            one_kernel_pattern(&q, rot, pr->sample_count);
        double a = e2_of(&p), b = e2_of(&q);
        if (fabs(a - b) > 1e-12 * a) {
            print_error("%s: E2 %.17g, rotated by 90: %.17g\n", pr->name, a, b);
            fail();
        }
        assert_true(fabs(p.cost_spp - q.cost_spp) < 1e-12);
        /* the label too: '+' counts shared reads, not which side a border sample is on
         * (d3d-16x has samples on the left/bottom border only) */
        assert_string_equal(p.family, q.family);
        aa_pattern_free(&p);
        aa_pattern_free(&q);
    }
}

/* ---------- tile form vs explicit kernels vs mirrored ---------- */

typedef struct abs_sample {
    double x, y, w;
} abs_sample;

static int cmp_yx(const void *a, const void *b)
{
    const abs_sample *u = a, *v = b;
    if (fabs(u->y - v->y) > 1e-9)
        return u->y < v->y ? -1 : 1;
    if (fabs(u->x - v->x) > 1e-9)
        return u->x < v->x ? -1 : 1;
    return 0;
}

static int cmp_sample(const void *a, const void *b)
{
    const aa_sample *u = a, *v = b;
    if (fabs(u->x - v->x) > 1e-9)
        return u->x < v->x ? -1 : 1;
    if (fabs(u->y - v->y) > 1e-9)
        return u->y < v->y ? -1 : 1;
    if (fabs(u->w - v->w) > 1e-12)
        return u->w < v->w ? -1 : 1;
    return 0;
}

/* Kernel k of p equals the sample set s (order-free, 1e-9). */
static bool kernel_equals(const aa_kernel *k, const aa_sample *s, size_t n)
{
    if (k->count != n)
        return false;
    aa_sample a[32], b[32];
    memcpy(a, k->samples, n * sizeof *a);
    memcpy(b, s, n * sizeof *b);
    qsort(a, n, sizeof *a, cmp_sample);
    qsort(b, n, sizeof *b, cmp_sample);
    for (size_t i = 0; i < n; i++)
        if (cmp_sample(&a[i], &b[i]) != 0)
            return false;
    return true;
}

/* Every kernel in `mine` occurs in p (and counts match). */
static void expect_same_kernel_set(const aa_pattern *p, aa_sample mine[4][16], size_t n,
                                   const char *what)
{
    assert_int_equal(p->kernel_count, 4);
    for (int m = 0; m < 4; m++) {
        bool found = false;
        for (size_t k = 0; k < 4 && !found; k++)
            found = kernel_equals(&p->kernels[k], mine[m], n);
        if (!found) {
            print_error("%s: mirror image %d not among the kernels\n", what, m);
            fail();
        }
    }
}

static void test_tile_kernels_mirrored_agree(void **state)
{
    (void)state;
    for (size_t i = 0; i < aa_preset_count(); i++) {
        const aa_preset *pr = aa_preset_at(i);
        if (pr->form != AA_FORM_MIRRORED)
            continue;
        size_t n = pr->sample_count;
        /* pixel (i, j) of the 2x2 tile uses mirror m = i + 2 j (across the shared edges) */
        aa_sample mine[4][16];
        for (int m = 0; m < 4; m++)
            mirror(pr->samples, n, m, mine[m]);
        aa_pattern pm, pk, pt;
        aa_error err = {0};
        assert_int_equal(aa_pattern_from_preset(&pm, pr, &err), AA_OK);
        expect_same_kernel_set(&pm, mine, n, "mirrored form");

        const aa_sample *ks[4] = {mine[0], mine[1], mine[2], mine[3]};
        size_t counts[4] = {n, n, n, n};
        assert_int_equal(aa_pattern_from_kernels(&pk, ks, counts, 4, 0, &err), AA_OK);
        expect_same_kernel_set(&pk, mine, n, "kernels form");

        /* tile form: T = 2, K = 1, border; tile samples are the distinct wrapped positions */
        aa_point tile[64];
        size_t tc = 0;
        double wts[4][16];
        const double *wp[4];
        size_t wc[4];
        for (int j = 0; j < 2; j++) {
            for (int ii = 0; ii < 2; ii++) {
                int m = ii + 2 * j;
                abs_sample a[16];
                for (size_t s = 0; s < n; s++) {
                    a[s] =
                        (abs_sample){ii + 0.5 + mine[m][s].x, j + 0.5 + mine[m][s].y, mine[m][s].w};
                    double tx = fmod(a[s].x, 2.0), ty = fmod(a[s].y, 2.0);
                    bool dup = false;
                    for (size_t t = 0; t < tc && !dup; t++)
                        dup = fabs(tile[t].x - tx) < 1e-9 && fabs(tile[t].y - ty) < 1e-9;
                    if (!dup)
                        tile[tc++] = (aa_point){tx, ty};
                }
                qsort(a, n, sizeof *a, cmp_yx); /* canonical order: y, then x */
                for (size_t s = 0; s < n; s++)
                    wts[m][s] = a[s].w;
                wp[m] = wts[m];
                wc[m] = n;
            }
        }
        aa_tile_spec spec = {.tile = 2,
                             .kernel_size = 1,
                             .border = true,
                             .count = tc,
                             .samples = tile,
                             .weights = wp,
                             .weight_counts = wc};
        int rc = aa_pattern_from_tile(&pt, &spec, 0, &err);
        if (rc != AA_OK) {
            print_error("%s tile form: %d %s (%s)\n", pr->name, rc, err.message, err.field);
            fail();
        }
        expect_same_kernel_set(&pt, mine, n, "tile form");
        /* pixel order of the tile form is row-major: kernel j*T + i is pixel (i, j) */
        for (int m = 0; m < 4; m++)
            assert_true(kernel_equals(&pt.kernels[m], mine[m], n));

        double e_m = e2_of(&pm), e_k = e2_of(&pk), e_t = e2_of(&pt);
        assert_true(fabs(e_k - e_m) <= 1e-12 * e_m);
        assert_true(fabs(e_t - e_m) <= 1e-12 * e_m);
        assert_true(fabs(pt.cost_spp - pr->cost_spp) < 1e-12);
        assert_true(fabs(pk.cost_spp - pr->cost_spp) < 1e-12);
        assert_string_equal(pt.family, pr->family);
        assert_string_equal(pk.family, pr->family);
        aa_pattern_free(&pm);
        aa_pattern_free(&pk);
        aa_pattern_free(&pt);
    }
}

/* Quincunx and RGSS as T = 1 tiles. */
static void test_tile_form_p11(void **state)
{
    (void)state;
    aa_error err = {0};
    {
        aa_point tile[2] = {{0.5, 0.5}, {0.0, 0.0}};
        double w[5] = {0.125, 0.125, 0.5, 0.125, 0.125}; /* (0,0) (1,0) centre (0,1) (1,1) */
        const double *wp[1] = {w};
        size_t wc[1] = {5};
        aa_tile_spec spec = {.tile = 1,
                             .kernel_size = 1,
                             .border = true,
                             .count = 2,
                             .samples = tile,
                             .weights = wp,
                             .weight_counts = wc};
        aa_pattern pt, pq;
        assert_int_equal(aa_pattern_from_tile(&pt, &spec, 0, &err), AA_OK);
        assert_int_equal(aa_pattern_from_preset(&pq, aa_preset_find("quincunx"), &err), AA_OK);
        assert_true(kernel_equals(&pt.kernels[0], pq.kernels[0].samples, 5));
        assert_string_equal(pt.family, "P(1,1+,2)");
        assert_true(fabs(pt.cost_spp - 2.0) < 1e-12);
        assert_true(fabs(e2_of(&pt) - e2_of(&pq)) <= 1e-12 * e2_of(&pq));
        aa_pattern_free(&pt);
        aa_pattern_free(&pq);
    }
    {
        const aa_preset *rg = aa_preset_find("rgss");
        aa_point tile[4];
        abs_sample a[4];
        for (int i = 0; i < 4; i++) {
            tile[i] = (aa_point){0.5 + rg->samples[i].x, 0.5 + rg->samples[i].y};
            a[i] = (abs_sample){tile[i].x, tile[i].y, rg->samples[i].w};
        }
        qsort(a, 4, sizeof *a, cmp_yx);
        double w[4] = {a[0].w, a[1].w, a[2].w, a[3].w};
        const double *wp[1] = {w};
        size_t wc[1] = {4};
        aa_tile_spec spec = {.tile = 1,
                             .kernel_size = 1,
                             .border = false,
                             .count = 4,
                             .samples = tile,
                             .weights = wp,
                             .weight_counts = wc};
        aa_pattern pt, pr;
        assert_int_equal(aa_pattern_from_tile(&pt, &spec, 0, &err), AA_OK);
        assert_int_equal(aa_pattern_from_preset(&pr, rg, &err), AA_OK);
        assert_true(kernel_equals(&pt.kernels[0], pr.kernels[0].samples, 4));
        assert_string_equal(pt.family, "P(1,1,4)");
        assert_true(fabs(e2_of(&pt) - e2_of(&pr)) <= 1e-12 * e2_of(&pr));
        aa_pattern_free(&pt);
        aa_pattern_free(&pr);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_preset_cost_and_family),
        cmocka_unit_test(test_family_label_format),
        cmocka_unit_test(test_mirrored_kernels_same_e2),
        cmocka_unit_test(test_rotation_by_90_same_e2),
        cmocka_unit_test(test_tile_kernels_mirrored_agree),
        cmocka_unit_test(test_tile_form_p11),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
