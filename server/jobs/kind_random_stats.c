/* Job kind "random-stats" (L&A Table 3): N random patterns of a distribution in a family, with
 * weights from the filter's impulse response; min / average / max E2; then the best of them
 * optimised for weights only ("Opt W") and, again from the best random pattern, for weights and
 * positions ("Opt W+P"), each with half of the remaining time budget. Opt W+P does not start
 * from Opt W: the weights-only optimum is a kink of the max where the descent finds no step in
 * the joint space either (measured, P(16,16,4) Poisson: W+P from Opt W 0.241 = Opt W, from the
 * random pattern 0.199). Spec: {"kind":"random-stats",
 * "family":"P(1,4,2)", "count":N?, "distribution":"uniform"?, "max_seconds":S?, "rng_seed":K?,
 * "filter":F?, "acuity":A?, "angles":[...]?}. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "kind_optimize_spec.h"
#include "aa_optimizer.h"

typedef struct stats_params {
    opt_common_spec common;
    aa_family family;
    size_t count;
    aa_seed_kind kind;
} stats_params;

static void stats_free(void *params)
{
    stats_params *sp = params;
    if (!sp)
        return;
    opt_common_free(&sp->common);
    free(sp);
}

static const char *const stats_keys[] = {"kind",        "family",   "count",  "distribution",
                                         "max_seconds", "rng_seed", "method", "filter",
                                         "acuity",      "angles",   NULL};

static int stats_parse(const json_t *spec, void **params, aa_error *err)
{
    *params = NULL;
    int rc = opt_spec_check_keys(spec, stats_keys, err);
    if (rc)
        return rc;
    stats_params *sp = calloc(1, sizeof *sp);
    if (!sp)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    rc = opt_common_parse(spec, 30, &sp->common, err);
    const char *family = NULL, *dist = "uniform";
    if (!rc)
        rc = opt_spec_string(spec, "family", &family, err);
    if (!rc && !family)
        rc = aa_error_set(err, AA_EINVAL, "family", "family is required");
    if (!rc)
        rc = aa_family_parse(family, &sp->family, err);
    json_int_t n = 1000;
    if (!rc)
        rc = opt_spec_integer(spec, "count", 1, 1000000, &n, err);
    sp->count = (size_t)n;
    if (!rc)
        rc = opt_spec_string(spec, "distribution", &dist, err);
    if (!rc && aa_seed_kind_parse(dist, &sp->kind))
        rc = aa_error_set(err, AA_EINVAL, "distribution",
                          "must be uniform, jittered, n-rooks, poisson or lloyd");
    if (rc) {
        stats_free(sp);
        return rc;
    }
    *params = sp;
    return AA_OK;
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

static int stats_run(void *params, job_ctx *ctx, json_t **result, aa_error *err)
{
    stats_params *sp = params;
    aa_metric_params metric = opt_common_metric(&sp->common);
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
    aa_optimize_method mw = opt_common_method(&sp->common, tiled, AA_OPTIMIZE_WEIGHTS);
    aa_optimize_method mwp = opt_common_method(&sp->common, tiled, AA_OPTIMIZE_BOTH);
    if (!rc)
        rc = optimize_stage(&best, &metric, AA_OPTIMIZE_WEIGHTS, mw, sp->common.max_seconds / 2,
                            sp->common.rng_seed, &b, &optw, &rw, err);
    b.base = 0.6;
    if (!rc)
        rc = optimize_stage(&best, &metric, AA_OPTIMIZE_BOTH, mwp, sp->common.max_seconds / 2,
                            sp->common.rng_seed, &b, &optwp, &rwp, err);
    if (!rc) {
        *result = json_pack(
            "{s:s,s:s,s:I,s:{s:o,s:o,s:o},s:o,s:{s:o,s:o,s:s},s:{s:o,s:o,s:s}}", "family",
            sp->family.label, "distribution", aa_seed_kind_name(sp->kind), "count",
            (json_int_t)rs.count, "random", "min", proto_real(rs.min), "avg", proto_real(rs.avg),
            "max", proto_real(rs.max), "best_random", proto_encode_pattern(&best), "opt_w", "e2",
            proto_real(rw.e2), "pattern", proto_encode_pattern(&optw), "method",
            aa_optimize_method_name(mw), "opt_wp", "e2", proto_real(rwp.e2), "pattern",
            proto_encode_pattern(&optwp), "method", aa_optimize_method_name(mwp));
        if (!*result)
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
        /* Opt W+P as the job's "best" / "e2", like the optimize kind's result. */
        if (!rc) {
            json_object_set_new(*result, "best", proto_encode_pattern(&optwp));
            json_object_set_new(*result, "e2", proto_real(rwp.e2));
        }
    }
    aa_pattern_free(&best);
    aa_pattern_free(&optw);
    aa_pattern_free(&optwp);
    return rc;
}

const job_kind job_kind_random_stats = {
    .name = "random-stats", .parse = stats_parse, .run = stats_run, .free_params = stats_free};
