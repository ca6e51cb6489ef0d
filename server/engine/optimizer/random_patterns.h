/* Random patterns of a family (L&A Table 3, its first columns): count patterns drawn from one
 * distribution, each evaluated; their min / average / max E2 and the best of them, the start of
 * the table's "Opt W" and "Opt W+P" columns. */
#ifndef AA_RANDOM_PATTERNS_H
#define AA_RANDOM_PATTERNS_H

#include <stddef.h>
#include <stdint.h>

#include "aa_pattern.h"
#include "aa_metric.h"

typedef struct aa_random_stats {
    size_t count; /* patterns evaluated */
    double min, avg, max;
} aa_random_stats;

/* Called after pattern i (0-based) when i % 64 == 0; nonzero cancels. */
typedef int (*aa_random_progress_fn)(void *user, size_t i);

/* Draws count (>= 1) seed patterns of the family (aa_family_seed: positions from distribution,
 * weights from metric->filter) and evaluates each: patterns first .. first + count - 1 of a
 * numbered sequence, where pattern i draws from its own PCG32 stream (rng_seed, i), so contiguous
 * ranges evaluated apart (shards of a job) give the patterns and E2 values of one run over the
 * whole sequence. e2 (optional, count entries) receives each pattern's E2 in order (to merge ranges
 * exactly: min / avg / max recomputed over the concatenated lists equal one run's); *best_index the
 * global index of *best (the first of equals). progress as above, with the local index. On error or
 * cancel (AA_ECANCELED) *stats and *best hold the patterns done so far. */
int aa_random_patterns_range(const aa_family *family, aa_seed_distribution distribution,
                             const aa_metric_params *metric, uint64_t rng_seed, size_t first,
                             size_t count, aa_random_progress_fn progress, void *user, double *e2,
                             aa_pattern *best, size_t *best_index, aa_random_stats *stats,
                             aa_error *err);
/* The same with a stated Poisson-disk radius in pixels (aa_family_seed_radius; 0: default). */
int aa_random_patterns_range_radius(const aa_family *family, aa_seed_distribution distribution,
                                    double poisson_radius, const aa_metric_params *metric,
                                    uint64_t rng_seed, size_t first, size_t count,
                                    aa_random_progress_fn progress, void *user, double *e2,
                                    aa_pattern *best, size_t *best_index, aa_random_stats *stats,
                                    aa_error *err);
/* Called with each pattern (local index i) and its E2 once evaluated, e.g. to take its
 * point-set figures; a nonzero return (an AA_E* code, err filled) ends the run with it. */
typedef int (*aa_random_visit_fn)(void *user, size_t i, const aa_pattern *p, double e2,
                                  aa_error *err);
/* The same, visiting every pattern (visit may be NULL). */
int aa_random_patterns_range_visit(const aa_family *family, aa_seed_distribution distribution,
                                   double poisson_radius, const aa_metric_params *metric,
                                   uint64_t rng_seed, size_t first, size_t count,
                                   aa_random_progress_fn progress, void *user,
                                   aa_random_visit_fn visit, void *visit_user, double *e2,
                                   aa_pattern *best, size_t *best_index, aa_random_stats *stats,
                                   aa_error *err);
/* min / avg / max of E2 values in order (avg as a running sum divided by the count, the way
 * aa_random_patterns_range computes it). */
aa_random_stats aa_random_stats_of(const double *e2, size_t count);

#endif
