/* The optimizer's step rules side by side on the same seeds (optimizer.h): one local run per
 * seed and rule, Laine & Aila's rule as the baseline of each ratio.
 *  1. Opt W+P of P(16,16,4) from Poisson seeds: best E2 and seconds per rule.
 *  2. Opt W (weights only, convex) of the best of 1000 Poisson P(16,16,4) patterns, as in L&A
 *     Table 3: E2 per rule beside the paper's 0.221.
 * Flags: --seeds N (default 4), --seconds S per run (default 30), --quick (2 seeds, 10 s). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aa_metric.h"
#include "aa_pattern.h"
#include "aa_optimizer.h"

static const aa_optimize_method rules[] = {AA_METHOD_LAINE_AILA, AA_METHOD_MINIMAX,
                                           AA_METHOD_SMOOTH};
#define RULES 3

static int run(const aa_pattern *seed, const aa_metric_params *metric, aa_optimize_mode mode,
               aa_optimize_method method, double seconds, aa_optimize_result *r)
{
    aa_optimize_params op;
    aa_optimize_params_default(&op);
    op.mode = mode;
    op.method = method;
    op.max_seconds = seconds;
    op.max_iterations = 100000000;
    op.stall_iterations = 2000;
    aa_pattern best;
    aa_error err = {0};
    int rc = aa_optimize(seed, metric, &op, NULL, NULL, &best, r, &err);
    if (rc) {
        fprintf(stderr, "%s: %s\n", aa_optimize_method_name(method), err.message);
        return rc;
    }
    aa_pattern_free(&best);
    return 0;
}

int main(int argc, char **argv)
{
    int seeds = 4;
    double seconds = 30;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) {
            seeds = 2;
            seconds = 10;
        } else if (!strcmp(argv[i], "--seeds") && i + 1 < argc) {
            seeds = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--seconds") && i + 1 < argc) {
            seconds = atof(argv[++i]);
        } else {
            fprintf(stderr, "usage: %s [--quick] [--seeds N] [--seconds S]\n", argv[0]);
            return 2;
        }
    }
    aa_filter filter;
    aa_acuity acuity;
    aa_filter_default(&filter);
    aa_acuity_naiman(&acuity);
    aa_metric_params metric = {&filter, &acuity, NULL, 0, 0};
    aa_family fam;
    aa_error err = {0};
    if (aa_family_parse("P(16,16,4)", &fam, &err))
        return 1;

    printf("bench_step_rules: P(16,16,4) Opt W+P, one run per Poisson seed and rule, <= %.0f s "
           "each\n",
           seconds);
    printf("%-6s", "seed");
    for (int m = 0; m < RULES; m++)
        printf("  %10s %6s", aa_optimize_method_name(rules[m]), "s");
    printf("\n");
    double sum[RULES] = {0}, secs[RULES] = {0};
    for (int s = 1; s <= seeds; s++) {
        aa_rng rng;
        aa_rng_seed(&rng, (uint64_t)s, 0);
        aa_pattern seed;
        if (aa_family_seed(&fam, AA_SEED_POISSON, &filter, &rng, &seed, &err))
            return 1;
        printf("%-6d", s);
        for (int m = 0; m < RULES; m++) {
            aa_optimize_result r;
            if (run(&seed, &metric, AA_OPTIMIZE_BOTH, rules[m], seconds, &r))
                return 1;
            printf("  %10.5f %6.1f", r.e2, r.seconds);
            fflush(stdout);
            sum[m] += r.e2;
            secs[m] += r.seconds;
        }
        printf("\n");
        aa_pattern_free(&seed);
    }
    printf("%-6s", "mean");
    for (int m = 0; m < RULES; m++)
        printf("  %10.5f %6.1f", sum[m] / seeds, secs[m] / seeds);
    printf("\n%-6s", "ratio");
    for (int m = 0; m < RULES; m++)
        printf("  %10.4f %6s", sum[m] / sum[0], "");
    printf("  (mean E2 / laine-aila's)\n\n");

    /* L&A Table 3, Opt W: the best of 1000 random Poisson patterns, weights only. */
    aa_pattern best;
    aa_random_stats rs;
    size_t best_index;
    if (aa_random_patterns_range(&fam, AA_SEED_POISSON, &metric, 1, 0, 1000, NULL, NULL, NULL,
                                 &best, &best_index, &rs, &err))
        return 1;
    printf("Opt W of the best of 1000 Poisson P(16,16,4) patterns (E2 %.4f; paper: 0.346 -> "
           "0.221)\n",
           rs.min);
    double base = 0;
    for (int m = 0; m < RULES; m++) {
        aa_optimize_result r;
        if (run(&best, &metric, AA_OPTIMIZE_WEIGHTS, rules[m], seconds, &r))
            return 1;
        if (m == 0)
            base = r.e2;
        printf("  %-10s %8.5f in %5.1f s  ratio %.4f  (paper 0.221: %+.4f)\n",
               aa_optimize_method_name(rules[m]), r.e2, r.seconds, r.e2 / base, r.e2 - 0.221);
        fflush(stdout);
    }
    aa_pattern_free(&best);
    return 0;
}
