#define _POSIX_C_SOURCE 200809L /* pthreads, clock_gettime */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "aa_pattern.h"
#include "optimizer.h"

void aa_multistart_params_default(aa_multistart_params *p)
{
    memset(p, 0, sizeof *p);
    aa_optimize_params_default(&p->local);
    p->local.max_seconds = 0;
    p->seed_count = 16;
    p->rng_seed = 1;
    p->workers = 1;
    p->max_seconds = 60;
    aa_perturb_params_default(&p->perturb);
    /* P(16,16,4), one worker, 60 CPU s, same seeds (README, Benchmarks): sigma 0.03 ends at
     * 0.1591 and 0.1657 where 0.01 ends at 0.1604 and 0.1674 (0.05: 0.1614 on the first). */
    p->perturb.sigma = 0.03;
}

void aa_multistart_result_free(aa_multistart_result *r)
{
    free(r->per_seed);
    r->per_seed = NULL;
}

/* The call's clock (local.clock: the caller may stop it while the run is paused). */
static double now_of(const aa_multistart_params *p)
{
    return aa_clock_seconds(&p->local.clock);
}

#define MAX_WORKERS 64

typedef struct shared_run {
    const aa_multistart_params *params;
    const aa_metric_params *metric;
    aa_optimize_progress_fn progress;
    void *user;
    double start;
    pthread_mutex_t lock;
    /* under lock: */
    bool cancel;
    double last_call;
    double snapshot_e2;  /* best E2 seen in any progress report (for the callback) */
    aa_pattern snapshot; /* its pattern */
    bool improved;
    /* finished seeds' counts, and each worker's counts of its current seed */
    long done_iterations, done_evaluations;
    long live_iterations[MAX_WORKERS], live_evaluations[MAX_WORKERS];
    size_t seeds_done;
    aa_multistart_seed *per_seed;
} shared_run;

typedef struct worker {
    shared_run *sh;
    int index;
    int status;
    aa_error err;
    double best_e2;
    size_t best_seed;
    aa_pattern best;
    aa_optimize_result best_result;
} worker;

typedef struct inner_ctx {
    worker *w;
    long iterations_before, evaluations_before; /* the seed's descent, while it is refined */
} inner_ctx;

/* Called by one seed's aa_optimize: forwards (rate-limited, serialised) to the user callback
 * and carries cancellation and the call's time budget to the seed. */
static int inner_progress(void *user, const aa_optimize_progress *pr)
{
    const inner_ctx *ic = user;
    worker *w = ic->w;
    shared_run *sh = w->sh;
    int stop = 0;
    pthread_mutex_lock(&sh->lock);
    sh->live_iterations[w->index] = ic->iterations_before + pr->iterations;
    sh->live_evaluations[w->index] = ic->evaluations_before + pr->evaluations;
    if (pr->best && pr->best_e2 < sh->snapshot_e2) {
        aa_pattern copy;
        if (aa_pattern_copy(&copy, pr->best) == AA_OK) {
            aa_pattern_free(&sh->snapshot);
            sh->snapshot = copy;
            sh->snapshot_e2 = pr->best_e2;
            sh->improved = true;
        }
    }
    double t = now_of(sh->params);
    if (sh->progress && !sh->cancel && t - sh->last_call >= 0.01) {
        sh->last_call = t;
        long it = sh->done_iterations, ev = sh->done_evaluations;
        for (int i = 0; i < MAX_WORKERS; i++) {
            it += sh->live_iterations[i];
            ev += sh->live_evaluations[i];
        }
        double fraction = (double)sh->seeds_done / (double)sh->params->seed_count;
        if (sh->params->max_seconds > 0)
            fraction = fmax(fraction, (t - sh->start) / sh->params->max_seconds);
        aa_optimize_progress up = {t - sh->start,
                                   it,
                                   ev,
                                   sh->snapshot_e2,
                                   fmin(fraction, 1),
                                   sh->improved,
                                   sh->snapshot_e2 < INFINITY ? &sh->snapshot : NULL};
        sh->improved = false;
        if (sh->progress(sh->user, &up))
            sh->cancel = true;
    }
    if (sh->params->max_seconds > 0 && t - sh->start >= sh->params->max_seconds)
        stop = 1;
    stop |= sh->cancel;
    pthread_mutex_unlock(&sh->lock);
    return stop;
}

/* Stream of candidate j of seed i's pool: above every seed's (i) and perturbation (2^32 + i)
 * stream. */
#define POOL_STREAM (UINT64_C(1) << 40)

static bool run_should_stop(shared_run *sh)
{
    pthread_mutex_lock(&sh->lock);
    bool stop = sh->cancel || (sh->params->max_seconds > 0 &&
                               now_of(sh->params) - sh->start >= sh->params->max_seconds);
    pthread_mutex_unlock(&sh->lock);
    return stop;
}

/* The lowest-E2 of seed_pool draws of seed i (global index gi) of a family; stops early (with
 * the best so far) when the call's budget ends or it is cancelled. */
static int pool_seed(shared_run *sh, size_t gi, aa_seed_distribution distribution, aa_pattern *out,
                     aa_error *err)
{
    const aa_multistart_params *p = sh->params;
    memset(out, 0, sizeof *out);
    double best_e2 = INFINITY;
    for (size_t j = 0; j < p->seed_pool; j++) {
        if (j > 0 && j % 16 == 0 && run_should_stop(sh))
            break;
        aa_rng rng;
        aa_rng_seed(&rng, p->rng_seed, POOL_STREAM + (uint64_t)gi * p->seed_pool + j);
        aa_pattern cand;
        int rc = aa_family_seed(p->family, distribution, sh->metric->filter, &rng, &cand, err);
        aa_evaluation ev;
        if (!rc && (rc = aa_evaluate(&cand, sh->metric, &ev, err)))
            aa_pattern_free(&cand);
        if (rc) {
            aa_pattern_free(out);
            return rc;
        }
        if (ev.e2 < best_e2) {
            best_e2 = ev.e2;
            aa_pattern_free(out);
            *out = cand;
        } else {
            aa_pattern_free(&cand);
        }
        aa_evaluation_free(&ev);
    }
    return AA_OK;
}

static int make_seed(shared_run *sh, size_t i, aa_seed_distribution *distribution, aa_pattern *out,
                     aa_error *err)
{
    const aa_multistart_params *p = sh->params;
    const aa_metric_params *metric = sh->metric;
    if (!p->family)
        return aa_pattern_copy(out, &p->seeds[i])
                   ? aa_error_set(err, AA_ENOMEM, "", "out of memory")
                   : AA_OK;
    static const aa_seed_distribution all[5] = {AA_SEED_UNIFORM, AA_SEED_JITTERED, AA_SEED_NROOKS,
                                                AA_SEED_POISSON, AA_SEED_LLOYD};
    /* The large tiled families: uniform and N-rooks seeds end far worse (P(16,16,4), smooth
     * rule, two seeds each: uniform 0.187 / 0.227, N-rooks 0.183 / 0.191, jittered 0.180 /
     * 0.181, Poisson 0.176 / 0.181), and a run of them has time for few seeds. Poisson alone:
     * with the iterated local search, seed 1 of P(16,16,4) ends at 0.1679 jittered and 0.1659
     * Poisson (60 CPU s, acuity version 2), as L&A Table 3's Opt W+P ranks them, and with two
     * workers the alternation gave every seed of the second worker the jittered grid. */
    static const aa_seed_distribution tiled[1] = {AA_SEED_POISSON};
    bool use_tiled = aa_family_perturbable(p->family);
    const aa_seed_distribution *distributions = p->distributions ? p->distributions
                                                : use_tiled      ? tiled
                                                                 : all;
    size_t n_distributions = p->distributions ? p->distribution_count : use_tiled ? 1 : 5;
    i += p->first_seed; /* everything below follows the global index */
    *distribution = distributions[i % n_distributions];
    aa_rng rng;
    aa_rng_seed(&rng, p->rng_seed, (uint64_t)i);
    if (p->family->mirrored) {
        /* The placement configuration matters more than the positions: seed i takes
         * configuration i mod count, so every configuration is tried in turn. */
        if (p->configs && p->config_count)
            return aa_mirrored_config_seed(&p->configs[i % p->config_count], *distribution,
                                           metric->filter, &rng, out, err);
        aa_mirrored_config *configs;
        size_t count;
        int rc = aa_enumerate_mirrored(p->family->cost, &configs, &count, err);
        if (rc)
            return rc;
        if (count == 0) {
            free(configs);
            return aa_error_set(err, AA_EINVAL, "family", "no configuration of this cost");
        }
        rc = aa_mirrored_config_seed(&configs[i % count], *distribution, metric->filter, &rng, out,
                                     err);
        free(configs);
        return rc;
    }
    if (p->seed_pool > 1)
        return pool_seed(sh, i, *distribution, out, err);
    return aa_family_seed(p->family, *distribution, metric->filter, &rng, out, err);
}

static void worker_main(void *arg)
{
    worker *w = arg;
    shared_run *sh = w->sh;
    const aa_multistart_params *p = sh->params;
    w->best_e2 = INFINITY;
    for (size_t i = (size_t)w->index; i < p->seed_count; i += (size_t)p->workers) {
        pthread_mutex_lock(&sh->lock);
        bool stop = sh->cancel || (p->max_seconds > 0 && now_of(p) - sh->start >= p->max_seconds);
        pthread_mutex_unlock(&sh->lock);
        if (stop)
            break;
        aa_pattern seed, out;
        aa_seed_distribution distribution = AA_SEED_UNIFORM;
        aa_error e = {0};
        int rc = make_seed(sh, i, &distribution, &seed, &e);
        aa_optimize_result r;
        memset(&r, 0, sizeof r);
        if (!rc) {
            aa_optimize_params local = p->local;
            inner_ctx ic = {w, 0, 0};
            rc = aa_optimize(&seed, sh->metric, &local, inner_progress, &ic, &out, &r, &e);
            aa_pattern_free(&seed);
            aa_perturb_params pp = p->perturb;
            if (p->seed_iterations > 0)
                pp.max_iterations = p->seed_iterations - r.iterations;
            if (rc == AA_OK && pp.rounds > 0 && aa_perturbable(&out) &&
                (p->seed_iterations <= 0 || pp.max_iterations > 0)) {
                /* Stream 2^32 + i: seed i's perturbations, apart from every seed's stream. */
                aa_rng rng;
                aa_rng_seed(&rng, p->rng_seed, (UINT64_C(1) << 32) + (uint64_t)(p->first_seed + i));
                aa_pattern refined;
                aa_optimize_result rr;
                ic.iterations_before = r.iterations;
                ic.evaluations_before = r.evaluations;
                rc = aa_optimize_perturbed(&out, sh->metric, &local, &pp, &rng, inner_progress, &ic,
                                           &refined, &rr, &e);
                if (rc != AA_OK && rc != AA_ECANCELED) {
                    rc = AA_OK; /* the refinement failed: the seed's own optimum stands */
                } else {
                    aa_pattern_free(&out);
                    out = refined;
                    aa_optimize_result_chain(&r, &rr);
                }
            }
        }
        pthread_mutex_lock(&sh->lock);
        sh->per_seed[i].distribution = distribution;
        sh->per_seed[i].status = rc;
        sh->per_seed[i].initial_e2 = rc && rc != AA_ECANCELED ? NAN : r.initial_e2;
        sh->per_seed[i].e2 = rc && rc != AA_ECANCELED ? NAN : r.e2;
        sh->per_seed[i].iterations = r.iterations;
        sh->done_iterations += r.iterations;
        sh->done_evaluations += r.evaluations;
        sh->live_iterations[w->index] = 0;
        sh->live_evaluations[w->index] = 0;
        sh->seeds_done++;
        pthread_mutex_unlock(&sh->lock);
        if (rc == AA_OK || rc == AA_ECANCELED) {
            /* AA_ECANCELED still hands back the seed's best so far (time budget or cancel). */
            if (out.kernels && r.e2 < w->best_e2) {
                aa_pattern_free(&w->best);
                w->best = out;
                w->best_e2 = r.e2;
                w->best_seed = i;
                w->best_result = r;
            } else {
                aa_pattern_free(&out);
            }
            if (rc == AA_ECANCELED)
                break;
        } else if (rc == AA_ENOMEM || rc == AA_EINVAL) {
            w->status = rc;
            w->err = e;
            break;
        }
    }
}

static int multistart_once(const aa_multistart_params *p, const aa_metric_params *metric,
                           aa_optimize_progress_fn progress, void *user, aa_pattern *best,
                           aa_multistart_result *result, aa_error *err);

typedef struct ranked_config {
    double e2;
    size_t index;
} ranked_config;

static int ranked_cmp(const void *a, const void *b)
{
    const ranked_config *x = a, *y = b;
    if (x->e2 != y->e2)
        return (x->e2 > y->e2) - (x->e2 < y->e2);
    return (x->index > y->index) - (x->index < y->index);
}

/* The two phases of a screened run report as one run: seconds, counts and fraction continue
 * from the screening phase (which gets the first quarter of the fraction), and the best
 * reported never rises above the screening phase's best, since the result keeps it too. */
typedef struct phase_relay {
    aa_optimize_progress_fn progress;
    void *user;
    const aa_multistart_params *params; /* its clock */
    double start;                       /* of the whole call */
    long iterations_before, evaluations_before;
    double fraction_base, fraction_span;
    double best_e2;  /* lowest E2 reported so far, over both phases */
    aa_pattern best; /* its pattern (empty until one is reported) */
} phase_relay;

static int relay_progress(void *user, const aa_optimize_progress *p)
{
    phase_relay *r = user;
    bool improved = p->best && p->best_e2 < r->best_e2;
    if (improved) {
        aa_pattern copy;
        if (aa_pattern_copy(&copy, p->best) == AA_OK) {
            aa_pattern_free(&r->best);
            r->best = copy;
            r->best_e2 = p->best_e2;
        }
    }
    aa_optimize_progress up = {now_of(r->params) - r->start,
                               r->iterations_before + p->iterations,
                               r->evaluations_before + p->evaluations,
                               r->best_e2,
                               r->fraction_base + r->fraction_span * p->fraction,
                               improved,
                               r->best.kernels ? &r->best : NULL};
    return r->progress(r->user, &up);
}

/* Two phases for mirrored families: screen every configuration briefly, then multi-start on the
 * best few. The result is the better of the two phases' bests (a short budget can leave the
 * second phase's seeds above the best screened configuration). */
static int multistart_screened(const aa_multistart_params *p, const aa_metric_params *metric,
                               aa_optimize_progress_fn progress, void *user, aa_pattern *best,
                               aa_multistart_result *result, aa_error *err)
{
    aa_mirrored_config *all;
    size_t count;
    int rc = aa_enumerate_mirrored(p->family->cost, &all, &count, err);
    if (rc)
        return rc;
    double start = now_of(p);
    phase_relay relay = {progress, user, p, start, 0, 0, 0, 0.25, INFINITY, {0}};
    aa_optimize_progress_fn relay_fn = progress ? relay_progress : NULL;
    aa_multistart_params screen = *p;
    screen.screen_top = 0;
    screen.first_seed = 0; /* every configuration, whatever range the call runs */
    screen.configs = all;
    screen.config_count = count;
    screen.seed_count = count;
    screen.local.max_iterations = p->screen_iterations;
    screen.max_seconds = p->max_seconds > 0 ? p->max_seconds / 4 : 0;
    aa_pattern first;
    aa_multistart_result r1;
    rc = multistart_once(&screen, metric, relay_fn, &relay, &first, &r1, err);
    if (rc == AA_ECANCELED) { /* the screening's best so far is the caller's */
        *best = first;
        *result = r1;
        result->seconds = now_of(p) - start;
        aa_pattern_free(&relay.best);
        free(all);
        return rc;
    }
    if (rc) {
        aa_pattern_free(&first);
        aa_multistart_result_free(&r1);
        aa_pattern_free(&relay.best);
        free(all);
        return rc;
    }
    ranked_config *rank = malloc(count * sizeof *rank);
    aa_mirrored_config *top = malloc(count * sizeof *top);
    if (!rank || !top) {
        free(rank);
        free(top);
        free(all);
        aa_pattern_free(&first);
        aa_multistart_result_free(&r1);
        aa_pattern_free(&relay.best);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    for (size_t i = 0; i < count; i++)
        rank[i] = (ranked_config){isnan(r1.per_seed[i].e2) ? INFINITY : r1.per_seed[i].e2, i};
    qsort(rank, count, sizeof *rank, ranked_cmp);
    size_t keep = p->screen_top < count ? p->screen_top : count;
    for (size_t i = 0; i < keep; i++)
        top[i] = all[rank[i].index];
    aa_multistart_params focus = *p;
    focus.screen_top = 0;
    focus.configs = top;
    focus.config_count = keep;
    if (p->max_seconds > 0)
        focus.max_seconds = fmax(0.01, p->max_seconds - (now_of(p) - start));
    relay.iterations_before = r1.iterations;
    relay.evaluations_before = r1.evaluations;
    relay.fraction_base = 0.25;
    relay.fraction_span = 0.75;
    rc = multistart_once(&focus, metric, relay_fn, &relay, best, result, err);
    if (rc == AA_EINVAL && !best->kernels && result->seeds_run == 0 && first.kernels)
        rc = AA_OK; /* the budget ran out before a focused seed ran: the screening's best */
    bool focus_usable = (rc == AA_OK || rc == AA_ECANCELED) && best->kernels;
    if ((rc == AA_OK || rc == AA_ECANCELED) && first.kernels &&
        (!focus_usable || r1.e2 < result->e2)) {
        /* The best screened configuration beat every focused seed: it is the result. */
        aa_pattern_free(best);
        *best = first;
        memset(&first, 0, sizeof first);
        result->e2 = r1.e2;
        result->best_seed = SIZE_MAX;
        result->argmax_kernel = r1.argmax_kernel;
        result->argmax_angle_deg = r1.argmax_angle_deg;
        result->e2_before_snap = r1.e2_before_snap;
    }
    result->iterations += r1.iterations;
    result->evaluations += r1.evaluations;
    result->seconds = now_of(p) - start;
    free(rank);
    free(top);
    free(all);
    aa_pattern_free(&first);
    aa_multistart_result_free(&r1);
    aa_pattern_free(&relay.best);
    return rc;
}

int aa_multistart(const aa_multistart_params *p, const aa_metric_params *metric,
                  aa_optimize_progress_fn progress, void *user, aa_pattern *best,
                  aa_multistart_result *result, aa_error *err)
{
    if (p->family && p->family->mirrored && p->screen_top > 0 && p->screen_iterations > 0 &&
        !p->configs) {
        memset(best, 0, sizeof *best);
        memset(result, 0, sizeof *result);
        return multistart_screened(p, metric, progress, user, best, result, err);
    }
    return multistart_once(p, metric, progress, user, best, result, err);
}

static int multistart_once(const aa_multistart_params *p, const aa_metric_params *metric,
                           aa_optimize_progress_fn progress, void *user, aa_pattern *best,
                           aa_multistart_result *result, aa_error *err)
{
    memset(best, 0, sizeof *best);
    memset(result, 0, sizeof *result);
    if (p->seed_count == 0 || p->seed_count > 1000000)
        return aa_error_set(err, AA_EINVAL, "seeds", "seeds must be 1..1000000");
    if (p->workers < 1 || p->workers > MAX_WORKERS)
        return aa_error_set(err, AA_EINVAL, "workers", "workers must be 1..%d", MAX_WORKERS);
    if (!p->family && !p->seeds)
        return aa_error_set(err, AA_EINVAL, "family", "a family or seed patterns are required");
    if (p->distributions && p->distribution_count == 0)
        return aa_error_set(err, AA_EINVAL, "distributions", "at least one distribution");
    shared_run sh;
    memset(&sh, 0, sizeof sh);
    sh.params = p;
    sh.metric = metric;
    sh.progress = progress;
    sh.user = user;
    sh.start = now_of(p);
    sh.last_call = sh.start - 1;
    sh.snapshot_e2 = INFINITY;
    sh.per_seed = calloc(p->seed_count, sizeof *sh.per_seed);
    worker *ws = calloc((size_t)p->workers, sizeof *ws);
    if (!sh.per_seed || !ws) {
        free(sh.per_seed);
        free(ws);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    for (size_t i = 0; i < p->seed_count; i++) {
        sh.per_seed[i].status = AA_ECANCELED; /* not run */
        sh.per_seed[i].initial_e2 = sh.per_seed[i].e2 = NAN;
    }
    pthread_mutex_init(&sh.lock, NULL);
    for (int k = 0; k < p->workers; k++) {
        ws[k].sh = &sh;
        ws[k].index = k;
    }
    aa_fork_join(ws, sizeof *ws, p->workers, worker_main);
    int rc = AA_OK;
    int winner = -1;
    for (int k = 0; k < p->workers; k++) {
        if (ws[k].status && !rc) {
            rc = ws[k].status;
            if (err)
                *err = ws[k].err;
        }
        if (ws[k].best.kernels &&
            (winner < 0 || ws[k].best_e2 < ws[winner].best_e2 ||
             (ws[k].best_e2 == ws[winner].best_e2 && ws[k].best_seed < ws[winner].best_seed)))
            winner = k;
    }
    result->per_seed = sh.per_seed;
    result->seed_count = p->seed_count;
    result->seeds_run = 0;
    for (size_t i = 0; i < p->seed_count; i++)
        if (!isnan(sh.per_seed[i].e2))
            result->seeds_run++;
    result->iterations = sh.done_iterations;
    result->evaluations = sh.done_evaluations;
    result->seconds = now_of(p) - sh.start;
    if (winner >= 0) {
        *best = ws[winner].best;
        ws[winner].best.kernels = NULL;
        memset(&ws[winner].best, 0, sizeof ws[winner].best);
        result->e2 = ws[winner].best_e2;
        result->best_seed = p->first_seed + ws[winner].best_seed;
        result->argmax_kernel = ws[winner].best_result.argmax_kernel;
        result->argmax_angle_deg = ws[winner].best_result.argmax_angle_deg;
        result->e2_before_snap = ws[winner].best_result.e2_before_snap;
    } else {
        result->e2 = NAN;
    }
    bool cancelled = sh.cancel;
    if (progress && !cancelled && winner >= 0) {
        aa_optimize_progress up = {
            result->seconds, result->iterations, result->evaluations, result->e2, 1.0, true, best};
        progress(user, &up);
    }
    for (int k = 0; k < p->workers; k++)
        aa_pattern_free(&ws[k].best);
    aa_pattern_free(&sh.snapshot);
    pthread_mutex_destroy(&sh.lock);
    free(ws);
    if (rc)
        return rc;
    if (cancelled)
        return aa_error_set(err, AA_ECANCELED, "", "cancelled by the progress callback");
    if (winner < 0)
        return aa_error_set(err, AA_EINVAL, "seeds", "no seed could be optimised");
    return AA_OK;
}
