#include "random_patterns.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

int aa_random_patterns_range(const aa_family *family, aa_seed_distribution distribution,
                             const aa_metric_params *metric, uint64_t rng_seed, size_t first,
                             size_t count, aa_random_progress_fn progress, void *user, double *e2,
                             aa_pattern *best, size_t *best_index, aa_random_stats *stats,
                             aa_error *err)
{
    return aa_random_patterns_range_radius(family, distribution, 0, metric, rng_seed, first, count,
                                           progress, user, e2, best, best_index, stats, err);
}

int aa_random_patterns_range_radius(const aa_family *family, aa_seed_distribution distribution,
                                    double poisson_radius, const aa_metric_params *metric,
                                    uint64_t rng_seed, size_t first, size_t count,
                                    aa_random_progress_fn progress, void *user, double *e2,
                                    aa_pattern *best, size_t *best_index, aa_random_stats *stats,
                                    aa_error *err)
{
    return aa_random_patterns_range_visit(family, distribution, poisson_radius, metric, rng_seed,
                                          first, count, progress, user, NULL, NULL, e2, best,
                                          best_index, stats, err);
}

int aa_random_patterns_range_visit(const aa_family *family, aa_seed_distribution distribution,
                                   double poisson_radius, const aa_metric_params *metric,
                                   uint64_t rng_seed, size_t first, size_t count,
                                   aa_random_progress_fn progress, void *user,
                                   aa_random_visit_fn visit, void *visit_user, double *e2,
                                   aa_pattern *best, size_t *best_index, aa_random_stats *stats,
                                   aa_error *err)
{
    memset(best, 0, sizeof *best);
    *best_index = SIZE_MAX;
    *stats = (aa_random_stats){0, INFINITY, NAN, -INFINITY};
    if (count == 0)
        return aa_error_set(err, AA_EINVAL, "count", "at least one pattern");
    double sum = 0;
    int rc = AA_OK;
    for (size_t i = 0; i < count && !rc; i++) {
        aa_rng rng;
        aa_rng_seed(&rng, rng_seed, (uint64_t)(first + i));
        aa_pattern p;
        rc = aa_family_seed_radius(family, distribution, poisson_radius, metric->filter, &rng, &p,
                                   err);
        aa_evaluation ev;
        if (!rc)
            rc = aa_evaluate(&p, metric, &ev, err);
        if (!rc && visit) {
            rc = visit(visit_user, i, &p, ev.e2, err);
            if (rc)
                aa_evaluation_free(&ev);
        }
        if (rc) {
            aa_pattern_free(&p);
            break;
        }
        if (e2)
            e2[i] = ev.e2;
        sum += ev.e2;
        stats->max = fmax(stats->max, ev.e2);
        if (ev.e2 < stats->min) {
            stats->min = ev.e2;
            aa_pattern_free(best);
            *best = p;
            *best_index = first + i;
        } else {
            aa_pattern_free(&p);
        }
        aa_evaluation_free(&ev);
        stats->count++;
        stats->avg = sum / (double)stats->count;
        if (progress && i % 64 == 0 && progress(user, i))
            rc = aa_error_set(err, AA_ECANCELED, "", "cancelled by the progress callback");
    }
    return rc;
}

aa_random_stats aa_random_stats_of(const double *e2, size_t count)
{
    aa_random_stats s = {0, INFINITY, NAN, -INFINITY};
    double sum = 0;
    for (size_t i = 0; i < count; i++) {
        sum += e2[i];
        s.max = fmax(s.max, e2[i]);
        s.min = fmin(s.min, e2[i]);
        s.count++;
    }
    if (count)
        s.avg = sum / (double)count;
    return s;
}
