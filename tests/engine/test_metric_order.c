/* The sorted order from angle to angle (server/engine/metric/order.c). Each rank pass this CPU
 * runs (AVX2, AVX-512; the others are reported as skipped) against a first sort from the input
 * order: on random kernels swept at fine and coarse steps, a rank pass either gives the same
 * arrays bit for bit or reports that its window did not hold and leaves them unchanged; both
 * outcomes occur. Ties whose old order is not their index order, infinite and NaN projections
 * are refused or sorted correctly. Through aa_e1_kernel_block: every pass gives bit-identical
 * E1, and the workspace's counters show which pass ran. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aa_core.h"
#include "aa_metric.h"
#include "order.h"

#define PI_D 3.14159265358979323846
#define MAX_N 512

static aa_rng rng;

static double uniform(double lo, double hi)
{
    return lo + (hi - lo) * aa_rng_uniform(&rng);
}

static const aa_order_pass rank_passes[] = {AA_ORDER_RANK_AVX2, AA_ORDER_RANK_AVX512};
static const char *const rank_names[] = {"AVX2", "AVX-512"};

/* A workspace with room for n, its projections of (x, y) on (c, s) in input order. */
static void project(aa_metric_workspace *ws, const double *x, const double *y, size_t n, double c,
                    double s)
{
    for (size_t i = 0; i < n; i++)
        ws->in_p[i] = x[i] * c + y[i] * s;
}

/* The reference: the projections sorted from the input order (merge or insertion sort). */
static void reference_order(aa_metric_workspace *ref, const double *x, const double *y, size_t n,
                            double c, double s)
{
    project(ref, x, y, n, c, s);
    aa_order_fresh(ref, n);
}

static void reserve_for(aa_metric_workspace *ws, size_t n)
{
    /* any call that sizes the workspace: a block of one direction over n dummy samples */
    aa_sample *s = calloc(n, sizeof *s);
    assert_non_null(s);
    for (size_t i = 0; i < n; i++)
        s[i] = (aa_sample){(double)i, 0, 1.0 / (double)n};
    aa_filter f;
    aa_filter_default(&f);
    double c = 1, sn = 0, e1;
    assert_int_equal(aa_e1_kernel_block(&f, s, n, &c, &sn, 1, AA_E1_AUTO, ws, &e1), AA_OK);
    ws->order_of = NULL;
    free(s);
}

/* One rank pass from ws's current order (p recomputed in that order) against the reference:
 * equal arrays on success, unchanged arrays on refusal. Returns whether it succeeded. */
static bool check_rank_pass(aa_metric_workspace *ws, aa_metric_workspace *ref, aa_order_pass pass,
                            const double *x, const double *y, size_t n, double c, double s)
{
    for (size_t k = 0; k < n; k++)
        ws->p[k] = x[ws->index[k]] * c + y[ws->index[k]] * s;
    static double before_p[MAX_N];
    static uint32_t before_ix[MAX_N];
    memcpy(before_p, ws->p, n * sizeof *before_p);
    memcpy(before_ix, ws->index, n * sizeof *before_ix);
    bool ok = aa_order_rank_pass(ws, n, pass);
    reference_order(ref, x, y, n, c, s);
    if (ok) {
        assert_memory_equal(ws->p, ref->p, n * sizeof *ws->p);
        assert_memory_equal(ws->index, ref->index, n * sizeof *ws->index);
    } else {
        assert_memory_equal(ws->p, before_p, n * sizeof *ws->p);
        assert_memory_equal(ws->index, before_ix, n * sizeof *ws->index);
        /* the kernel goes on with the insertion pass, which must reach the same order */
        aa_order_insertion_pass(ws, n);
        assert_memory_equal(ws->p, ref->p, n * sizeof *ws->p);
        assert_memory_equal(ws->index, ref->index, n * sizeof *ws->index);
    }
    return ok;
}

static void test_rank_pass_matches_fresh_sort(void **state)
{
    (void)state;
    static const size_t sizes[] = {2, 17, 40, 64, 100, 256, 512};
    static const double steps_deg[] = {0.5, 5, 20};
    static double x[MAX_N], y[MAX_N];
    for (size_t q = 0; q < 2; q++) {
        if (!aa_order_pass_supported(rank_passes[q])) {
            printf("rank pass %s: not supported by this CPU, skipped\n", rank_names[q]);
            continue;
        }
        long held = 0, refused = 0;
        aa_rng_seed(&rng, 11 + q, 0);
        for (size_t si = 0; si < sizeof sizes / sizeof *sizes; si++) {
            size_t n = sizes[si];
            aa_metric_workspace ws, ref;
            aa_metric_workspace_init(&ws);
            aa_metric_workspace_init(&ref);
            reserve_for(&ws, n);
            reserve_for(&ref, n);
            for (size_t st = 0; st < 3; st++) {
                for (size_t i = 0; i < n; i++) {
                    x[i] = uniform(-2, 2);
                    y[i] = uniform(-2, 2);
                }
                double step = steps_deg[st] * (PI_D / 180), c, s;
                aa_metric_direction(0, &c, &s);
                project(&ws, x, y, n, c, s);
                aa_order_fresh(&ws, n);
                for (int a = 1; a <= 40; a++) {
                    aa_metric_direction(step * a, &c, &s);
                    if (check_rank_pass(&ws, &ref, rank_passes[q], x, y, n, c, s))
                        held++;
                    else
                        refused++;
                }
            }
            aa_metric_workspace_free(&ws);
            aa_metric_workspace_free(&ref);
        }
        printf("rank pass %s: window held on %ld angles, refused on %ld\n", rank_names[q], held,
               refused);
        assert_true(held > 100);
        assert_true(refused > 20);
    }
}

/* Ties: entries with equal p keep their old order in the rank pass; where that is not their
 * index order, the pass must refuse. Infinite projections sort; NaN is refused. */
static void test_rank_pass_ties_and_non_finite(void **state)
{
    (void)state;
    const size_t n = 48;
    for (size_t q = 0; q < 2; q++) {
        if (!aa_order_pass_supported(rank_passes[q])) {
            printf("rank pass %s: not supported by this CPU, skipped\n", rank_names[q]);
            continue;
        }
        aa_metric_workspace ws;
        aa_metric_workspace_init(&ws);
        reserve_for(&ws, n);
        /* sorted but for one tie out of index order: refused, unchanged */
        for (size_t k = 0; k < n; k++) {
            ws.p[k] = (double)(k / 2); /* pairs tie */
            ws.index[k] = (uint32_t)k;
        }
        ws.index[10] = 11;
        ws.index[11] = 10;
        assert_false(aa_order_rank_pass(&ws, n, rank_passes[q]));
        assert_int_equal(ws.index[10], 11);
        aa_order_insertion_pass(&ws, n);
        assert_int_equal(ws.index[10], 10);
        /* ties in index order, neighbours swapped around them: sorted */
        ws.p[20] = 10.5;
        ws.p[21] = 10.25;
        ws.index[20] = 21;
        ws.index[21] = 20;
        for (size_t k = 22; k < n; k++)
            ws.p[k] = (double)k;
        assert_true(aa_order_rank_pass(&ws, n, rank_passes[q]));
        for (size_t k = 0; k + 1 < n; k++)
            assert_true(ws.p[k] < ws.p[k + 1] ||
                        (ws.p[k] == ws.p[k + 1] && ws.index[k] < ws.index[k + 1]));
        /* infinities: the pads never count against them */
        for (size_t k = 0; k < n; k++) {
            ws.p[k] = (double)k;
            ws.index[k] = (uint32_t)k;
        }
        ws.p[0] = INFINITY;
        ws.p[n - 1] = -INFINITY;
        ws.p[5] = INFINITY;
        assert_false(aa_order_rank_pass(&ws, n, rank_passes[q])); /* moves past more than 16 */
        ws.p[0] = 0.5;
        ws.p[n - 1] = INFINITY;
        ws.p[5] = -INFINITY;
        assert_true(aa_order_rank_pass(&ws, n, rank_passes[q]));
        assert_true(ws.p[0] == -INFINITY && ws.index[0] == 5);
        assert_true(ws.p[n - 1] == INFINITY && ws.index[n - 1] == n - 1);
        assert_true(ws.p[1] == 0.5 && ws.index[1] == 0);
        /* NaN: refused, unchanged */
        ws.p[7] = NAN;
        assert_false(aa_order_rank_pass(&ws, n, rank_passes[q]));
        assert_true(isnan(ws.p[7]));
        aa_metric_workspace_free(&ws);
    }
}

/* Through the block: every pass the CPU runs gives bit-identical E1 at every angle, on a dense
 * 64-sample kernel (the rank pass holds) and a 512-sample one at 20 degree steps (it does not:
 * the kernel falls back to insertion after the first refusal). */
static void test_block_passes_agree(void **state)
{
    (void)state;
    aa_filter f;
    aa_filter_default(&f);
    static aa_sample s[512];
    static const size_t sizes[] = {64, 512};
    static const double steps[] = {5, 20};
    for (size_t t = 0; t < 2; t++) {
        size_t n = sizes[t];
        aa_rng_seed(&rng, 101 + t, 0);
        double sum = 0;
        for (size_t i = 0; i < n; i++) {
            s[i] = (aa_sample){uniform(-2, 2), uniform(-2, 2), uniform(0.2, 1)};
            sum += s[i].w;
        }
        for (size_t i = 0; i < n; i++)
            s[i].w /= sum;
        double dc[36], ds[36], e1_ins[36], e1[36];
        for (int a = 0; a < 36; a++)
            aa_metric_direction(a * steps[t] * (PI_D / 180), &dc[a], &ds[a]);
        aa_metric_workspace ws;
        aa_metric_workspace_init(&ws);
        ws.order_pass = AA_ORDER_INSERTION;
        assert_int_equal(aa_e1_kernel_block(&f, s, n, dc, ds, 36, AA_E1_AUTO, &ws, e1_ins), AA_OK);
        assert_int_equal(ws.rank_passes, 0);
        assert_int_equal(ws.insertion_passes, 35);
        aa_metric_workspace_free(&ws);
        for (int q = 0; q < 3; q++) {
            aa_order_pass pass = q == 2 ? AA_ORDER_AUTO : rank_passes[q];
            if (!aa_order_pass_supported(pass == AA_ORDER_AUTO ? AA_ORDER_INSERTION : pass))
                continue;
            aa_metric_workspace_init(&ws);
            ws.order_pass = pass;
            assert_int_equal(aa_e1_kernel_block(&f, s, n, dc, ds, 36, AA_E1_AUTO, &ws, e1), AA_OK);
            assert_memory_equal(e1, e1_ins, sizeof e1);
            bool any_rank = aa_order_pass_supported(AA_ORDER_RANK_AVX2) ||
                            aa_order_pass_supported(AA_ORDER_RANK_AVX512);
            if (n == 64 && (pass != AA_ORDER_AUTO || any_rank))
                assert_true(ws.rank_passes >= 30);
            if (n == 512)
                assert_true(ws.insertion_passes >= 30);
            assert_int_equal(ws.rank_passes + ws.insertion_passes, 35);
            aa_metric_workspace_free(&ws);
        }
    }
    /* below AA_ORDER_RANK_MIN the insertion pass runs whatever was asked */
    for (size_t i = 0; i < AA_ORDER_RANK_MIN - 1; i++)
        s[i] = (aa_sample){uniform(-1, 1), uniform(-1, 1), 1.0 / (AA_ORDER_RANK_MIN - 1)};
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    ws.order_pass = AA_ORDER_RANK_AVX512;
    double dc[4], ds[4], e1[4];
    for (int a = 0; a < 4; a++)
        aa_metric_direction(a * 0.1, &dc[a], &ds[a]);
    assert_int_equal(
        aa_e1_kernel_block(&f, s, AA_ORDER_RANK_MIN - 1, dc, ds, 4, AA_E1_AUTO, &ws, e1), AA_OK);
    assert_int_equal(ws.rank_passes, 0);
    assert_int_equal(ws.insertion_passes, 3);
    aa_metric_workspace_free(&ws);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rank_pass_matches_fresh_sort),
        cmocka_unit_test(test_rank_pass_ties_and_non_finite),
        cmocka_unit_test(test_block_passes_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
