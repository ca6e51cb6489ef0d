#include "table3.h"

#include <math.h>
#include <string.h>

static const aa_table3_paper paper_rows[] = {
    {AA_SEED_JITTERED, 0.423, 0.622, 0.907, 0.242, 0.169},
    {AA_SEED_POISSON, 0.346, 0.473, 0.782, 0.221, 0.161},
};

const aa_table3_paper *aa_table3_paper_row(aa_seed_distribution distribution)
{
    for (size_t i = 0; i < sizeof paper_rows / sizeof paper_rows[0]; i++)
        if (paper_rows[i].distribution == distribution)
            return &paper_rows[i];
    return NULL;
}

void aa_table3_params_default(aa_table3_params *p)
{
    memset(p, 0, sizeof *p);
    p->count = 1000;
    p->opt_w_seconds = 60;
    p->opt_wp_seconds = 60;
    p->opt_wp_method = -1;
}

void aa_table3_cell_free(aa_table3_cell *c)
{
    aa_pattern_free(&c->best_random);
    aa_pattern_free(&c->opt_wp_pattern);
}

void aa_mean_sd(const double *v, size_t n, double *mean, double *sd)
{
    double s = 0, q = 0;
    for (size_t i = 0; i < n; i++)
        s += v[i];
    *mean = n ? s / (double)n : NAN;
    for (size_t i = 0; i < n; i++)
        q += (v[i] - *mean) * (v[i] - *mean);
    *sd = n > 1 ? sqrt(q / (double)(n - 1)) : 0;
}

typedef struct relay {
    aa_table3_progress_fn fn;
    void *user;
    int phase;
    size_t count;
} relay;

static int relay_random(void *user, size_t i)
{
    relay *r = user;
    aa_table3_progress p = {0, (double)i / (double)r->count, NULL};
    return r->fn ? r->fn(r->user, &p) : 0;
}

static int relay_opt(void *user, const aa_optimize_progress *op)
{
    relay *r = user;
    aa_table3_progress p = {r->phase, 1, op};
    return r->fn ? r->fn(r->user, &p) : 0;
}

/* Stream of Opt W+P's iterated local search: apart from every pattern's stream (rng_seed, i). */
#define PERTURB_STREAM (UINT64_C(1) << 32)

static int opt_stage(const aa_pattern *start, const aa_metric_params *metric, aa_optimize_mode mode,
                     const aa_table3_params *tp, uint64_t rng_seed, relay *rl, aa_pattern *out,
                     aa_optimize_result *r, aa_optimize_method *method, aa_error *err)
{
    double seconds = mode == AA_OPTIMIZE_BOTH ? tp->opt_wp_seconds : tp->opt_w_seconds;
    long iterations = mode == AA_OPTIMIZE_BOTH ? tp->max_iterations : 0;
    aa_optimize_params op;
    aa_optimize_params_default(&op);
    op.mode = mode;
    op.method = *method = mode == AA_OPTIMIZE_BOTH && tp->opt_wp_method >= 0
                              ? (aa_optimize_method)tp->opt_wp_method
                              : aa_auto_method(aa_pattern_tiled_without_border(start), mode);
    op.max_seconds = seconds;
    op.max_iterations = iterations > 0 ? iterations : 1000000;
    op.stall_iterations = 2000;
    op.clock = tp->clock;
    /* Opt W+P: the descent stops at a kink well within its budget, iterated local search
     * spends the rest. */
    aa_perturb_params pp;
    aa_perturb_params_default(&pp);
    pp.rounds = AA_PERTURB_UNTIL_STALL;
    aa_rng rng;
    aa_rng_seed(&rng, rng_seed, PERTURB_STREAM);
    return aa_optimize_refined(start, metric, &op, iterations, &pp, &rng, relay_opt, rl, out, r,
                               err);
}

int aa_table3_cell_run(const aa_family *family, aa_seed_distribution distribution,
                       const aa_metric_params *metric, const aa_table3_params *params,
                       uint64_t rng_seed, aa_table3_progress_fn progress, void *user,
                       aa_table3_cell *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    out->opt_w = out->opt_wp = NAN;
    relay rl = {progress, user, 0, params->count};
    int rc = aa_random_patterns_range_visit(family, distribution, params->poisson_radius, metric,
                                            rng_seed, 0, params->count, relay_random, &rl,
                                            params->visit, params->visit_user, NULL,
                                            &out->best_random, &out->best_index, &out->random, err);
    if (rc)
        return rc;
    aa_pattern w;
    memset(&w, 0, sizeof w);
    rl.phase = 1;
    rc = opt_stage(&out->best_random, metric, AA_OPTIMIZE_WEIGHTS, params, rng_seed, &rl, &w,
                   &out->opt_w_run, &out->opt_w_method, err);
    aa_pattern_free(&w);
    if (rc)
        return rc;
    out->opt_w = out->opt_w_run.e2;
    rl.phase = 2;
    rc = opt_stage(&out->best_random, metric, AA_OPTIMIZE_BOTH, params, rng_seed, &rl,
                   &out->opt_wp_pattern, &out->opt_wp_run, &out->opt_wp_method, err);
    if (!rc)
        out->opt_wp = out->opt_wp_run.e2;
    return rc;
}
