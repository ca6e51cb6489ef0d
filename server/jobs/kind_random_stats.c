/* Job kind "random-stats" (L&A Table 3): N random patterns of a distribution in a family, with
 * weights from the filter's impulse response; min / average / max E2; then the best of them
 * optimised for weights only ("Opt W") and, again from the best random pattern, for weights and
 * positions ("Opt W+P"), each with half of the remaining time budget. Opt W+P does not start
 * from Opt W: the weights-only optimum is a kink of the max where the descent finds no step in
 * the joint space either (measured, P(16,16,4) Poisson: W+P from Opt W 0.241 = Opt W, from the
 * random pattern 0.199). The spec is proto/job_random_stats.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "job_random_stats.h"
#include "kinds.h"
#include "optimizer_bridge.h"
#include "aa_optimizer.h"

JOB_KIND_SPEC_PARAMS(kind_random_stats, proto_random_stats_spec, proto_decode_random_stats_spec,
                     proto_random_stats_spec_free)

double kind_random_stats_max_seconds(const void *params)
{
    return ((const proto_random_stats_spec *)params)->common.max_seconds;
}

const char *kind_random_stats_family(const void *params)
{
    const proto_random_stats_spec *sp = params;
    return sp->family.label;
}

json_t *kind_random_stats_best_of(const json_t *result, double *e2)
{
    proto_random_stats_result r;
    aa_error err = {0};
    *e2 = NAN;
    if (proto_decode_random_stats_result(result, &r, &err))
        return NULL;
    *e2 = r.opt_wp.e2;
    json_t *best = proto_encode_pattern(&r.opt_wp.pattern);
    proto_random_stats_result_free(&r);
    return best;
}

static int optimize_stage(const aa_pattern *seed, const aa_metric_params *metric,
                          aa_optimize_mode mode, aa_optimize_method method, double seconds,
                          uint64_t rng_seed, opt_job_bridge *b, aa_pattern *out,
                          aa_optimize_result *r, aa_error *err)
{
    aa_optimize_params op;
    aa_optimize_params_default(&op);
    op.mode = mode;
    op.method = method;
    op.max_seconds = seconds;
    op.max_iterations = 1000000;
    op.stall_iterations = 2000;
    op.clock = job_ctx_clock(b->ctx);
    int rc = aa_optimize(seed, metric, &op, opt_job_progress, b, out, r, err);
    b->iterations_before += r->iterations;
    b->evaluations_before += r->evaluations;
    b->seconds_before += r->seconds;
    if (rc == AA_OK && mode == AA_OPTIMIZE_BOTH && aa_perturbable(out) && r->seconds < seconds) {
        /* The descent stops at a kink within seconds: spend the rest of the stage's budget on
         * iterated local search from its optimum (as optimize jobs do for tiled families). */
        aa_perturb_params pp;
        aa_perturb_params_default(&pp);
        pp.rounds = AA_PERTURB_UNTIL_STALL;
        pp.max_seconds = seconds - r->seconds;
        aa_rng rng;
        aa_rng_seed(&rng, rng_seed, 1);
        aa_pattern refined;
        aa_optimize_result rr;
        int prc = aa_optimize_perturbed(out, metric, &op, &pp, &rng, opt_job_progress, b, &refined,
                                        &rr, err);
        if (prc == AA_OK || prc == AA_ECANCELED) {
            b->iterations_before += rr.iterations;
            b->evaluations_before += rr.evaluations;
            b->seconds_before += rr.seconds;
            aa_pattern_free(out);
            *out = refined;
            aa_optimize_result_chain(r, &rr);
            rc = prc; /* AA_ECANCELED: the job was cancelled */
        }
    }
    return rc;
}

/* The random patterns are the job's first 20%. */
typedef struct random_progress {
    job_ctx *ctx;
    size_t count;
} random_progress;

static int random_patterns_progress(void *user, size_t i)
{
    const random_progress *rp = user;
    return job_ctx_progress(rp->ctx, 0.2 * (double)i / (double)rp->count, NULL);
}

static int random_stats_run(void *params, job_ctx *ctx, proto_random_stats_result *out,
                            aa_error *err)
{
    proto_random_stats_spec *sp = params;
    aa_metric_params metric = proto_optimizer_spec_metric(&sp->common);
    aa_rng rng;
    aa_rng_seed(&rng, sp->common.rng_seed, 0);
    opt_job_bridge b = {ctx, 0, 0.2, 0, 0, 0, INFINITY, -1};
    aa_pattern best;
    aa_random_stats rs;
    random_progress rp = {ctx, sp->count};
    int rc = aa_random_patterns(&sp->family, sp->kind, &metric, &rng, sp->count,
                                random_patterns_progress, &rp, &best, &rs, err);
    aa_pattern optw, optwp;
    memset(&optw, 0, sizeof optw);
    memset(&optwp, 0, sizeof optwp);
    aa_optimize_result rw, rwp;
    memset(&rw, 0, sizeof rw);
    memset(&rwp, 0, sizeof rwp);
    b.base = 0.2;
    b.span = 0.4;
    bool tiled = !rc && aa_pattern_tiled_without_border(&best);
    aa_optimize_method mw = proto_optimizer_spec_method(&sp->common, tiled, AA_OPTIMIZE_WEIGHTS);
    aa_optimize_method mwp = proto_optimizer_spec_method(&sp->common, tiled, AA_OPTIMIZE_BOTH);
    if (!rc)
        rc = optimize_stage(&best, &metric, AA_OPTIMIZE_WEIGHTS, mw, sp->common.max_seconds / 2,
                            sp->common.rng_seed, &b, &optw, &rw, err);
    b.base = 0.6;
    if (!rc)
        rc = optimize_stage(&best, &metric, AA_OPTIMIZE_BOTH, mwp, sp->common.max_seconds / 2,
                            sp->common.rng_seed, &b, &optwp, &rwp, err);
    if (!rc) {
        /* The result owns the patterns now. */
        *out = (proto_random_stats_result){.distribution = sp->kind,
                                           .count = (long)rs.count,
                                           .min = rs.min,
                                           .avg = rs.avg,
                                           .max = rs.max,
                                           .best_random = best,
                                           .opt_w = {rw.e2, optw, mw},
                                           .opt_wp = {rwp.e2, optwp, mwp}};
        snprintf(out->family, sizeof out->family, "%s", sp->family.label);
        return AA_OK;
    }
    aa_pattern_free(&best);
    aa_pattern_free(&optw);
    aa_pattern_free(&optwp);
    return rc;
}

JOB_KIND_RESULT(kind_random_stats, proto_random_stats_result, random_stats_run,
                proto_encode_random_stats_result, proto_random_stats_result_free)
