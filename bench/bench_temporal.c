/* Temporal antialiasing benchmark (issue 30, docs/temporal.md): the presets' E2 (worst phase),
 * mean over phases, F2 and frames to 5 % after a cut, side by side; then the first optimizer of
 * the offsets (temporal_optimize.h) for N = 8, alpha = 0.1, no resolve, within a time budget
 * (argv[1] seconds, default 60; one thread), against Halton(2,3) x 8 from index 1 in the same
 * run, and with argv[2] = lambda > 0 again with the objective E2 + lambda F2 and with
 * E2 + lambda max(0, F2 - Halton's F2).
 * `bench_temporal S L gaussian` also optimizes under the urp-like Gaussian resolve, and
 * `bench_temporal S L gaussian 16` also on a grid of 1/16 pixel;
 * `bench_temporal grid S` also runs N = 4, 8, 16 at alpha 0.05, 0.1, 0.2 for S seconds
 * each, without and with that resolve; `bench_temporal constrained S T` searches, on T threads
 * for S seconds, for E2 <= 0.31 with F2 no higher than Halton's (constrained() below).
 * The sequences are generated as the presets of proto/temporal_presets.c state them. */
#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aa_metric.h"
#include "aa_pattern.h"
#include "aa_temporal.h"

static aa_filter filter;
static aa_acuity acuity;
static aa_metric_params mp;
static double hop;       /* AALAB_TEMPORAL_HOP: the optimizer's hop (0: uniform starts only) */
static double grid_step; /* the grid of the next optimize() (0: none) */
static aa_temporal_resolve gaussian = {.radius = 1}; /* the urp-like resolve: sigma 0.5, 3 x 3 */

static void die(const char *what, const aa_error *err)
{
    fprintf(stderr, "%s: %s (%s)\n", what, err->message, err->field);
    exit(1);
}

static void report(const char *name, const aa_point *jitter, size_t n, aa_blend blend,
                   const aa_temporal_resolve *rs, aa_temporal_evaluation *keep)
{
    aa_temporal_spec spec = {.count = n, .jitter = jitter, .resolve = rs, .blend = blend};
    aa_temporal t;
    aa_temporal_evaluation ev;
    aa_error err = {0};
    if (aa_temporal_build(&t, &spec, &err))
        die(name, &err);
    double t0 = aa_monotonic_seconds();
    if (aa_temporal_evaluate(&t, &mp, 0, &ev, &err))
        die(name, &err);
    double dt = aa_monotonic_seconds() - t0;
    char settle[32];
    if (ev.frames_to_settle > 0)
        snprintf(settle, sizeof settle, "%ld", ev.frames_to_settle);
    else
        snprintf(settle, sizeof settle, "none<=%zu", ev.cut_count);
    printf("%-28s %4zu %8.4f %8.4f %8.4f %9s %9.1f\n", name, n, ev.e2, ev.mean_phase_e2, ev.f2,
           settle, dt * 1e3);
    if (keep)
        *keep = ev;
    else
        aa_temporal_evaluation_free(&ev);
    aa_temporal_free(&t);
}

static void halton(aa_point *out, size_t n, unsigned long start)
{
    aa_error err = {0};
    if (aa_jitter_halton(out, n, 2, 3, start, 1.0, &err))
        die("halton", &err);
}

static void presets(void)
{
    static aa_point j[128];
    aa_blend a01 = {AA_BLEND_EXPONENTIAL, 0.1};
    printf("%-28s %4s %8s %8s %8s %9s %9s\n", "preset (alpha 0.1)", "N", "E2", "mean", "F2",
           "frames5%", "eval ms");
    halton(j, 8, 1);
    report("halton23-8", j, 8, a01, NULL, NULL);
    halton(j, 16, 1);
    report("halton23-16", j, 16, a01, NULL, NULL);
    const double scales[] = {1.5, 1.7, 2, 3};
    for (size_t i = 0; i < 4; i++) {
        int n = aa_jitter_fsr2_phase_count(scales[i]);
        char name[32];
        snprintf(name, sizeof name, "fsr2-%gx", scales[i]);
        halton(j, (size_t)n, 1);
        report(name, j, (size_t)n, a01, NULL, NULL);
    }
    aa_temporal_resolve rs = {.radius = 1};
    aa_error err = {0};
    if (aa_filter_gaussian(&rs.filter, 0.5, 2, &err))
        die("gaussian", &err);
    halton(j, 8, 1);
    report("urp-like (Gaussian resolve)", j, 8, a01, &rs, NULL);
    aa_jitter_rgss4(j, 1.0);
    report("filament-rgss4", j, 4, a01, NULL, NULL);
    const size_t fn[] = {8, 16, 32};
    for (size_t i = 0; i < 3; i++) {
        char name[32];
        snprintf(name, sizeof name, "filament-halton%zu", fn[i]);
        halton(j, fn[i], 409);
        report(name, j, fn[i], a01, NULL, NULL);
    }
}

static void optimize(size_t n, double alpha, double seconds, double lambda, bool cap,
                     const aa_temporal_resolve *rs, uint64_t seed)
{
    aa_point start[16], best[16];
    halton(start, n, 1);
    aa_blend blend = {AA_BLEND_EXPONENTIAL, alpha};
    aa_error err = {0};
    double halton_e2;
    if (aa_temporal_e2(start, n, blend, NULL, rs, &mp, &halton_e2, &err))
        die("halton e2", &err);
    double halton_f2 = 0;
    if (cap) {
        aa_temporal t;
        aa_temporal_evaluation ev;
        aa_temporal_spec spec = {.count = n, .jitter = start, .resolve = rs, .blend = blend};
        if (aa_temporal_build(&t, &spec, &err) || aa_temporal_evaluate(&t, &mp, 1, &ev, &err))
            die("halton f2", &err);
        halton_f2 = ev.f2;
        aa_temporal_evaluation_free(&ev);
        aa_temporal_free(&t);
    }
    aa_temporal_opt_params p = {.count = n,
                                .blend = blend,
                                .range = 1,
                                .metric = &mp,
                                .start = start,
                                .max_seconds = seconds,
                                .flicker_weight = lambda,
                                .flicker_cap = halton_f2,
                                .resolve = rs,
                                .hop = hop,
                                .grid_step = grid_step,
                                .seed = seed};
    aa_temporal_opt_result r;
    if (aa_temporal_optimize(&p, best, &r, &err))
        die("optimize", &err);
    aa_temporal_evaluation ev_h, ev_o;
    char name[96];
    snprintf(name, sizeof name, "Halton N%zu a%g%s", n, alpha, rs ? " G" : "");
    report(name, start, n, blend, rs, &ev_h);
    snprintf(name, sizeof name, "optimized N%zu a%g l%g%s%s%s", n, alpha, lambda, cap ? " cap" : "",
             rs ? " G" : "", grid_step > 0 ? " grid" : "");
    report(name, best, n, blend, rs, &ev_o);
    printf("  -> E2 ratio to Halton %.3f, F2 ratio %.3f; %ld starts, %ld evaluations, %.1f s "
           "(first start, from Halton: %.4f)\n",
           ev_o.e2 / ev_h.e2, ev_o.f2 / ev_h.f2, r.starts, r.evaluations, r.seconds, r.first_score);
    printf("  offsets:");
    for (size_t f = 0; f < n; f++)
        printf(" (%.4f, %.4f)", best[f].x, best[f].y);
    printf("\n");
    aa_temporal_evaluation_free(&ev_h);
    aa_temporal_evaluation_free(&ev_o);
}

/* The constrained search (`bench_temporal constrained S [threads]`): E2 <= 0.31 with F2 no
 * higher than Halton's at N = 8, alpha 0.1, no resolve. Each thread repeats, until S seconds:
 * one E2-only start from a uniform random sequence (seed k), then a schedule of descents from
 * it with the objective E2 + lambda max(0, F2 - cap), lambda = 2, 5, 10, 20, 50, 100, cap =
 * 0.99 x Halton's F2 (a margin: the descent's power mean of F1 is below its maximum). The best
 * sequence with F2 <= Halton's wins. */
typedef struct constrained_job {
    double seconds, cap, halton_f2, t0;
    int thread, threads;
    aa_point best[8];
    double best_e2, best_f2, best_any_e2, best_any_f2;
    long candidates, feasible;
} constrained_job;

static double exact_f2(const aa_point *j, aa_blend blend, double *e2)
{
    aa_temporal t;
    aa_temporal_evaluation ev;
    aa_temporal_spec spec = {.count = 8, .jitter = j, .blend = blend};
    aa_error err = {0};
    if (aa_temporal_build(&t, &spec, &err) || aa_temporal_evaluate(&t, &mp, 1, &ev, &err))
        die("f2", &err);
    double f2 = ev.f2;
    *e2 = ev.e2;
    aa_temporal_evaluation_free(&ev);
    aa_temporal_free(&t);
    return f2;
}

static void *constrained_thread(void *arg)
{
    constrained_job *cj = arg;
    aa_blend blend = {AA_BLEND_EXPONENTIAL, 0.1};
    const double lambdas[] = {2, 5, 10, 20, 50, 100};
    cj->best_e2 = cj->best_any_e2 = INFINITY;
    for (uint64_t k = (uint64_t)cj->thread; aa_monotonic_seconds() - cj->t0 < cj->seconds;
         k += (uint64_t)cj->threads) {
        aa_point x[8], y[8];
        aa_error err = {0};
        aa_temporal_opt_params p = {
            .count = 8, .blend = blend, .range = 1, .metric = &mp, .max_starts = 1, .seed = k};
        aa_temporal_opt_result r;
        if (aa_temporal_optimize(&p, x, &r, &err))
            die("constrained e2", &err);
        p.start = x;
        p.flicker_cap = cj->cap;
        for (size_t l = 0; l < sizeof lambdas / sizeof *lambdas; l++) {
            p.flicker_weight = lambdas[l];
            if (aa_temporal_optimize(&p, y, &r, &err))
                die("constrained", &err);
            memcpy(x, y, sizeof x);
            double e2, f2 = exact_f2(x, blend, &e2);
            cj->candidates++;
            if (e2 < cj->best_any_e2 && f2 <= 1.05 * cj->halton_f2) {
                cj->best_any_e2 = e2;
                cj->best_any_f2 = f2;
            }
            if (f2 <= cj->halton_f2) {
                cj->feasible++;
                if (e2 < cj->best_e2) {
                    cj->best_e2 = e2;
                    cj->best_f2 = f2;
                    memcpy(cj->best, x, sizeof x);
                }
                break; /* feasible: a larger lambda only trades E2 away */
            }
        }
    }
    return NULL;
}

static void constrained(double seconds, int threads)
{
    aa_point h[8];
    halton(h, 8, 1);
    aa_blend blend = {AA_BLEND_EXPONENTIAL, 0.1};
    double halton_e2, halton_f2 = exact_f2(h, blend, &halton_e2);
    constrained_job jobs[8];
    pthread_t tid[8];
    threads = threads < 1 ? 1 : threads > 8 ? 8 : threads;
    double t0 = aa_monotonic_seconds();
    for (int i = 0; i < threads; i++) {
        jobs[i] = (constrained_job){.seconds = seconds,
                                    .cap = 0.99 * halton_f2,
                                    .halton_f2 = halton_f2,
                                    .t0 = t0,
                                    .thread = i,
                                    .threads = threads};
        pthread_create(&tid[i], NULL, constrained_thread, &jobs[i]);
    }
    constrained_job *win = NULL;
    long candidates = 0, feasible = 0;
    double any_e2 = INFINITY, any_f2 = 0;
    for (int i = 0; i < threads; i++) {
        pthread_join(tid[i], NULL);
        candidates += jobs[i].candidates;
        feasible += jobs[i].feasible;
        if (!win || jobs[i].best_e2 < win->best_e2)
            win = &jobs[i];
        if (jobs[i].best_any_e2 < any_e2) {
            any_e2 = jobs[i].best_any_e2;
            any_f2 = jobs[i].best_any_f2;
        }
    }
    printf("constrained N8 a0.1, %d threads, %.1f s: Halton E2 %.4f F2 %.4f; best with F2 <= "
           "Halton's: E2 %.4f F2 %.4f (ratio %.3f / %.3f); %ld candidates, %ld feasible; best "
           "with F2 <= 1.05 x Halton's: E2 %.4f F2 %.4f\n",
           threads, aa_monotonic_seconds() - t0, halton_e2, halton_f2, win->best_e2, win->best_f2,
           win->best_e2 / halton_e2, win->best_f2 / halton_f2, candidates, feasible, any_e2,
           any_f2);
    if (isfinite(win->best_e2)) {
        printf("  offsets:");
        for (size_t f = 0; f < 8; f++)
            printf(" (%.17g, %.17g)", win->best[f].x, win->best[f].y);
        printf("\n");
    }
}

int main(int argc, char **argv)
{
    aa_filter_default(&filter);
    aa_acuity_naiman(&acuity);
    mp = (aa_metric_params){.filter = &filter, .acuity = &acuity};
    const char *hop_env = getenv("AALAB_TEMPORAL_HOP");
    hop = hop_env ? atof(hop_env) : 0;
    aa_error err = {0};
    if (aa_filter_gaussian(&gaussian.filter, 0.5, 2, &err))
        die("gaussian", &err);
    presets();
    printf("\n");
    if (argc > 1 && !strcmp(argv[1], "constrained")) {
        constrained(argc > 2 ? atof(argv[2]) : 60, argc > 3 ? atoi(argv[3]) : 2);
        return 0;
    }
    if (argc > 1 && !strcmp(argv[1], "grid")) {
        double s = argc > 2 ? atof(argv[2]) : 10;
        const size_t ns[] = {4, 8, 16};
        const double as[] = {0.05, 0.1, 0.2};
        for (int r = 0; r < 2; r++)
            for (size_t i = 0; i < 3; i++)
                for (size_t k = 0; k < 3; k++)
                    optimize(ns[i], as[k], s, 0, false, r ? &gaussian : NULL, 1);
        return 0;
    }
    double seconds = argc > 1 ? atof(argv[1]) : 60;
    double lambda = argc > 2 ? atof(argv[2]) : 0;
    optimize(8, 0.1, seconds, 0, false, NULL, 1);
    if (lambda > 0) {
        optimize(8, 0.1, seconds, lambda, false, NULL, 1);
        optimize(8, 0.1, seconds, lambda, true, NULL, 1);
    }
    if (argc > 3 && !strcmp(argv[3], "gaussian"))
        optimize(8, 0.1, seconds, 0, false, &gaussian, 1);
    if (argc > 4) { /* a grid of 1/argv[4] pixels */
        grid_step = 1.0 / atof(argv[4]);
        optimize(8, 0.1, seconds, 0, false, NULL, 1);
    }
    return 0;
}
