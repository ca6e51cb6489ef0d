/* Spearman's rank correlation of two samples, as scipy.stats.spearmanr computes it: Pearson's
 * correlation of the ranks, ties given their average rank, and the two-sided p-value of the
 * Student t approximation with n - 2 degrees of freedom. Used by random-stats and table3 to ask
 * whether a point-set figure predicts E2 (docs/analysis.md). */
#ifndef AA_SPEARMAN_H
#define AA_SPEARMAN_H

#include <stddef.h>

typedef struct aa_spearman_result {
    size_t n;       /* pairs where both values are finite (the others are left out) */
    double rho;     /* NaN: n < 3, or one side constant over the pairs */
    double p_value; /* P(|T| >= |t|), t = rho sqrt((n - 2) / (1 - rho^2)); NaN with rho */
} aa_spearman_result;

/* Ranks 1..n of v (all finite), ties the mean of their ranks; AA_ENOMEM (naming nothing) when
 * out of memory. */
int aa_rank_average(const double *v, size_t n, double *ranks);
/* Spearman's rho of x and y (n pairs each), pairs with a non-finite value dropped. AA_ENOMEM
 * when out of memory; every other case is an answer (rho NaN where undefined). */
int aa_spearman_of(const double *x, const double *y, size_t n, aa_spearman_result *out);
/* The regularised incomplete beta function I_x(a, b) for a, b > 0 and x in [0, 1] (Lentz's
 * continued fraction). The p-values it gives are within 1.1e-11 relative of scipy's for 3 to
 * 5,000 pairs (spearman_scipy); the log-gamma terms lose some digits as a grows. */
double aa_incomplete_beta(double a, double b, double x);

#endif
