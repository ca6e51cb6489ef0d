/* A descent, then iterated local search for the rest of its stage's budget (optimizer.h,
 * aa_optimize_refined): the one "Opt W+P" stage of random-stats and table3. The descent of a
 * tile pattern stops at a kink of the max well within its budget; the search spends the rest. */

#include "optimizer.h"
#include "optimizer_run.h"

int aa_optimize_refined(const aa_pattern *start, const aa_metric_params *metric,
                        const aa_optimize_params *local, long stage_iterations,
                        const aa_perturb_params *search, aa_rng *rng,
                        aa_optimize_progress_fn progress, void *user, aa_pattern *out,
                        aa_optimize_result *result, aa_error *err)
{
    /* The stage as one run, against its budgets (the runs' own fractions end at 1 when they
     * stop early). */
    opt_chained_progress sp = {progress,
                               user,
                               local->max_seconds,
                               stage_iterations > 0 ? stage_iterations : local->max_iterations,
                               0,
                               0,
                               0,
                               0};
    aa_optimize_progress_fn relay = progress ? opt_chained_progress_forward : NULL;
    int rc = aa_optimize(start, metric, local, relay, &sp, out, result, err);
    long rest = stage_iterations > 0 ? stage_iterations - result->iterations : 0;
    if (rc || local->mode != AA_OPTIMIZE_BOTH || !aa_perturbable(out) ||
        (local->max_seconds > 0 && result->seconds >= local->max_seconds) ||
        (stage_iterations > 0 && rest <= 0))
        return rc;
    aa_perturb_params pp = *search;
    pp.max_seconds = local->max_seconds > 0 ? local->max_seconds - result->seconds : 0;
    pp.max_iterations = rest;
    sp.seconds = result->seconds;
    sp.iterations = result->iterations;
    sp.evaluations = result->evaluations;
    aa_pattern refined;
    aa_optimize_result rr;
    rc = aa_optimize_perturbed(out, metric, local, &pp, rng, relay, &sp, &refined, &rr, err);
    if (rc && rc != AA_ECANCELED) {
        aa_pattern_free(out);
        return rc;
    }
    aa_pattern_free(out);
    *out = refined; /* AA_ECANCELED: the best so far */
    aa_optimize_result_chain(result, &rr);
    return rc;
}
