/* The family searches of L&A Table 3 and Hasselgren Fig. 3: multi-start
 * optimisation of positions and weights per family, printed beside the published best E2.
 * Flags: --family-seconds S (default 60), --p16-seconds S (default 600), --quick (8 s per family,
 * 30 s for P(16,16,4)), --workers W (default 2), --seed K, --only LABEL, --method
 * auto|laine-aila|minimax|smooth (default auto: the step rule optimize jobs choose), --acuity
 * NAME (default naiman, version 2; naiman-envelope is version 1), --cpu-clock (budgets in the
 * process's CPU seconds divided by the workers, for a machine shared with other work), --trace
 * (best E2 against the budget's clock, every seed's end point). To study the search on one
 * family (defaults: as optimize jobs): --first-seed K, --poisson-only, --seed-pool N (each seed
 * the best of N draws), --perturb-sigma S, --perturb-stall N, --perturb-redraw N,
 * --perturb-keep-pixels (the search's move before 2026-11-27: samples jittered inside their pixel),
 * --kink-width W (the smooth rule's first-stage width of E1's smoothed crossing kinks, pixels;
 * 0: exact E1 throughout, as before 2026-11-27; default AA_SMOOTH_KINK_WIDTH).
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "aa_metric.h"
#include "aa_pattern.h"
#include "aa_optimizer.h"

typedef struct bench_case {
    const char *label;
    double published;
} bench_case;

static const bench_case cases[] = {
    {"P(1,1,2)", 0.696},   {"P(1,1,3)", 0.480},  {"P(1,1,4)", 0.359},  {"P(1,1,5)", 0.301},
    {"P(1,1,6)", 0.274},   {"P(4,1+,2)", 0.359}, {"P(4,1+,3)", 0.301}, {"P(4,1+,4)", 0.274},
    {"P(4,1+,5)", 0.259},  {"P(4,1+,6)", 0.249}, {"P(1,4,2)", 0.465},  {"P(1,4,3)", 0.335},
    {"P(1,4,4)", 0.241},   {"P(1,4,5)", 0.197},  {"P(1,4,6)", 0.168},  {"P(4,1+,1.25)", 0.560},
    {"P(16,16,4)", 0.161},
};

/* The process's CPU seconds per worker: a budget that other work on the machine does not eat. */
static double cpu_per_worker(void *user)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ((double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec) / *(const int *)user;
}

typedef struct trace_state {
    double last_e2, last_t;
} trace_state;

/* --trace: the best E2 against the budget's clock, at improvements (at most every 5 s) */
static int trace_progress(void *user, const aa_optimize_progress *p)
{
    trace_state *ts = user;
    if (p->best_e2 < ts->last_e2 && p->seconds - ts->last_t >= 5) {
        printf("  trace %7.1f s  %.4f  (%ld steps)\n", p->seconds, p->best_e2, p->iterations);
        fflush(stdout);
        ts->last_e2 = p->best_e2;
        ts->last_t = p->seconds;
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *acuity_name = "naiman";
    bool cpu_clock = false;
    double family_seconds = 60, p16_seconds = 600;
    aa_optimize_method method = AA_METHOD_LAINE_AILA;
    bool method_auto = true;
    int workers = 2;
    unsigned long long rng_seed = 1;
    const char *only = NULL;
    long seed_pool = -1; /* -1: the default (as optimize jobs) */
    bool trace = false;
    double perturb_sigma = 0;
    int perturb_stall = 0, perturb_redraw = 0;
    bool perturb_keep_pixels = false;
    double kink_width = AA_SMOOTH_KINK_WIDTH;
    long first_seed = 0;
    bool poisson_only = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) {
            family_seconds = 4;
            p16_seconds = 30;
        } else if (!strcmp(argv[i], "--family-seconds") && i + 1 < argc) {
            family_seconds = atof(argv[++i]);
        } else if (!strcmp(argv[i], "--p16-seconds") && i + 1 < argc) {
            p16_seconds = atof(argv[++i]);
        } else if (!strcmp(argv[i], "--workers") && i + 1 < argc) {
            workers = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--seed") && i + 1 < argc) {
            rng_seed = strtoull(argv[++i], NULL, 10);
        } else if (!strcmp(argv[i], "--method") && i + 1 < argc) {
            ++i;
            method_auto = !strcmp(argv[i], "auto");
            if (!method_auto && aa_optimize_method_parse(argv[i], &method)) {
                fprintf(stderr, "--method: auto, laine-aila, minimax or smooth\n");
                return 2;
            }
        } else if (!strcmp(argv[i], "--acuity") && i + 1 < argc) {
            acuity_name = argv[++i];
        } else if (!strcmp(argv[i], "--cpu-clock")) {
            cpu_clock = true;
        } else if (!strcmp(argv[i], "--seed-pool") && i + 1 < argc) {
            seed_pool = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--perturb-sigma") && i + 1 < argc) {
            perturb_sigma = atof(argv[++i]);
        } else if (!strcmp(argv[i], "--perturb-stall") && i + 1 < argc) {
            perturb_stall = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--perturb-redraw") && i + 1 < argc) {
            perturb_redraw = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--perturb-keep-pixels")) {
            perturb_keep_pixels = true;
        } else if (!strcmp(argv[i], "--kink-width") && i + 1 < argc) {
            kink_width = atof(argv[++i]);
        } else if (!strcmp(argv[i], "--first-seed") && i + 1 < argc) {
            first_seed = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--poisson-only")) {
            poisson_only = true;
        } else if (!strcmp(argv[i], "--trace")) {
            trace = true;
        } else if (!strcmp(argv[i], "--only") && i + 1 < argc) {
            only = argv[++i];
        } else {
            fprintf(stderr,
                    "usage: %s [--quick] [--family-seconds S] [--p16-seconds S] [--workers W] "
                    "[--seed K] [--only LABEL] [--acuity NAME] [--cpu-clock] [--trace] "
                    "[--first-seed K] "
                    "[--poisson-only] [--seed-pool N] [--perturb-sigma S] [--perturb-stall N] "
                    "[--perturb-redraw N] [--perturb-keep-pixels] [--kink-width W]\n",
                    argv[0]);
            return 2;
        }
    }
    aa_filter filter;
    aa_acuity acuity;
    aa_filter_default(&filter);
    aa_error aerr = {0};
    if (aa_acuity_by_name(&acuity, acuity_name, &aerr)) {
        fprintf(stderr, "--acuity: %s\n", aerr.message);
        return 2;
    }
    aa_metric_params metric = {&filter, &acuity, NULL, 0, 0};
    printf("bench_families: multi-start descent, Opt W+P, %d workers, rng_seed %llu, method %s, "
           "acuity %s version %d, kink width %g%s\n",
           workers, rng_seed, method_auto ? "auto" : aa_optimize_method_name(method), acuity.name,
           acuity.version, kink_width, cpu_clock ? ", budgets in CPU seconds per worker" : "");
    printf("%-14s %8s %8s %9s %8s %7s %9s  %s\n", "family", "best_e2", "seconds", "published",
           "diff", "seeds", "ratio", "method");
    int short_count = 0, total = 0;
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        if (only && strcmp(only, cases[c].label))
            continue;
        aa_family fam;
        aa_error err = {0};
        if (aa_family_parse(cases[c].label, &fam, &err)) {
            fprintf(stderr, "%s: %s\n", cases[c].label, err.message);
            return 1;
        }
        bool big = !strcmp(cases[c].label, "P(16,16,4)");
        aa_multistart_params mp;
        aa_multistart_params_default(&mp);
        mp.family = &fam;
        mp.workers = workers;
        mp.rng_seed = rng_seed;
        mp.max_seconds = big ? p16_seconds : family_seconds;
        if (cpu_clock)
            mp.local.clock = (aa_clock){cpu_per_worker, &workers};
        mp.seed_count = 100000; /* the time budget ends the search */
        /* As optimize jobs do by default ("method":"auto"). */
        mp.local.method =
            method_auto ? aa_auto_method(aa_family_perturbable(&fam), mp.local.mode) : method;
        mp.local.max_iterations = big ? 200000 : 4000;
        mp.local.stall_iterations = big ? 2000 : 300;
        mp.screen_iterations = 150; /* mirrored families: screen configurations first */
        mp.screen_top = 8;
        /* As optimize jobs do: iterated local search for the tiled families (optimizer.h). */
        if (aa_family_perturbable(&fam))
            mp.perturb.rounds = AA_PERTURB_UNTIL_STALL;

        if (perturb_sigma > 0)
            mp.perturb.sigma = perturb_sigma;
        if (perturb_stall > 0)
            mp.perturb.stall = perturb_stall;
        if (perturb_redraw > 0)
            mp.perturb.redraw = perturb_redraw;
        mp.perturb.keep_pixels = perturb_keep_pixels;
        mp.local.kink_width = kink_width;
        static const aa_seed_distribution poisson[1] = {AA_SEED_POISSON};
        if (poisson_only) {
            mp.distributions = poisson;
            mp.distribution_count = 1;
        }
        mp.first_seed = (size_t)first_seed;
        if (seed_pool >= 0)
            mp.seed_pool = (size_t)seed_pool;

        aa_pattern best;
        aa_multistart_result r;
        trace_state ts = {INFINITY, -1};
        int rc = aa_multistart(&mp, &metric, trace ? trace_progress : NULL, &ts, &best, &r, &err);
        if (rc && rc != AA_ECANCELED) {
            fprintf(stderr, "%s: %s\n", cases[c].label, err.message);
            return 1;
        }
        double diff = r.e2 - cases[c].published;
        printf("%-14s %8.4f %8.1f %9.3f %+8.4f %7zu %9.4f  %-10s%s\n", cases[c].label, r.e2,
               r.seconds, cases[c].published, diff, r.seeds_run, r.e2 / cases[c].published,
               aa_optimize_method_name(mp.local.method), diff > 0.005 ? "  short" : "");
        fflush(stdout);
        total++;
        short_count += diff > 0.005;
        if (trace)
            for (size_t s = 0; s < r.seed_count; s++)
                if (!isnan(r.per_seed[s].e2))
                    printf("  seed %zu: %s %.4f -> %.4f (%ld steps)\n", s,
                           r.per_seed[s].distribution == AA_SEED_POISSON ? "poisson" : "other",
                           r.per_seed[s].initial_e2, r.per_seed[s].e2, r.per_seed[s].iterations);
        aa_pattern_free(&best);
        aa_multistart_result_free(&r);
    }
    printf("%d of %d families within +0.005 of the published best (ratio = ours / published)\n",
           total - short_count, total);
    return 0;
}
