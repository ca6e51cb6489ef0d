/* Seed and pattern ranges: a multi-start over seeds [0,k) plus one over [k,n) gives, seed for
 * seed, the results of one run over [0,n) (plain, perturbed and screened mirrored runs), and
 * random patterns split into index ranges are the patterns of one run. What the job shards
 * (job_split.h) rely on for results that do not depend on the number of shards. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "aa_core.h"
#include "aa_optimizer.h"
#include "aa_pattern.h"

static aa_filter filter;
static aa_acuity acuity;
static aa_metric_params metric;

static int setup(void **state)
{
    (void)state;
    aa_filter_default(&filter);
    aa_acuity_naiman(&acuity);
    metric = (aa_metric_params){&filter, &acuity, NULL, 0, 0};
    return 0;
}

typedef struct range_case {
    const char *family;
    long iterations;
    long perturb_rounds;
    size_t screen_top; /* 0: no screening */
} range_case;

static void run_range(const range_case *c, size_t first, size_t count, int workers,
                      aa_pattern *best, aa_multistart_result *r)
{
    aa_family fam;
    assert_int_equal(aa_family_parse(c->family, &fam, NULL), AA_OK);
    aa_multistart_params mp;
    aa_multistart_params_default(&mp);
    mp.family = &fam;
    mp.first_seed = first;
    mp.seed_count = count;
    mp.workers = workers;
    mp.rng_seed = 7;
    mp.max_seconds = 0;
    mp.local.max_iterations = c->iterations;
    mp.perturb.rounds = c->perturb_rounds;
    mp.perturb.stall = 2;
    if (c->screen_top) {
        mp.screen_iterations = 20;
        mp.screen_top = c->screen_top;
    }
    assert_int_equal(aa_multistart(&mp, &metric, NULL, NULL, best, r, NULL), AA_OK);
}

/* Bit-identical patterns: every kernel's samples (positions and weights). */
static void pattern_equal(const aa_pattern *a, const aa_pattern *b)
{
    assert_int_equal(a->kernel_count, b->kernel_count);
    for (size_t k = 0; k < a->kernel_count; k++) {
        assert_int_equal(a->kernels[k].count, b->kernels[k].count);
        assert_memory_equal(a->kernels[k].samples, b->kernels[k].samples,
                            a->kernels[k].count * sizeof *a->kernels[k].samples);
    }
}

static void seed_equal(const aa_multistart_seed *a, const aa_multistart_seed *b)
{
    assert_int_equal(a->distribution, b->distribution);
    assert_int_equal(a->status, b->status);
    assert_memory_equal(&a->initial_e2, &b->initial_e2, sizeof a->initial_e2);
    assert_memory_equal(&a->e2, &b->e2, sizeof a->e2);
    assert_int_equal(a->iterations, b->iterations);
}

static void split_matches_whole(const range_case *c, size_t n, size_t k)
{
    aa_pattern whole, lo, hi;
    aa_multistart_result rw, rl, rh;
    run_range(c, 0, n, 2, &whole, &rw);
    run_range(c, 0, k, 1, &lo, &rl);
    run_range(c, k, n - k, 2, &hi, &rh);
    for (size_t i = 0; i < k; i++)
        seed_equal(&rw.per_seed[i], &rl.per_seed[i]);
    for (size_t i = k; i < n; i++)
        seed_equal(&rw.per_seed[i], &rh.per_seed[i - k]);
    /* The better half holds the whole run's best, with its global index. */
    const aa_multistart_result *winner = rh.e2 < rl.e2 ? &rh : &rl;
    const aa_pattern *wp = rh.e2 < rl.e2 ? &hi : &lo;
    assert_memory_equal(&winner->e2, &rw.e2, sizeof rw.e2);
    assert_int_equal(winner->best_seed, rw.best_seed);
    pattern_equal(wp, &whole);
    if (rw.best_seed != SIZE_MAX)
        assert_true(rw.best_seed < n);
    aa_pattern_free(&whole);
    aa_pattern_free(&lo);
    aa_pattern_free(&hi);
    aa_multistart_result_free(&rw);
    aa_multistart_result_free(&rl);
    aa_multistart_result_free(&rh);
}

static void plain_range_split(void **state)
{
    (void)state;
    range_case c = {"P(1,1,3)", 60, 0, 0};
    split_matches_whole(&c, 7, 3);
}

static void perturbed_range_split(void **state)
{
    (void)state;
    range_case c = {"P(4,4,1)", 40, 3, 0};
    split_matches_whole(&c, 4, 1);
}

static void screened_range_split(void **state)
{
    (void)state;
    range_case c = {"P(4,1+,1.5)", 60, 0, 3};
    split_matches_whole(&c, 6, 4);
}

static void random_pattern_ranges_match_one_run(void **state)
{
    (void)state;
    aa_family fam;
    assert_int_equal(aa_family_parse("P(1,1,3)", &fam, NULL), AA_OK);
    enum { N = 40, K = 13 };
    double whole[N], parts[N];
    aa_pattern bw, b1, b2;
    size_t iw, i1, i2;
    aa_random_stats sw, s1, s2;
    assert_int_equal(aa_random_patterns_range(&fam, AA_SEED_UNIFORM, &metric, 5, 0, N, NULL, NULL,
                                              whole, &bw, &iw, &sw, NULL),
                     AA_OK);
    assert_int_equal(aa_random_patterns_range(&fam, AA_SEED_UNIFORM, &metric, 5, 0, K, NULL, NULL,
                                              parts, &b1, &i1, &s1, NULL),
                     AA_OK);
    assert_int_equal(aa_random_patterns_range(&fam, AA_SEED_UNIFORM, &metric, 5, K, N - K, NULL,
                                              NULL, parts + K, &b2, &i2, &s2, NULL),
                     AA_OK);
    assert_memory_equal(whole, parts, sizeof whole);
    aa_random_stats merged = aa_random_stats_of(parts, N);
    assert_memory_equal(&merged.min, &sw.min, sizeof sw.min);
    assert_memory_equal(&merged.avg, &sw.avg, sizeof sw.avg);
    assert_memory_equal(&merged.max, &sw.max, sizeof sw.max);
    assert_int_equal(merged.count, N);
    size_t bi = s2.min < s1.min ? i2 : i1;
    const aa_pattern *bp = s2.min < s1.min ? &b2 : &b1;
    assert_int_equal(bi, iw);
    pattern_equal(bp, &bw);
    aa_pattern_free(&bw);
    aa_pattern_free(&b1);
    aa_pattern_free(&b2);
}

/* seed_iterations bounds a seed's descent and its refinement together (the clock-free budget
 * seeds x max_iterations), where the refinement alone would run until it stalls. */
static void seed_iterations_bound_the_refinement(void **state)
{
    (void)state;
    aa_family fam;
    assert_int_equal(aa_family_parse("P(4,4,1)", &fam, NULL), AA_OK);
    aa_multistart_params mp;
    aa_multistart_params_default(&mp);
    mp.family = &fam;
    mp.seed_count = 2;
    mp.rng_seed = 3;
    mp.max_seconds = 0;
    mp.local.max_iterations = 60;
    mp.perturb.rounds = AA_PERTURB_UNTIL_STALL;
    aa_pattern best;
    aa_multistart_result unbounded, bounded;
    assert_int_equal(aa_multistart(&mp, &metric, NULL, NULL, &best, &unbounded, NULL), AA_OK);
    aa_pattern_free(&best);
    mp.seed_iterations = 100;
    assert_int_equal(aa_multistart(&mp, &metric, NULL, NULL, &best, &bounded, NULL), AA_OK);
    aa_pattern_free(&best);
    for (size_t i = 0; i < 2; i++) {
        assert_true(unbounded.per_seed[i].iterations > 100); /* the case is not vacuous */
        assert_true(bounded.per_seed[i].iterations <= 100);
        assert_true(bounded.per_seed[i].iterations > 60); /* the refinement did run */
    }
    assert_true(bounded.iterations <= 200);
    aa_multistart_result_free(&unbounded);
    aa_multistart_result_free(&bounded);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(plain_range_split),
        cmocka_unit_test(perturbed_range_split),
        cmocka_unit_test(screened_range_split),
        cmocka_unit_test(random_pattern_ranges_match_one_run),
        cmocka_unit_test(seed_iterations_bound_the_refinement),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
