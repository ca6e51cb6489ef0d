/* The smoothed step rule (AA_METHOD_SMOOTH): quasi-Newton descent of a smooth stand-in for the
 * max, with continuation towards the max itself.
 *
 * E2 = max_i f_i (f_i = W(theta) E1(theta) of one kernel and angle) has a kink wherever two terms
 * tie, and optima sit on many such kinks at once, which stalls first-order descents of the max
 * (optimizer_perturb.c). The Lp norm F_p = (sum_i f_i^p)^(1/p) is smooth away from E1's own
 * kinks, lies between E2 and N^(1/p) E2 (N terms: 576 for P(16,16,4), so within 2.5% at
 * p = 256), and its gradient sum_i (f_i / F_p)^(p-1) grad f_i weights the near-maximal terms
 * automatically. L-BFGS (liblbfgs, More-Thuente line search) minimises F_p for p = 16, 32, ...,
 * 65536, each stage from the best pattern so far; the best true E2 seen at any evaluation is
 * kept, so the result and the trace are monotone in E2. E1 itself has kinks where two
 * projections cross (docs/metric.md section 7), and optima collect pairs held aligned by them;
 * the stages smooth those over a width kink_width * 16 / p (aa_e1_smoothed_at_direction: 0.3 px
 * at p = 16 down to 7e-5 px at 65536 by default). The first stages thus descend a stand-in far
 * from E1 (at 0.3 px most terms of an optimised P(16,16,4) drop to 0), the later ones one within
 * a few per cent; measured, this reaches lower optima (P(16,16,4) 0.1548 against 0.1564 in
 * 600 s). The E2 kept is always the exact one (docs/optimizer.md, "E1's crossing kinks"). Before
 * it, on P(16,16,4) from a Poisson seed: 0.176-0.181 in 13-19 s, where the L&A rule stops at
 * 0.196-0.199 and the minimax step at 0.185-0.213 (bench_step_rules); neither of them improves the
 * smooth rule's end point. Stages past 4096 gain ~3e-5. Positions leave their box only at a
 * quadratic penalty and are clamped into it before E1 is evaluated; weights move along Sigma w = 1
 * (the metric's projected gradients), so every iterate keeps the family's structure. Cost per
 * evaluation of P(16,16,4): all E1 values (~1.3 ms) and the gradients of the terms whose factor
 * (f_i / F_p)^(p-1) exceeds 1e-9. */
#include <lbfgs.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "optimizer_run.h"

#define SMOOTH_FIRST_P 16
#define SMOOTH_MAX_P 65536
#define SMOOTH_PENALTY 1e4 /* per squared pixel outside a point's box */
#define SMOOTH_RESTARTS 20
#define SMOOTH_RESTART_GAIN 1e-4
#define SMOOTH_MIN_KINK_WIDTH 1e-7 /* below: the exact E1 */

typedef struct smooth_ctx {
    opt_loop *L;
    size_t np, nw; /* points, weight slots */
    double p;      /* current exponent */
    int stop;      /* why the run stops: 1 (budget), AA_ECANCELED or an error */
} smooth_ctx;

/* x = [x_0..x_np-1, y_0..y_np-1, w_0..w_nw-1] into trial (points clamped), kernels applied;
 * returns the penalty of the unclamped points. */
static double load_trial(smooth_ctx *c, const lbfgsfloatval_t *x, double *pen_grad)
{
    opt_state *st = &c->L->trial;
    double pen = 0;
    for (size_t m = 0; m < c->np; m++) {
        opt_point *pt = &st->points[m];
        double vx = x[m], vy = x[c->np + m];
        double ex = vx < pt->lo_x ? vx - pt->lo_x : vx > pt->hi_x ? vx - pt->hi_x : 0;
        double ey = vy < pt->lo_y ? vy - pt->lo_y : vy > pt->hi_y ? vy - pt->hi_y : 0;
        pen += SMOOTH_PENALTY * (ex * ex + ey * ey);
        pen_grad[m] = 2 * SMOOTH_PENALTY * ex;
        pen_grad[c->np + m] = 2 * SMOOTH_PENALTY * ey;
        pt->x = vx;
        pt->y = vy;
        opt_point_clamp(pt);
    }
    memcpy(st->weights, x + 2 * c->np, c->nw * sizeof *st->weights);
    opt_state_apply(st);
    return pen;
}

static lbfgsfloatval_t evaluate(void *instance, const lbfgsfloatval_t *x, lbfgsfloatval_t *g,
                                const int n, const lbfgsfloatval_t step)
{
    (void)step;
    smooth_ctx *c = instance;
    opt_loop *L = c->L;
    opt_run *r = &L->run;
    opt_state *st = &L->trial;
    memset(g, 0, (size_t)n * sizeof *g);
    double pen = load_trial(c, x, g);
    double e2;
    int rc = opt_run_eval_e2(r, st, &e2);
    if (rc) {
        c->stop = rc;
        return INFINITY;
    }
    opt_loop_offer_best(L, st, e2);
    size_t kc = st->work.kernel_count, na = r->angle_count;
    /* F_p scaled by the max so that f^p neither overflows nor underflows. */
    /* The stand-in is built from the smoothed terms (exact at kink width 0). */
    const double *f = r->smoothed;
    double top = 0;
    for (size_t i = 0; i < kc * na; i++)
        top = fmax(top, f[i]);
    double sum = 0;
    for (size_t i = 0; i < kc * na; i++)
        sum += pow(f[i] / top, c->p);
    double F = top * pow(sum, 1.0 / c->p);
    const opt_gradient_target to = {g, g + c->np, g + 2 * c->np, 0, 0, NULL, NULL};
    for (size_t k = 0; k < kc; k++)
        for (size_t a = 0; a < na; a++) {
            double factor = pow(f[k * na + a] / F, c->p - 1) * r->weight[a];
            if (factor < 1e-9)
                continue;
            if ((rc = opt_run_add_term_gradient(r, st, k, a, factor, &to))) {
                c->stop = rc;
                return INFINITY;
            }
        }
    return F + pen;
}

static int progress(void *instance, const lbfgsfloatval_t *x, const lbfgsfloatval_t *g,
                    const lbfgsfloatval_t fx, const lbfgsfloatval_t xnorm,
                    const lbfgsfloatval_t gnorm, const lbfgsfloatval_t step, int n, int k, int ls)
{
    (void)x, (void)g, (void)fx, (void)xnorm, (void)gnorm, (void)step, (void)n, (void)k, (void)ls;
    smooth_ctx *c = instance;
    c->L->it++;
    int rc = opt_loop_tick(c->L);
    if (rc)
        c->stop = rc;
    return rc;
}

int opt_descend_smooth(opt_loop *L)
{
    smooth_ctx c = {L, L->cur.point_count, L->cur.weight_count, SMOOTH_FIRST_P, 0};
    int n = (int)(2 * c.np + c.nw);
    lbfgsfloatval_t *x = lbfgs_malloc(n);
    if (!x)
        return aa_error_set(L->err, AA_ENOMEM, "", "out of memory");
    const aa_optimize_params *params = L->run.params;
    for (; c.p <= SMOOTH_MAX_P && !c.stop; c.p *= 2) {
        /* E1's crossing kinks smoothed over a width that shrinks with the max's smoothing */
        double h = params->kink_width * SMOOTH_FIRST_P / c.p;
        L->run.kink_width = h >= SMOOTH_MIN_KINK_WIDTH ? h : 0;
        /* Each stage starts from the best pattern so far. When the line search gives up at a
         * kink of E1 (liblbfgs returns an error and the last good point), the stage goes on
         * from there with a fresh Hessian estimate as long as that still lowers F_p. */
        for (size_t m = 0; m < c.np; m++) {
            x[m] = L->top.points[m].x;
            x[c.np + m] = L->top.points[m].y;
        }
        memcpy(x + 2 * c.np, L->top.weights, c.nw * sizeof *x);
        double previous = INFINITY;
        for (int restart = 0; restart < SMOOTH_RESTARTS && !c.stop; restart++) {
            lbfgs_parameter_t lp;
            lbfgs_parameter_init(&lp);
            lp.epsilon = 1e-7;
            lp.past = 20;
            lp.delta = params->rel_tolerance;
            lp.max_iterations = 100000;
            lp.linesearch = LBFGS_LINESEARCH_MORETHUENTE;
            lbfgsfloatval_t fx = INFINITY;
            int lrc = lbfgs(n, x, &fx, evaluate, progress, &c, &lp);
            if (lrc >= 0 || !(fx < previous * (1 - SMOOTH_RESTART_GAIN)))
                break; /* converged, or going on no longer pays */
            previous = fx;
        }
    }
    L->run.kink_width = 0;
    lbfgs_free(x);
    int rc = c.stop; /* the result is read from top */
    return rc == 1 ? AA_OK : rc;
}
