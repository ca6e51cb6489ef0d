/* Laine & Aila's Table 3 protocol for one distribution and one rng_seed: `count` random patterns
 * of a family (weights from the filter), their min / avg / max E2; the best of them optimised for
 * the weights only ("Opt W", a convex problem solved exactly by the minimax rule) and, again from
 * the best random pattern, for weights and positions ("Opt W+P": the auto rule's descent, then
 * iterated local search for the rest of its budget). The same steps random-stats jobs take;
 * table3 jobs and bench_table3 run this over K rng_seeds and report mean +- sd. */
#ifndef AA_TABLE3_H
#define AA_TABLE3_H

#include <stddef.h>
#include <stdint.h>

#include "aa_metric.h"
#include "aa_pattern.h"
#include "optimizer.h"
#include "random_patterns.h"

/* L&A Table 3 (P(16,16,4)), the rows this protocol reproduces. */
typedef struct aa_table3_paper {
    aa_seed_distribution distribution;
    double min, avg, max, opt_w, opt_wp;
} aa_table3_paper;
/* The paper's value for a distribution (Poisson, jittered); NULL for any other. */
const aa_table3_paper *aa_table3_paper_row(aa_seed_distribution distribution);

typedef struct aa_table3_params {
    size_t count;          /* random patterns, default 1000 */
    double poisson_radius; /* pixels; 0: aa_poisson_default_radius */
    double opt_w_seconds;  /* Opt W budget, default 60 (it converges in seconds); <= 0: none */
    double opt_wp_seconds; /* Opt W+P budget, default 60; <= 0: none (then max_iterations) */
    long max_iterations;   /* Opt W+P steps, descent and search together; 0: none */
    int opt_wp_method;     /* an aa_optimize_method for Opt W+P; -1 (default): aa_auto_method */
    aa_clock clock;
    /* Optional: called with every random pattern (aa_random_patterns_range_visit). */
    aa_random_visit_fn visit;
    void *visit_user;
} aa_table3_params;
void aa_table3_params_default(aa_table3_params *p);

typedef struct aa_table3_cell {
    aa_random_stats random;
    size_t best_index;
    aa_pattern best_random;
    double opt_w, opt_wp;
    aa_optimize_method opt_w_method, opt_wp_method;
    aa_optimize_result opt_w_run, opt_wp_run; /* work and seconds of each stage */
    aa_pattern opt_wp_pattern;
} aa_table3_cell;
void aa_table3_cell_free(aa_table3_cell *c);

/* Which phase a progress report belongs to. random_fraction is 0..1 during the random patterns;
 * opt is set during Opt W and Opt W+P. Return nonzero to cancel (AA_ECANCELED). */
typedef struct aa_table3_progress {
    int phase; /* 0 random patterns, 1 Opt W, 2 Opt W+P */
    double random_fraction;
    const aa_optimize_progress *opt;
} aa_table3_progress;
typedef int (*aa_table3_progress_fn)(void *user, const aa_table3_progress *p);

/* Runs the protocol for one distribution and rng_seed: pattern i from stream (rng_seed, i), Opt
 * W+P's search from stream (rng_seed, 2^32) (as random-stats). On error or cancel *out holds
 * what was done (free it with aa_table3_cell_free either way). */
int aa_table3_cell_run(const aa_family *family, aa_seed_distribution distribution,
                       const aa_metric_params *metric, const aa_table3_params *params,
                       uint64_t rng_seed, aa_table3_progress_fn progress, void *user,
                       aa_table3_cell *out, aa_error *err);

/* Mean and sample standard deviation (n - 1; 0 for one value) of n values. */
void aa_mean_sd(const double *v, size_t n, double *mean, double *sd);

#endif
