/* A descent, then iterated local search for the rest of its stage's budget (optimizer.h,
 * aa_optimize_refined): the one "Opt W+P" stage of random-stats and table3. The descent of a
 * tile pattern stops at a kink of the max well within its budget; the search spends the rest. */
#include <math.h>

#include "optimizer.h"

/* The stage seen as one run by the caller's progress: counters continue from the descent into
 * the search, and the fraction is the share of the stage's budgets spent. The runs' own
 * fractions end at 1 when they stop early, so they are not passed on. */
typedef struct stage_progress {
    aa_optimize_progress_fn fn;
    void *user;
    double budget_seconds;  /* <= 0: none */
    long budget_iterations; /* > 0 */
    double seconds;         /* the descent's, once the search runs */
    long iterations, evaluations;
    double fraction; /* the last reported: it never steps back */
} stage_progress;

static int stage_relay(void *user, const aa_optimize_progress *p)
{
    stage_progress *s = user;
    aa_optimize_progress q = *p;
    q.seconds += s->seconds;
    q.iterations += s->iterations;
    q.evaluations += s->evaluations;
    double f = fmax(s->fraction, (double)q.iterations / (double)s->budget_iterations);
    if (s->budget_seconds > 0)
        f = fmax(f, q.seconds / s->budget_seconds);
    s->fraction = q.fraction = fmin(f, 1);
    return s->fn(s->user, &q);
}

int aa_optimize_refined(const aa_pattern *start, const aa_metric_params *metric,
                        const aa_optimize_params *local, long stage_iterations,
                        const aa_perturb_params *search, aa_rng *rng,
                        aa_optimize_progress_fn progress, void *user, aa_pattern *out,
                        aa_optimize_result *result, aa_error *err)
{
    stage_progress sp = {progress,
                         user,
                         local->max_seconds,
                         stage_iterations > 0 ? stage_iterations : local->max_iterations,
                         0,
                         0,
                         0,
                         0};
    aa_optimize_progress_fn relay = progress ? stage_relay : NULL;
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
