/* The scene objective (objective_scene.h): its gradient against central differences, the
 * descent lowering it, the blend's end points, and cancellation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include "aa_metric.h"
#include "aa_optimizer.h"
#include "aa_pattern.h"

static aa_filter filter;
static aa_acuity acuity;
static aa_metric_params metric;
static aa_scene_objective scene;

static int setup(void **state)
{
    (void)state;
    aa_filter_default(&filter);
    aa_acuity_naiman(&acuity);
    metric = (aa_metric_params){&filter, &acuity, NULL, 0, 0};
    /* Edges at four generic angles (no projections tie there for random samples). */
    scene = (aa_scene_objective){.filter = &filter, .pixels = 256.0 * 256.0};
    scene.length[3] = 300;
    scene.length[31] = 120;
    scene.length[93] = 250;
    scene.length[137] = 60;
    return 0;
}

static void seed_of(const char *label, uint64_t s, aa_pattern *p)
{
    aa_family fam;
    assert_int_equal(aa_family_parse(label, &fam, NULL), AA_OK);
    aa_rng rng;
    aa_rng_seed(&rng, s, 7);
    assert_int_equal(aa_family_seed(&fam, AA_SEED_UNIFORM, &filter, &rng, p, NULL), AA_OK);
}

static double value_of(const aa_pattern *p)
{
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    double v = NAN;
    assert_int_equal(aa_scene_objective_eval(&scene, p, &ws, &v, NULL, NULL, NULL, NULL), AA_OK);
    aa_metric_workspace_free(&ws);
    return v;
}

/* Every sample's x and y, and zero-sum weight pairs, against central differences. */
static void test_gradient_matches_differences(void **state)
{
    (void)state;
    const char *families[] = {"P(1,1,4)", "P(1,4,4)", "P(4,4,2)"};
    for (size_t f = 0; f < 3; f++) {
        aa_pattern p;
        seed_of(families[f], 11 + f, &p);
        size_t n = aa_pattern_total_kernel_samples(&p);
        double *g = malloc(3 * n * sizeof *g), v;
        assert_non_null(g);
        aa_metric_workspace ws;
        aa_metric_workspace_init(&ws);
        assert_int_equal(aa_scene_objective_eval(&scene, &p, &ws, &v, g, g + n, g + 2 * n, NULL),
                         AA_OK);
        aa_metric_workspace_free(&ws);
        assert_true(v > 0);
        const double h = 1e-6;
        size_t off = 0, checked = 0;
        for (size_t k = 0; k < p.kernel_count; k++) {
            aa_kernel *ker = &p.kernels[k];
            for (size_t i = 0; i < ker->count; i++, off++) {
                double *coord[2] = {&ker->samples[i].x, &ker->samples[i].y};
                for (int c = 0; c < 2; c++) {
                    double x0 = *coord[c];
                    *coord[c] = x0 + h;
                    double up = value_of(&p);
                    *coord[c] = x0 - h;
                    double down = value_of(&p);
                    *coord[c] = x0;
                    double fd = (up - down) / (2 * h), an = g[c * n + off];
                    assert_true(fabs(fd - an) <= 1e-5 * (1 + fabs(fd)));
                    checked++;
                }
                if (i + 1 < ker->count) {
                    /* w_i + h, w_{i+1} - h keeps the kernel's sum; the projected gradient's
                     * directional derivative is gw[i] - gw[i+1]. */
                    double wi = ker->samples[i].w, wj = ker->samples[i + 1].w;
                    ker->samples[i].w = wi + h;
                    ker->samples[i + 1].w = wj - h;
                    double up = value_of(&p);
                    ker->samples[i].w = wi - h;
                    ker->samples[i + 1].w = wj + h;
                    double down = value_of(&p);
                    ker->samples[i].w = wi;
                    ker->samples[i + 1].w = wj;
                    double fd = (up - down) / (2 * h), an = g[2 * n + off] - g[2 * n + off + 1];
                    assert_true(fabs(fd - an) <= 1e-5 * (1 + fabs(fd)));
                    checked++;
                }
            }
        }
        assert_true(checked >= 3 * n - p.kernel_count);
        free(g);
        aa_pattern_free(&p);
    }
}

static aa_scene_optimize_params params_of(double blend)
{
    aa_scene_optimize_params sp = {.blend = blend};
    aa_optimize_params_default(&sp.local);
    sp.local.mode = AA_OPTIMIZE_BOTH;
    sp.local.max_iterations = 300;
    sp.local.max_seconds = 0;
    sp.local.stall_iterations = 100;
    return sp;
}

static void test_descent_lowers_scene_term(void **state)
{
    (void)state;
    aa_pattern seed, best;
    seed_of("P(1,1,4)", 5, &seed);
    aa_scene_optimize_params sp = params_of(0);
    aa_scene_optimize_result r;
    assert_int_equal(aa_optimize_scene(&seed, &metric, &scene, &sp, NULL, NULL, &best, &r, NULL),
                     AA_OK);
    assert_true(r.scene < 0.9 * r.initial_scene);
    assert_true(fabs(r.objective - r.scene / r.scene_ref) < 1e-12);
    /* The reported figures are the best pattern's. */
    double f, s, e2;
    assert_int_equal(aa_scene_objective_blend(&best, &metric, &scene, 0, r.scene_ref, r.e2_ref, &f,
                                              &s, &e2, NULL),
                     AA_OK);
    assert_true(fabs(s - r.scene) <= 1e-9 * s && fabs(e2 - r.e2) <= 1e-9 * e2);
    aa_pattern_free(&best);
    /* blend 1: E2 alone, through its smooth stand-in; it must not get worse. */
    sp = params_of(1);
    assert_int_equal(aa_optimize_scene(&seed, &metric, &scene, &sp, NULL, NULL, &best, &r, NULL),
                     AA_OK);
    assert_true(r.e2 < r.initial_e2);
    aa_pattern_free(&best);
    aa_pattern_free(&seed);
}

static int cancel_after(void *user, const aa_scene_progress *pr)
{
    int *calls = user;
    assert_non_null(pr->best);
    return ++*calls >= 1;
}

static void test_cancel_returns_best_so_far(void **state)
{
    (void)state;
    aa_pattern seed, best;
    seed_of("P(1,1,4)", 9, &seed);
    aa_scene_optimize_params sp = params_of(0.5);
    sp.local.max_iterations = 100000000;
    sp.local.stall_iterations = 100000000;
    int calls = 0;
    aa_scene_optimize_result r;
    assert_int_equal(
        aa_optimize_scene(&seed, &metric, &scene, &sp, cancel_after, &calls, &best, &r, NULL),
        AA_ECANCELED);
    assert_true(calls >= 1);
    assert_int_equal(best.kernel_count, seed.kernel_count);
    assert_true(r.objective <= r.initial_objective);
    aa_pattern_free(&best);
    aa_pattern_free(&seed);
}

static void test_bad_inputs(void **state)
{
    (void)state;
    aa_pattern seed, best;
    seed_of("P(1,1,4)", 1, &seed);
    aa_scene_optimize_params sp = params_of(1.5);
    aa_scene_optimize_result r;
    aa_error err = {0};
    assert_int_equal(aa_optimize_scene(&seed, &metric, &scene, &sp, NULL, NULL, &best, &r, &err),
                     AA_EINVAL);
    aa_scene_objective empty = {.pixels = 100};
    sp = params_of(0);
    assert_int_equal(aa_optimize_scene(&seed, &metric, &empty, &sp, NULL, NULL, &best, &r, &err),
                     AA_EINVAL);
    aa_pattern_free(&seed);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gradient_matches_differences),
        cmocka_unit_test(test_descent_lowers_scene_term),
        cmocka_unit_test(test_cancel_returns_best_so_far),
        cmocka_unit_test(test_bad_inputs),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
