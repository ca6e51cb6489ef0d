/* aa_random_patterns (L&A Table 3's random columns): min / avg / max and the best pattern
 * against an independent recomputation (the reference E2 of each pattern drawn from the same
 * stream), the progress cadence, cancellation and bad counts. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "aa_optimizer.h"
#include "reference_e2.h"

static aa_filter filter;
static aa_acuity acuity;
static aa_metric_params metric;
static ref_filter rfilter;

static int setup(void **state)
{
    (void)state;
    aa_filter_default(&filter);
    aa_acuity_naiman(&acuity);
    metric = (aa_metric_params){&filter, &acuity, NULL, 0, 0};
    ref_filter_mitchell(&rfilter, 1.0L / 3, 1.0L / 3, 2.0L);
    return 0;
}

/* Reference E2 of a one-kernel pattern (P(1,1,n): the kernel is the pixel). */
static double reference_e2(const aa_pattern *p)
{
    assert_int_equal(p->kernel_count, 1);
    ref_sample s[64];
    const aa_kernel *k = &p->kernels[0];
    for (size_t i = 0; i < k->count; i++)
        s[i] = (ref_sample){k->samples[i].x, k->samples[i].y, k->samples[i].w};
    double deg;
    return (double)ref_kernel_e2(&rfilter, s, k->count, &deg);
}

static void stats_and_best_match_an_independent_loop(void **state)
{
    (void)state;
    aa_family fam;
    assert_int_equal(aa_family_parse("P(1,1,3)", &fam, NULL), AA_OK);
    const size_t count = 150;
    aa_pattern best;
    aa_random_stats rs;
    size_t best_index;
    assert_int_equal(aa_random_patterns_range(&fam, AA_SEED_POISSON, &metric, 11, 0, count, NULL,
                                              NULL, NULL, &best, &best_index, &rs, NULL),
                     AA_OK);
    /* The same streams, drawn by hand, evaluated by the reference. */
    double mn = INFINITY, mx = -INFINITY, sum = 0;
    for (size_t i = 0; i < count; i++) {
        aa_rng rng;
        aa_rng_seed(&rng, 11, i);
        aa_pattern p;
        assert_int_equal(aa_family_seed(&fam, AA_SEED_POISSON, &filter, &rng, &p, NULL), AA_OK);
        double e2 = reference_e2(&p);
        mn = fmin(mn, e2);
        mx = fmax(mx, e2);
        sum += e2;
        aa_pattern_free(&p);
    }
    assert_int_equal(rs.count, count);
    assert_true(fabs(rs.min - mn) < 1e-9);
    assert_true(fabs(rs.max - mx) < 1e-9);
    assert_true(fabs(rs.avg - sum / count) < 1e-9);
    assert_true(rs.min < rs.avg && rs.avg < rs.max);
    assert_true(fabs(reference_e2(&best) - rs.min) < 1e-9);
    aa_pattern_free(&best);
}

typedef struct progress_log {
    size_t calls, last, cancel_at;
} progress_log;

static int log_progress(void *user, size_t i)
{
    progress_log *l = user;
    l->calls++;
    l->last = i;
    return i >= l->cancel_at;
}

static void progress_every_64_and_cancel(void **state)
{
    (void)state;
    aa_family fam;
    assert_int_equal(aa_family_parse("P(1,4,2)", &fam, NULL), AA_OK);
    aa_pattern best;
    aa_random_stats rs;
    size_t bi;
    progress_log l = {0, 0, SIZE_MAX};
    assert_int_equal(aa_random_patterns_range(&fam, AA_SEED_JITTERED, &metric, 3, 0, 200,
                                              log_progress, &l, NULL, &best, &bi, &rs, NULL),
                     AA_OK);
    assert_int_equal(l.calls, 4); /* after patterns 0, 64, 128, 192 */
    assert_int_equal(l.last, 192);
    aa_pattern_free(&best);

    /* Cancelled after pattern 64: the 65 done so far are kept. */
    progress_log c = {0, 0, 64};
    aa_error err;
    assert_int_equal(aa_random_patterns_range(&fam, AA_SEED_JITTERED, &metric, 3, 0, 200,
                                              log_progress, &c, NULL, &best, &bi, &rs, &err),
                     AA_ECANCELED);
    assert_int_equal(rs.count, 65);
    assert_non_null(best.kernels);
    assert_true(isfinite(rs.min) && rs.min <= rs.avg && rs.avg <= rs.max);
    aa_pattern_free(&best);

    assert_int_equal(aa_random_patterns_range(&fam, AA_SEED_JITTERED, &metric, 3, 0, 0, NULL, NULL,
                                              NULL, &best, &bi, &rs, &err),
                     AA_EINVAL);
    assert_string_equal(err.field, "count");
    assert_null(best.kernels);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(stats_and_best_match_an_independent_loop),
        cmocka_unit_test(progress_every_64_and_cancel),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
