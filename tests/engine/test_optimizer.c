/* Optimizer: gradient direction, site constraints, determinism, cancellation, monotone trace;
 * the structural tests run for every step rule (laine-aila, minimax, smooth). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "aa_core.h"
#include "aa_pattern.h"
#include "aa_optimizer.h"
#include "test_small.h"

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

static const aa_optimize_method methods[] = {AA_METHOD_LAINE_AILA, AA_METHOD_MINIMAX,
                                             AA_METHOD_SMOOTH};
#define METHOD_COUNT (sizeof methods / sizeof methods[0])

static void seed_of(const char *label, uint64_t s, aa_pattern *p)
{
    aa_family fam;
    assert_int_equal(aa_family_parse(label, &fam, NULL), AA_OK);
    aa_rng rng;
    aa_rng_seed(&rng, s, 3);
    assert_int_equal(aa_family_seed(&fam, AA_SEED_JITTERED, &filter, &rng, p, NULL), AA_OK);
}

static void small_step_against_gradient_lowers_e1(void **state)
{
    (void)state;
    aa_pattern p;
    seed_of("P(1,4,3)", 11, &p);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    const aa_kernel *k = &p.kernels[0];
    size_t n = k->count;
    double *dx = malloc(n * sizeof *dx), *dy = malloc(n * sizeof *dy), *dw = malloc(n * sizeof *dw);
    aa_sample *moved = malloc(n * sizeof *moved);
    for (int a = 0; a < 36; a += 5) {
        double th = a * 5 * 3.14159265358979323846 / 180, e1, e1m;
        assert_int_equal(aa_e1_gradient_at_angle(&filter, k->samples, n, th, &ws, &e1, dx, dy, dw),
                         AA_OK);
        double h = 1e-4;
        for (size_t i = 0; i < n; i++)
            moved[i] = (aa_sample){k->samples[i].x - h * dx[i], k->samples[i].y - h * dy[i],
                                   k->samples[i].w - h * dw[i]};
        assert_int_equal(aa_e1_at_angle(&filter, moved, n, th, &ws, &e1m), AA_OK);
        assert_true(e1m < e1);
    }
    free(dx);
    free(dy);
    free(dw);
    free(moved);
    aa_metric_workspace_free(&ws);
    aa_pattern_free(&p);
}

static void optimize_never_raises_e2(void **state)
{
    (void)state;
    const char *fams[] = {"P(1,1,3)", "P(4,1+,2)", "P(1,4,2)", "P(4,4,1)"};
    aa_optimize_mode modes[] = {AA_OPTIMIZE_WEIGHTS, AA_OPTIMIZE_POSITIONS, AA_OPTIMIZE_BOTH};
    for (size_t f = 0; f < 4; f++) {
        for (size_t m = 0; m < 3 * METHOD_COUNT; m++) {
            aa_pattern seed, best;
            seed_of(fams[f], 5 + f, &seed);
            aa_optimize_params op;
            aa_optimize_params_default(&op);
            op.mode = modes[m % 3];
            op.method = methods[m / 3];
            op.max_iterations = 150;
            op.max_seconds = 0;
            aa_optimize_result r;
            assert_int_equal(aa_optimize(&seed, &metric, &op, NULL, NULL, &best, &r, NULL), AA_OK);
            assert_true(r.e2 <= r.initial_e2 + 1e-12);
            assert_true(r.e2 < r.initial_e2); /* 150 steps from a random seed always help */
            aa_pattern_free(&seed);
            aa_pattern_free(&best);
        }
    }
}

/* A P(4,1+,n) seed with one corner, two edge and one interior sample (uniform, rng stream 9). */
static void mirrored_test_seed(aa_pattern *seed)
{
    aa_mirrored_config c = {{1, 0, 0, 0}, {0, 2, 1, 0}, 1};
    aa_rng rng;
    aa_rng_seed(&rng, 9, 0);
    assert_int_equal(aa_mirrored_config_seed(&c, AA_SEED_UNIFORM, &filter, &rng, seed, NULL),
                     AA_OK);
}

/* A clock that advances one "second" per reading: the budget and the reported seconds follow
 * the caller's clock, not the wall clock (a paused run's clock stands still). */
static double counting_clock(void *user)
{
    double *t = user;
    return *t += 1.0;
}

static void budget_follows_the_given_clock(void **state)
{
    (void)state;
    aa_pattern seed, best;
    mirrored_test_seed(&seed);
    aa_optimize_params op;
    aa_optimize_params_default(&op);
    op.max_iterations = 1000000;
    op.stall_iterations = 1000000;
    op.max_seconds = 40;
    double t = 0;
    op.clock = (aa_clock){counting_clock, &t};
    aa_optimize_result r;
    assert_int_equal(aa_optimize(&seed, &metric, &op, NULL, NULL, &best, &r, NULL), AA_OK);
    /* One reading per step: the run ends after about 40 steps, and says 40-odd seconds. */
    assert_true(r.iterations >= 30 && r.iterations <= 45);
    assert_true(r.seconds >= 40 && r.seconds <= 50);
    aa_pattern_free(&best);
    /* With the budget far away, max_iterations ends the run. */
    op.max_iterations = 60;
    t = 0;
    op.clock = (aa_clock){counting_clock, &t};
    op.max_seconds = 1e9;
    assert_int_equal(aa_optimize(&seed, &metric, &op, NULL, NULL, &best, &r, NULL), AA_OK);
    assert_int_equal(r.iterations, 60);
    aa_pattern_free(&best);
    aa_pattern_free(&seed);
}

static void mirrored_sites_are_preserved_by(aa_optimize_method method)
{
    aa_pattern seed, best;
    mirrored_test_seed(&seed);
    aa_optimize_params op;
    aa_optimize_params_default(&op);
    op.method = method;
    op.max_iterations = 300;
    op.max_seconds = 0;
    aa_optimize_result r;
    assert_int_equal(aa_optimize(&seed, &metric, &op, NULL, NULL, &best, &r, NULL), AA_OK);
    assert_int_equal(best.form, AA_FORM_MIRRORED);
    assert_int_equal(best.source_count, seed.source_count);
    assert_true(fabs(best.cost_spp - seed.cost_spp) < 1e-12);
    double wsum = 0;
    int moved = 0;
    for (size_t i = 0; i < seed.source_count; i++) {
        const aa_sample *a = &seed.source[i], *b = &best.source[i];
        bool ax = fabs(fabs(a->x) - 0.5) < 1e-9, ay = fabs(fabs(a->y) - 0.5) < 1e-9;
        if (ax)
            assert_true(b->x == a->x); /* on a vertical edge or corner: x fixed */
        else
            assert_true(fabs(b->x) < 0.5);
        if (ay)
            assert_true(b->y == a->y);
        else
            assert_true(fabs(b->y) < 0.5);
        moved += b->x != a->x || b->y != a->y;
        wsum += b->w;
    }
    assert_true(moved > 0);
    assert_true(fabs(wsum - 1) < 1e-9);
    /* Mirror structure: every kernel is the source mirrored. */
    for (size_t k = 0; k < 4; k++)
        for (size_t i = 0; i < best.source_count; i++)
            assert_true(fabs(fabs(best.kernels[k].samples[i].x) - fabs(best.source[i].x)) < 1e-12);
    aa_pattern_free(&seed);
    aa_pattern_free(&best);
}

static void mirrored_sites_are_preserved(void **state)
{
    (void)state;
    for (size_t m = 0; m < METHOD_COUNT; m++)
        mirrored_sites_are_preserved_by(methods[m]);
}

static void tile_sites_and_pixels_are_preserved(void **state)
{
    (void)state;
    const char *fams[] = {"P(1,1+,3)", "P(4,4,2)"};
    for (size_t f = 0; f < 2 * METHOD_COUNT; f++) {
        aa_pattern seed, best;
        seed_of(fams[f % 2], 21, &seed);
        aa_optimize_params op;
        aa_optimize_params_default(&op);
        op.method = methods[f / 2];
        op.max_iterations = 200;
        op.max_seconds = 0;
        aa_optimize_result r;
        assert_int_equal(aa_optimize(&seed, &metric, &op, NULL, NULL, &best, &r, NULL), AA_OK);
        assert_int_equal(best.tile_count, seed.tile_count);
        assert_string_equal(best.family, seed.family);
        for (size_t t = 0; t < seed.tile_count; t++) {
            /* from_tile may renumber samples: find the one in the same pixel with the same site
             * nearest to the seed's. */
            aa_point a = seed.tile_samples[t];
            double bd = INFINITY;
            size_t bi = 0;
            for (size_t u = 0; u < best.tile_count; u++) {
                aa_point b = best.tile_samples[u];
                double d = hypot(b.x - a.x, b.y - a.y);
                if (floor(b.x + 1e-9) == floor(a.x + 1e-9) &&
                    floor(b.y + 1e-9) == floor(a.y + 1e-9) &&
                    best.tile_site[u] == seed.tile_site[t] && d < bd) {
                    bd = d;
                    bi = u;
                }
            }
            assert_true(bd < INFINITY);
            aa_point b = best.tile_samples[bi];
            if (seed.tile_site[t] == AA_SITE_VERTICAL_EDGE || seed.tile_site[t] == AA_SITE_CORNER)
                assert_true(fabs(b.x - a.x) < 1e-9);
            if (seed.tile_site[t] == AA_SITE_HORIZONTAL_EDGE || seed.tile_site[t] == AA_SITE_CORNER)
                assert_true(fabs(b.y - a.y) < 1e-9);
        }
        for (size_t k = 0; k < best.kernel_count; k++) {
            double s = 0;
            for (size_t i = 0; i < best.kernels[k].count; i++)
                s += best.kernels[k].samples[i].w;
            assert_true(fabs(s - 1) < 1e-9);
        }
        aa_pattern_free(&seed);
        aa_pattern_free(&best);
    }
}

/* Iterated local search: never worse than its start, same family and per-pixel structure,
 * deterministic for a given rng state, refused where samples sit on borders. */
static void check_perturbed_search(int redraw, bool keep_pixels)
{
    aa_pattern seed, local, a, b;
    seed_of("P(4,4,2)", 5, &seed);
    aa_optimize_params op;
    aa_optimize_params_default(&op);
    op.max_iterations = 300;
    op.max_seconds = 0;
    aa_optimize_result r, ra, rb;
    assert_int_equal(aa_optimize(&seed, &metric, &op, NULL, NULL, &local, &r, NULL), AA_OK);
    assert_true(aa_perturbable(&local));
    aa_perturb_params pp;
    aa_perturb_params_default(&pp);
    pp.rounds = test_small() ? 4 : 8; /* small: half the rounds, every move still made */
    pp.sigma = 0.02;
    pp.redraw = redraw;
    pp.keep_pixels = keep_pixels;
    aa_rng rng;
    aa_rng_seed(&rng, 9, 1);
    assert_int_equal(
        aa_optimize_perturbed(&local, &metric, &op, &pp, &rng, NULL, NULL, &a, &ra, NULL), AA_OK);
    aa_rng_seed(&rng, 9, 1);
    assert_int_equal(
        aa_optimize_perturbed(&local, &metric, &op, &pp, &rng, NULL, NULL, &b, &rb, NULL), AA_OK);
    assert_true(ra.e2 <= r.e2);
    assert_true(fabs(ra.initial_e2 - r.e2) < 1e-12);
    assert_true(ra.e2 == rb.e2);
    assert_true(ra.iterations > 0);
    assert_int_equal(a.tile_count, local.tile_count);
    assert_memory_equal(a.tile_samples, b.tile_samples, a.tile_count * sizeof *a.tile_samples);
    assert_string_equal(a.family, local.family);
    /* Samples may change pixels (the jitter crosses edges) but every one stays strictly inside
     * a pixel of the tile, so no sample becomes an edge or corner sample. */
    for (size_t t = 0; t < a.tile_count; t++) {
        const double c[2] = {a.tile_samples[t].x, a.tile_samples[t].y};
        for (int k = 0; k < 2; k++) {
            assert_true(c[k] >= 0 && c[k] < 2);
            assert_true(c[k] - floor(c[k]) > 1e-7 && c[k] - floor(c[k]) < 1 - 1e-7);
        }
    }
    assert_false(a.border);
    if (keep_pixels) { /* every pixel of the 2x2 tile keeps its number of samples */
        int per_pixel[4] = {0}, before[4] = {0};
        for (size_t t = 0; t < a.tile_count; t++) {
            per_pixel[(int)floor(a.tile_samples[t].y) * 2 + (int)floor(a.tile_samples[t].x)]++;
            before[(int)floor(local.tile_samples[t].y) * 2 + (int)floor(local.tile_samples[t].x)]++;
        }
        for (int px = 0; px < 4; px++)
            assert_int_equal(per_pixel[px], before[px]);
    }
    aa_evaluation ev;
    assert_int_equal(aa_evaluate(&a, &metric, &ev, NULL), AA_OK);
    assert_true(fabs(ev.e2 - ra.e2) < 1e-12);
    aa_evaluation_free(&ev);

    aa_pattern border, out;
    seed_of("P(1,1+,3)", 5, &border);
    assert_false(aa_perturbable(&border));
    aa_error err = {0};
    assert_int_equal(
        aa_optimize_perturbed(&border, &metric, &op, &pp, &rng, NULL, NULL, &out, &ra, &err),
        AA_EINVAL);
    aa_pattern_free(&border);
    aa_pattern_free(&seed);
    aa_pattern_free(&local);
    aa_pattern_free(&a);
    aa_pattern_free(&b);
}

static void perturbed_search_keeps_structure_and_is_deterministic(void **state)
{
    (void)state;
    check_perturbed_search(0, false);
    check_perturbed_search(3, false); /* with samples drawn afresh in their pixels */
    check_perturbed_search(0, true);  /* the move that keeps samples in their pixels */
}

/* Progress of a descent-then-search stage: what the caller saw, checked as it comes. */
typedef struct stage_watch {
    int calls;
    double fraction;
    long iterations;
} stage_watch;

static int watch_stage(void *user, const aa_optimize_progress *p)
{
    stage_watch *w = user;
    assert_true(p->fraction >= w->fraction && p->fraction <= 1);
    assert_true(p->iterations >= w->iterations);
    w->fraction = p->fraction;
    w->iterations = p->iterations;
    w->calls++;
    return 0;
}

/* aa_optimize_refined is the descent, then the search for the rest of the stage's steps, as
 * one run: the same pattern and counts as the two calls made by hand, and a progress whose
 * fraction (steps spent of the stage's) and counters never step back across the two. */
static void refined_stage_is_descent_then_search(void **state)
{
    (void)state;
    aa_pattern seed, by_hand, descended, refined;
    seed_of("P(4,4,2)", 5, &seed);
    aa_optimize_params op;
    aa_optimize_params_default(&op);
    op.max_iterations = 400;
    op.max_seconds = 0;
    op.stall_iterations = 100;
    const long stage_steps = 1500;
    aa_perturb_params pp;
    aa_perturb_params_default(&pp);
    pp.rounds = AA_PERTURB_UNTIL_STALL;
    pp.stall = 4;
    aa_rng rng;
    aa_rng_seed(&rng, 3, 7);
    stage_watch w = {0, 0, 0};
    aa_optimize_result r, rd, rs;
    assert_int_equal(aa_optimize_refined(&seed, &metric, &op, stage_steps, &pp, &rng, watch_stage,
                                         &w, &refined, &r, NULL),
                     AA_OK);
    assert_true(w.calls > 0);
    assert_true(r.iterations <= stage_steps);
    assert_true(w.iterations <= r.iterations);
    assert_true(w.fraction <= (double)r.iterations / (double)stage_steps + 1e-12);

    assert_int_equal(aa_optimize(&seed, &metric, &op, NULL, NULL, &descended, &rd, NULL), AA_OK);
    assert_true(rd.iterations < stage_steps); /* the search ran: the case under test */
    aa_perturb_params rest = pp;
    rest.max_iterations = stage_steps - rd.iterations;
    aa_rng_seed(&rng, 3, 7);
    assert_int_equal(aa_optimize_perturbed(&descended, &metric, &op, &rest, &rng, NULL, NULL,
                                           &by_hand, &rs, NULL),
                     AA_OK);
    assert_true(rs.iterations > 0);
    assert_int_equal(r.iterations, rd.iterations + rs.iterations);
    assert_true(r.e2 == rs.e2);
    assert_memory_equal(refined.tile_samples, by_hand.tile_samples,
                        refined.tile_count * sizeof *refined.tile_samples);
    aa_pattern_free(&seed);
    aa_pattern_free(&descended);
    aa_pattern_free(&by_hand);
    aa_pattern_free(&refined);
}

static void run_multistart_of(const char *label, size_t seeds, uint64_t rng_seed, long iterations,
                              long perturb_rounds, int workers, aa_pattern *best,
                              aa_multistart_result *r)
{
    aa_family fam;
    assert_int_equal(aa_family_parse(label, &fam, NULL), AA_OK);
    aa_multistart_params mp;
    aa_multistart_params_default(&mp);
    mp.family = &fam;
    mp.seed_count = seeds;
    mp.workers = workers;
    mp.rng_seed = rng_seed;
    mp.max_seconds = 0;
    mp.local.max_iterations = iterations;
    mp.perturb.rounds = perturb_rounds;
    assert_int_equal(aa_multistart(&mp, &metric, NULL, NULL, best, r, NULL), AA_OK);
}

static void run_multistart(int workers, aa_pattern *best, aa_multistart_result *r)
{
    run_multistart_of("P(4,1+,1.5)", 6, 42, 150, 0, workers, best, r);
}

/* Multi-start with the refinement on: the same result for 1 and 2 workers. */
static void perturbed_multistart_is_deterministic(void **state)
{
    (void)state;
    double e2[2];
    for (int w = 1; w <= 2; w++) {
        aa_pattern best;
        aa_multistart_result r;
        run_multistart_of("P(4,4,1)", 4, 3, 100, 4, w, &best, &r);
        e2[w - 1] = r.e2;
        aa_pattern_free(&best);
        aa_multistart_result_free(&r);
    }
    assert_true(e2[0] == e2[1]);
}

/* Seeds from a pool: the best of 12 draws starts lower than one draw (mean over 6 seeds), and
 * the result is the same for 1 and 2 workers. */
static void pooled_seeds_start_lower_and_are_deterministic(void **state)
{
    (void)state;
    aa_family fam;
    assert_int_equal(aa_family_parse("P(4,4,1)", &fam, NULL), AA_OK);
    double mean_start[2] = {0, 0}, e2[2];
    for (int run = 0; run < 3; run++) {
        aa_multistart_params mp;
        aa_multistart_params_default(&mp);
        mp.family = &fam;
        mp.seed_count = 6;
        mp.workers = run == 2 ? 2 : 1;
        mp.rng_seed = 7;
        mp.max_seconds = 0;
        mp.local.max_iterations = 60;
        mp.seed_pool = run == 0 ? 1 : 12;
        aa_pattern best;
        aa_multistart_result r;
        assert_int_equal(aa_multistart(&mp, &metric, NULL, NULL, &best, &r, NULL), AA_OK);
        assert_int_equal(r.seeds_run, 6);
        if (run < 2)
            for (size_t i = 0; i < 6; i++)
                mean_start[run] += r.per_seed[i].initial_e2 / 6;
        if (run > 0)
            e2[run - 1] = r.e2;
        aa_pattern_free(&best);
        aa_multistart_result_free(&r);
    }
    assert_true(mean_start[1] < mean_start[0]);
    assert_true(e2[0] == e2[1]);
}

static void multistart_is_deterministic(void **state)
{
    (void)state;
    aa_pattern a, b, c;
    aa_multistart_result ra, rb, rc;
    run_multistart(2, &a, &ra);
    run_multistart(2, &b, &rb);
    run_multistart(1, &c, &rc);
    assert_true(ra.e2 == rb.e2);
    assert_true(ra.e2 == rc.e2);
    assert_int_equal(ra.best_seed, rb.best_seed);
    assert_int_equal(a.source_count, b.source_count);
    assert_memory_equal(a.source, b.source, a.source_count * sizeof *a.source);
    assert_memory_equal(a.source, c.source, a.source_count * sizeof *a.source);
    for (size_t i = 0; i < ra.seed_count; i++)
        assert_true(ra.per_seed[i].e2 == rb.per_seed[i].e2);
    aa_pattern_free(&a);
    aa_pattern_free(&b);
    aa_pattern_free(&c);
    aa_multistart_result_free(&ra);
    aa_multistart_result_free(&rb);
    aa_multistart_result_free(&rc);
}

/* Every step rule is deterministic without a time budget: the same seed, the same result. */
static void every_method_is_deterministic(void **state)
{
    (void)state;
    for (size_t m = 0; m < METHOD_COUNT; m++) {
        aa_pattern seed, a, b;
        seed_of("P(4,4,2)", 17, &seed);
        aa_optimize_params op;
        aa_optimize_params_default(&op);
        op.method = methods[m];
        op.max_iterations = 120;
        op.max_seconds = 0;
        aa_optimize_result ra, rb;
        assert_int_equal(aa_optimize(&seed, &metric, &op, NULL, NULL, &a, &ra, NULL), AA_OK);
        assert_int_equal(aa_optimize(&seed, &metric, &op, NULL, NULL, &b, &rb, NULL), AA_OK);
        assert_true(ra.e2 == rb.e2);
        assert_int_equal(ra.iterations, rb.iterations);
        assert_memory_equal(a.tile_samples, b.tile_samples, a.tile_count * sizeof *a.tile_samples);
        for (size_t k = 0; k < a.kernel_count; k++)
            assert_memory_equal(a.kernels[k].samples, b.kernels[k].samples,
                                a.kernels[k].count * sizeof *a.kernels[k].samples);
        aa_pattern_free(&seed);
        aa_pattern_free(&a);
        aa_pattern_free(&b);
    }
}

typedef struct cancel_probe {
    double start, cancelled_at;
    int calls;
    double last_e2;
    int nonmonotone;
    int improvements;
} cancel_probe;

static int cancel_after_50ms(void *user, const aa_optimize_progress *p)
{
    cancel_probe *c = user;
    c->calls++;
    if (p->best_e2 > c->last_e2 + 1e-15)
        c->nonmonotone++;
    c->last_e2 = p->best_e2;
    if (aa_monotonic_seconds() - c->start >= 0.05) {
        c->cancelled_at = aa_monotonic_seconds();
        return 1;
    }
    return 0;
}

static void cancel_stops_within_100ms(void **state)
{
    (void)state;
    aa_pattern seed, best;
    seed_of("P(16,16,4)", 3, &seed);
    int rc;
    double stopped;
    for (size_t m = 0; m < METHOD_COUNT; m++) {
        aa_optimize_params op;
        aa_optimize_params_default(&op);
        op.method = methods[m];
        op.max_iterations = 1000000;
        op.max_seconds = 60;
        cancel_probe c = {aa_monotonic_seconds(), 0, 0, INFINITY, 0, 0};
        aa_optimize_result r;
        rc = aa_optimize(&seed, &metric, &op, cancel_after_50ms, &c, &best, &r, NULL);
        stopped = aa_monotonic_seconds();
        assert_int_equal(rc, AA_ECANCELED);
        assert_true(c.cancelled_at > 0);
        assert_true(stopped - c.cancelled_at < 0.1);
        assert_int_equal(c.nonmonotone, 0);
        assert_non_null(best.kernels); /* best so far is handed back */
        aa_pattern_free(&best);
    }

    aa_family fam;
    assert_int_equal(aa_family_parse("P(16,16,4)", &fam, NULL), AA_OK);
    aa_multistart_params mp;
    aa_multistart_params_default(&mp);
    mp.family = &fam;
    mp.seed_count = 8;
    mp.workers = 2;
    mp.max_seconds = 60;
    mp.local.max_iterations = 1000000;
    cancel_probe c2 = {aa_monotonic_seconds(), 0, 0, INFINITY, 0, 0};
    aa_multistart_result mr;
    rc = aa_multistart(&mp, &metric, cancel_after_50ms, &c2, &best, &mr, NULL);
    stopped = aa_monotonic_seconds();
    assert_int_equal(rc, AA_ECANCELED);
    assert_true(stopped - c2.cancelled_at < 0.1);
    aa_pattern_free(&best);
    aa_multistart_result_free(&mr);
    aa_pattern_free(&seed);
}

/* Every field of the progress reports of one call, in order. */
typedef struct report_log {
    int calls, backwards;
    double seconds, fraction, lowest_e2, last_e2;
    long iterations, evaluations;
} report_log;

static int log_reports(void *user, const aa_optimize_progress *p)
{
    report_log *l = user;
    if (l->calls > 0 && (p->seconds < l->seconds || p->iterations < l->iterations ||
                         p->evaluations < l->evaluations || p->fraction < l->fraction - 1e-12 ||
                         p->best_e2 > l->last_e2 + 1e-12)) /* the final E2 is re-evaluated */
        l->backwards++;
    l->calls++;
    l->seconds = p->seconds;
    l->iterations = p->iterations;
    l->evaluations = p->evaluations;
    l->fraction = p->fraction;
    l->last_e2 = p->best_e2;
    l->lowest_e2 = fmin(l->lowest_e2, p->best_e2);
    return 0;
}

/* Runs mp with log_reports into *l and checks what every multi-start's reports must show:
 * nothing goes backwards, the result is the best reported, and the last report is the result. */
static void run_logged(const aa_multistart_params *mp, report_log *l, aa_pattern *best,
                       aa_multistart_result *r)
{
    *l = (report_log){0, 0, 0, 0, INFINITY, INFINITY, 0, 0};
    assert_int_equal(aa_multistart(mp, &metric, log_reports, l, best, r, NULL), AA_OK);
    assert_true(l->calls >= 1);
    assert_int_equal(l->backwards, 0);
    assert_true(fabs(l->last_e2 - r->e2) < 1e-12);
    assert_true(r->e2 <= l->lowest_e2 + 1e-12);
}

/* Plain and refined (iterated local search) multi-starts on 2 workers: seconds, iterations,
 * evaluations and fraction never go back, best E2 never rises, the last report is the result. */
static void trace_is_monotone(void **state)
{
    (void)state;
    const char *families[] = {"P(1,4,2)", "P(4,4,1)"};
    for (size_t f = 0; f < 2; f++)
        for (size_t m = 0; m < METHOD_COUNT; m++) {
            aa_family fam;
            assert_int_equal(aa_family_parse(families[f], &fam, NULL), AA_OK);
            aa_multistart_params mp;
            aa_multistart_params_default(&mp);
            mp.family = &fam;
            mp.seed_count = f ? 3 : 6;
            mp.workers = 2;
            mp.max_seconds = 0;
            mp.local.method = methods[m];
            /* small: a fifth of the steps, still many reports from both workers */
            mp.local.max_iterations = (m == 0 ? 3000 : 300) / (test_small() ? 5 : 1);
            if (f) { /* P(4,4,1): refined by a few perturbation rounds */
                mp.local.max_iterations = 100;
                mp.perturb.rounds = 3;
            }
            report_log l;
            aa_pattern best;
            aa_multistart_result r;
            run_logged(&mp, &l, &best, &r);
            assert_int_equal(l.iterations, r.iterations);
            assert_int_equal(l.evaluations, r.evaluations);
            aa_pattern_free(&best);
            aa_multistart_result_free(&r);
        }
}

/* A screened run (mirrored family: every configuration briefly, then seeds on the best few)
 * reports as one run: nothing goes backwards between its phases, and its result is the best it
 * reported, even when the focused seeds end above the best screened configuration (here they
 * get 2 steps each against the screening's 150). */
static void screened_run_reports_one_monotone_trace(void **state)
{
    (void)state;
    aa_family fam;
    assert_int_equal(aa_family_parse("P(4,1+,2)", &fam, NULL), AA_OK);
    for (int short_focus = 0; short_focus < 2; short_focus++)
        for (size_t m = 0; m < METHOD_COUNT; m++) {
            aa_multistart_params mp;
            aa_multistart_params_default(&mp);
            mp.family = &fam;
            mp.seed_count = 4;
            mp.workers = 2;
            mp.max_seconds = 0;
            mp.screen_iterations = 150;
            mp.screen_top = 4;
            mp.local.method = methods[m];
            mp.local.max_iterations = short_focus ? 2 : 400;
            report_log l;
            aa_pattern best;
            aa_multistart_result r;
            run_logged(&mp, &l, &best, &r);
            assert_true(l.calls >= 2);
            assert_true(fabs(l.fraction - 1) < 1e-12);
            aa_evaluation ev;
            assert_int_equal(aa_evaluate(&best, &metric, &ev, NULL), AA_OK);
            assert_true(fabs(ev.e2 - r.e2) < 1e-12);
            aa_evaluation_free(&ev);
            if (short_focus) /* 2 steps cannot beat 150: the screening's best is the result */
                assert_true(r.best_seed == SIZE_MAX);
            aa_pattern_free(&best);
            aa_multistart_result_free(&r);
        }
}

static void grid_snapping_reports_quantisation(void **state)
{
    (void)state;
    aa_pattern seed, best;
    seed_of("P(4,1+,2)", 8, &seed);
    aa_optimize_params op;
    aa_optimize_params_default(&op);
    op.max_iterations = 300;
    op.max_seconds = 0;
    op.grid_bits = 4;
    op.d3d12_range = true;
    aa_optimize_result r;
    assert_int_equal(aa_optimize(&seed, &metric, &op, NULL, NULL, &best, &r, NULL), AA_OK);
    for (size_t i = 0; i < best.source_count; i++) {
        double x = best.source[i].x * 16, y = best.source[i].y * 16;
        assert_true(fabs(x - round(x)) < 1e-9 && fabs(y - round(y)) < 1e-9);
    }
    assert_true(isfinite(r.e2_before_snap));
    aa_pattern_free(&seed);
    aa_pattern_free(&best);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(small_step_against_gradient_lowers_e1),
        cmocka_unit_test(optimize_never_raises_e2),
        cmocka_unit_test(budget_follows_the_given_clock),
        cmocka_unit_test(mirrored_sites_are_preserved),
        cmocka_unit_test(tile_sites_and_pixels_are_preserved),
        cmocka_unit_test(multistart_is_deterministic),
        cmocka_unit_test(every_method_is_deterministic),
        cmocka_unit_test(perturbed_search_keeps_structure_and_is_deterministic),
        cmocka_unit_test(perturbed_multistart_is_deterministic),
        cmocka_unit_test(refined_stage_is_descent_then_search),
        cmocka_unit_test(pooled_seeds_start_lower_and_are_deterministic),
        cmocka_unit_test(cancel_stops_within_100ms),
        cmocka_unit_test(trace_is_monotone),
        cmocka_unit_test(screened_run_reports_one_monotone_trace),
        cmocka_unit_test(grid_snapping_reports_quantisation),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
