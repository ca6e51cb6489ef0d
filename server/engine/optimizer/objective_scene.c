/* The scene objective and its descent (objective_scene.h). */
#include "objective_scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "optimizer_state.h"

#define PI 3.14159265358979323846

int aa_scene_objective_eval(const aa_scene_objective *o, const aa_pattern *p,
                            aa_metric_workspace *ws, double *value, double *gx, double *gy,
                            double *gw, aa_error *err)
{
    aa_filter fd;
    const aa_filter *f = o->filter;
    if (!f) {
        aa_filter_default(&fd);
        f = &fd;
    }
    if (!(o->pixels > 0))
        return aa_error_set(err, AA_EINVAL, "scene", "the scene has no pixels");
    size_t K = p->kernel_count, total = aa_pattern_total_kernel_samples(p);
    double *e1 = malloc(K * AA_SCENE_BINS * sizeof *e1);
    if (!e1)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    double q = 0;
    int rc = AA_OK;
    for (size_t k = 0; k < K && !rc; k++) {
        const aa_kernel *ker = &p->kernels[k];
        for (int d = 0; d < AA_SCENE_BINS && !rc; d++) {
            double *e = &e1[k * AA_SCENE_BINS + d];
            *e = 0;
            if (o->length[d] <= 0)
                continue;
            double c, s;
            aa_metric_direction(d * PI / 180, &c, &s);
            rc = aa_e1_at_direction(f, ker->samples, ker->count, c, s, AA_E1_AUTO, ws, e);
            q += o->length[d] * *e * *e / (double)K;
        }
    }
    if (!rc && !(q > 0))
        rc = aa_error_set(err, AA_EINVAL, "scene", "the scene has no edges the model covers");
    else if (rc)
        rc = aa_error_set(err, rc, "pattern", "E1 failed (an empty kernel?)");
    if (rc) {
        free(e1);
        return rc;
    }
    *value = 255 * sqrt(q / o->pixels);
    if (gx) {
        memset(gx, 0, total * sizeof *gx);
        memset(gy, 0, total * sizeof *gy);
        memset(gw, 0, total * sizeof *gw);
        size_t nmax = 0;
        for (size_t k = 0; k < K; k++)
            nmax = p->kernels[k].count > nmax ? p->kernels[k].count : nmax;
        double *dx = malloc(3 * (nmax ? nmax : 1) * sizeof *dx), *dy = dx + nmax,
               *dw = dx + 2 * nmax;
        if (!dx) {
            free(e1);
            return aa_error_set(err, AA_ENOMEM, "", "out of memory");
        }
        double scale = 255 / (K * sqrt(o->pixels * q));
        size_t off = 0;
        for (size_t k = 0; k < K && !rc; k++) {
            const aa_kernel *ker = &p->kernels[k];
            for (int d = 0; d < AA_SCENE_BINS && !rc; d++) {
                if (o->length[d] <= 0)
                    continue;
                double c, s, e;
                aa_metric_direction(d * PI / 180, &c, &s);
                rc = aa_e1_gradient_at_direction(f, ker->samples, ker->count, c, s, AA_E1_AUTO, ws,
                                                 &e, dx, dy, dw);
                double factor = scale * o->length[d] * e;
                for (size_t i = 0; i < ker->count && !rc; i++) {
                    gx[off + i] += factor * dx[i];
                    gy[off + i] += factor * dy[i];
                    gw[off + i] += factor * dw[i];
                }
            }
            off += ker->count;
        }
        free(dx);
        if (rc)
            rc = aa_error_set(err, rc, "pattern", "E1 gradient failed");
    }
    free(e1);
    return rc;
}

/* One evaluation of a state: scene term (and gradient), true E2 and its power-mean stand-in
 * (and gradient). */
typedef struct scene_eval {
    double f_true, f_smooth, fold, scene, e2, e2p; /* fold: S; scene: the reported term */
} scene_eval;

typedef struct scene_run {
    const aa_metric_params *metric;
    const aa_scene_objective *o;
    const aa_scene_optimize_params *params;
    double fold_ref; /* S of the seed: the smooth F's reference */
    aa_metric_workspace ws;
    size_t total;
    double *gx, *gy, *gw; /* per kernel sample, scene term */
    double *hx, *hy, *hw; /* per kernel sample, E2 stand-in */
    double *vx, *vy, *vw; /* on the free variables */
    double *tx, *ty, *tw; /* scratch of one E1 gradient (max kernel size) */
    long evaluations;
} scene_run;

static int run_eval(scene_run *r, opt_state *st, bool gradient, scene_eval *out, aa_error *err)
{
    const aa_scene_optimize_params *pp = r->params;
    double alpha = pp->blend;
    opt_state_apply(st);
    const aa_pattern *p = &st->work;
    r->evaluations++;
    int rc = aa_scene_objective_eval(r->o, p, &r->ws, &out->fold, gradient ? r->gx : NULL, r->gy,
                                     r->gw, err);
    out->scene = out->fold;
    /* Trials are judged by the smooth F; the exact term only where a state may become best. */
    if (!rc && gradient && r->o->exact)
        rc = r->o->exact(r->o->exact_user, p, &out->scene, err);
    if (rc)
        return rc;
    aa_metric_params mp = *r->metric;
    mp.lp = AA_SCENE_E2_POWER;
    aa_evaluation ev;
    if ((rc = aa_evaluate(p, &mp, &ev, err)))
        return rc;
    out->e2 = ev.e2;
    out->e2p = ev.lp_norm;
    double sr = pp->scene_ref, er = pp->e2_ref;
    out->f_true = (1 - alpha) * out->scene / sr + alpha * out->e2 / er;
    out->f_smooth = (1 - alpha) * out->fold / r->fold_ref + alpha * out->e2p / er;
    if (gradient) {
        memset(r->hx, 0, r->total * sizeof *r->hx);
        memset(r->hy, 0, r->total * sizeof *r->hy);
        memset(r->hw, 0, r->total * sizeof *r->hw);
        if (alpha > 0) {
            const aa_filter *f = r->metric->filter;
            aa_filter fd;
            if (!f) {
                aa_filter_default(&fd);
                f = &fd;
            }
            double P = AA_SCENE_E2_POWER, M = (double)(ev.kernel_count * ev.angle_count);
            size_t off = 0;
            for (size_t k = 0; k < ev.kernel_count && !rc; k++) {
                const aa_kernel *ker = &p->kernels[k];
                for (size_t a = 0; a < ev.angle_count && !rc; a++) {
                    double t = ev.weight[a] * ev.e1[k * ev.angle_count + a];
                    /* d Ep / d t = (1/M) (t / Ep)^(p-1); terms far below the mean add nothing. */
                    double dt = pow(t / ev.lp_norm, P - 1) / M;
                    if (dt < 1e-12)
                        continue;
                    double e, factor = alpha / er * dt * ev.weight[a];
                    rc = aa_e1_gradient_at_angle(f, ker->samples, ker->count,
                                                 ev.angles_deg[a] * PI / 180, &r->ws, &e, r->tx,
                                                 r->ty, r->tw);
                    for (size_t i = 0; i < ker->count && !rc; i++) {
                        r->hx[off + i] += factor * r->tx[i];
                        r->hy[off + i] += factor * r->ty[i];
                        r->hw[off + i] += factor * r->tw[i];
                    }
                }
                off += ker->count;
            }
            if (rc)
                rc = aa_error_set(err, rc, "pattern", "E1 gradient failed");
        }
        /* Onto the free variables: mirror signs, shared samples summed, fixed coordinates and
         * the coordinates the mode does not move left out. */
        memset(r->vx, 0, st->point_count * sizeof *r->vx);
        memset(r->vy, 0, st->point_count * sizeof *r->vy);
        memset(r->vw, 0, st->weight_count * sizeof *r->vw);
        aa_optimize_mode mode = pp->local.mode;
        double sc = (1 - alpha) / r->fold_ref;
        size_t off = 0;
        for (size_t k = 0; k < p->kernel_count; k++) {
            for (size_t i = 0; i < p->kernels[k].count; i++, off++) {
                const opt_ref *ref = &st->refs[k][i];
                const opt_point *pt = &st->points[ref->point];
                if (mode != AA_OPTIMIZE_WEIGHTS) {
                    if (pt->lo_x < pt->hi_x)
                        r->vx[ref->point] += ref->sx * (sc * r->gx[off] + r->hx[off]);
                    if (pt->lo_y < pt->hi_y)
                        r->vy[ref->point] += ref->sy * (sc * r->gy[off] + r->hy[off]);
                }
                if (mode != AA_OPTIMIZE_POSITIONS)
                    r->vw[ref->weight] += sc * r->gw[off] + r->hw[off];
            }
        }
    }
    aa_evaluation_free(&ev);
    return rc;
}

/* trial := base - step * v / max|v| (step in pixels or weight units), projected. */
static void take_step(const scene_run *r, opt_state *trial, const opt_state *base, double step)
{
    double m = 0;
    for (size_t i = 0; i < base->point_count; i++)
        m = fmax(m, fmax(fabs(r->vx[i]), fabs(r->vy[i])));
    for (size_t i = 0; i < base->weight_count; i++)
        m = fmax(m, fabs(r->vw[i]));
    double s = m > 0 ? step / m : 0;
    for (size_t i = 0; i < base->point_count; i++) {
        trial->points[i] = base->points[i];
        trial->points[i].x -= s * r->vx[i];
        trial->points[i].y -= s * r->vy[i];
        opt_point_clamp(&trial->points[i]);
    }
    for (size_t i = 0; i < base->weight_count; i++)
        trial->weights[i] = base->weights[i] - s * r->vw[i];
    opt_state_normalize_weights(trial);
    opt_state_apply(trial);
}

static void copy_vars(opt_state *dst, const opt_state *src)
{
    memcpy(dst->points, src->points, src->point_count * sizeof *src->points);
    memcpy(dst->weights, src->weights, src->weight_count * sizeof *src->weights);
    opt_state_apply(dst);
}

static void run_free(scene_run *r)
{
    aa_metric_workspace_free(&r->ws);
    free(r->gx);
    free(r->vx);
    free(r->tx);
}

static int run_init(scene_run *r, const opt_state *st, aa_error *err)
{
    aa_metric_workspace_init(&r->ws);
    size_t n = r->total ? r->total : 1, pc = st->point_count ? st->point_count : 1,
           wc = st->weight_count ? st->weight_count : 1, nmax = 1;
    for (size_t k = 0; k < st->work.kernel_count; k++)
        nmax = st->work.kernels[k].count > nmax ? st->work.kernels[k].count : nmax;
    r->gx = malloc(6 * n * sizeof *r->gx);
    r->vx = malloc((2 * pc + wc) * sizeof *r->vx);
    r->tx = malloc(3 * nmax * sizeof *r->tx);
    if (!r->gx || !r->vx || !r->tx) {
        run_free(r);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    r->gy = r->gx + n;
    r->gw = r->gx + 2 * n;
    r->hx = r->gx + 3 * n;
    r->hy = r->gx + 4 * n;
    r->hw = r->gx + 5 * n;
    r->vy = r->vx + pc;
    r->vw = r->vx + 2 * pc;
    r->ty = r->tx + nmax;
    r->tw = r->tx + 2 * nmax;
    return AA_OK;
}

static int report(aa_scene_progress_fn fn, void *user, const aa_clock *clock, double start,
                  double *last, long it, const scene_eval *b, const opt_state *top, bool force)
{
    if (!fn)
        return AA_OK;
    double now = aa_clock_seconds(clock);
    if (!force && now - *last < 0.01)
        return AA_OK;
    *last = now;
    aa_scene_progress pr = {now - start, it, b->f_true, b->scene, b->e2, &top->work};
    return fn(user, &pr) ? AA_ECANCELED : AA_OK;
}

int aa_scene_objective_blend(const aa_pattern *p, const aa_metric_params *metric,
                             const aa_scene_objective *o, double blend, double scene_ref,
                             double e2_ref, double *objective, double *scene, double *e2,
                             aa_error *err)
{
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    int rc = aa_scene_objective_eval(o, p, &ws, scene, NULL, NULL, NULL, err);
    aa_metric_workspace_free(&ws);
    if (!rc && o->exact)
        rc = o->exact(o->exact_user, p, scene, err);
    aa_evaluation ev;
    if (!rc && !(rc = aa_evaluate(p, metric, &ev, err))) {
        *e2 = ev.e2;
        aa_evaluation_free(&ev);
        double sr = scene_ref > 0 ? scene_ref : *scene, er = e2_ref > 0 ? e2_ref : *e2;
        *objective = (1 - blend) * *scene / sr + blend * *e2 / er;
    }
    return rc;
}

int aa_optimize_scene(const aa_pattern *seed, const aa_metric_params *metric,
                      const aa_scene_objective *o, const aa_scene_optimize_params *params,
                      aa_scene_progress_fn progress, void *user, aa_pattern *best,
                      aa_scene_optimize_result *result, aa_error *err)
{
    memset(best, 0, sizeof *best);
    memset(result, 0, sizeof *result);
    if (!(params->blend >= 0 && params->blend <= 1))
        return aa_error_set(err, AA_EINVAL, "blend", "must be in [0, 1]");
    if (params->local.grid_bits != 0)
        return aa_error_set(err, AA_EINVAL, "grid", "not supported with a scene objective");
    const aa_clock *clock = &params->local.clock;
    double start = aa_clock_seconds(clock), last = start;
    aa_scene_optimize_params pp = *params;
    opt_state cur, trial, top;
    memset(&trial, 0, sizeof trial);
    memset(&top, 0, sizeof top);
    int rc = opt_state_init(&cur, seed, err);
    if (rc)
        return rc;
    if ((rc = opt_state_init(&trial, seed, err)) || (rc = opt_state_init(&top, seed, err))) {
        opt_state_free(&cur);
        opt_state_free(&trial);
        return rc;
    }
    scene_run r = {.metric = metric, .o = o, .params = &pp};
    r.total = aa_pattern_total_kernel_samples(&cur.work);
    if ((rc = run_init(&r, &cur, err)))
        goto done;
    /* References from the seed where the caller left them open. */
    double s0, e0, f0;
    if ((rc = aa_scene_objective_blend(seed, metric, o, pp.blend, pp.scene_ref, pp.e2_ref, &f0, &s0,
                                       &e0, err)))
        goto done;
    pp.scene_ref = pp.scene_ref > 0 ? pp.scene_ref : s0;
    {
        aa_metric_workspace ws;
        aa_metric_workspace_init(&ws);
        rc = aa_scene_objective_eval(o, seed, &ws, &r.fold_ref, NULL, NULL, NULL, err);
        aa_metric_workspace_free(&ws);
        if (rc)
            goto done;
    }
    pp.e2_ref = pp.e2_ref > 0 ? pp.e2_ref : e0;
    scene_eval ce, te, be;
    if ((rc = run_eval(&r, &cur, true, &ce, err)))
        goto done;
    be = ce;
    result->initial_objective = ce.f_true;
    result->initial_scene = ce.scene;
    result->initial_e2 = ce.e2;
    long it = 0, mark_it = 0;
    double mark_f = be.f_true, step = 0.01;
    const aa_optimize_params *lp = &pp.local;
    while (!rc) {
        if (lp->max_iterations > 0 && it >= lp->max_iterations)
            break;
        if (lp->max_seconds > 0 && aa_clock_seconds(clock) - start >= lp->max_seconds)
            break;
        if (it - mark_it >= lp->stall_iterations || step < 1e-12)
            break;
        if ((rc = report(progress, user, clock, start, &last, it, &be, &top, false)))
            break;
        it++;
        take_step(&r, &trial, &cur, step);
        if ((rc = run_eval(&r, &trial, false, &te, err)))
            break;
        if (!(te.f_smooth < ce.f_smooth)) {
            step *= 0.5;
            continue;
        }
        step = fmin(step * 1.2, 0.25);
        copy_vars(&cur, &trial);
        if ((rc = run_eval(&r, &cur, true, &ce, err)))
            break;
        if (ce.f_true < be.f_true) {
            aa_pattern probe;
            aa_error perr = {0};
            /* Only valid patterns (no two samples of a kernel at one position) become best. */
            if (!opt_state_to_pattern(&cur, &probe, &perr)) {
                aa_pattern_free(&probe);
                copy_vars(&top, &cur);
                be = ce;
            }
        }
        if (be.f_true < mark_f * (1 - lp->rel_tolerance)) {
            mark_f = be.f_true;
            mark_it = it;
        }
    }
    int rep = report(progress, user, clock, start, &last, it, &be, &top, true);
    if (!rc)
        rc = rep;
    int brc = opt_state_to_pattern(&top, best, err);
    if (brc && (!rc || rc == AA_ECANCELED))
        rc = brc;
    result->objective = be.f_true;
    result->scene = be.scene;
    result->e2 = be.e2;
    result->scene_ref = pp.scene_ref;
    result->e2_ref = pp.e2_ref;
    result->iterations = it;
    result->evaluations = r.evaluations;
    result->seconds = aa_clock_seconds(clock) - start;
done:
    run_free(&r);
    opt_state_free(&cur);
    opt_state_free(&trial);
    opt_state_free(&top);
    return rc;
}
