/* Random patterns of a family (L&A Table 3, its first columns): count patterns drawn from one
 * distribution, each evaluated; their min / average / max E2 and the best of them, the start of
 * the table's "Opt W" and "Opt W+P" columns. */
#ifndef AA_RANDOM_PATTERNS_H
#define AA_RANDOM_PATTERNS_H

#include <stddef.h>

#include "aa_pattern.h"
#include "aa_metric.h"

typedef struct aa_random_stats {
    size_t count; /* patterns evaluated */
    double min, avg, max;
} aa_random_stats;

/* Called after pattern i (0-based) when i % 64 == 0; nonzero cancels. */
typedef int (*aa_random_progress_fn)(void *user, size_t i);

/* Draws count (>= 1) seed patterns of the family (aa_family_seed: positions from kind, weights
 * from metric->filter) in turn from rng and evaluates each. *best: the lowest E2, the first of
 * equals. On error or cancel (AA_ECANCELED) *stats and *best hold the patterns done so far. */
int aa_random_patterns(const aa_family *family, aa_seed_kind kind, const aa_metric_params *metric,
                       aa_rng *rng, size_t count, aa_random_progress_fn progress, void *user,
                       aa_pattern *best, aa_random_stats *stats, aa_error *err);

#endif
