#include "optimizer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "optimizer_run.h"
#include "optimizer_state.h"

void aa_optimize_params_default(aa_optimize_params *p)
{
    p->mode = AA_OPTIMIZE_BOTH;
    p->method = AA_METHOD_LAINE_AILA;
    p->threshold = 0.99;
    p->step = 1e-4;
    p->active_ratio = 100;
    p->max_iterations = 20000;
    p->max_seconds = 10;
    p->stall_iterations = 500;
    p->rel_tolerance = 1e-6;
    p->kink_width = AA_SMOOTH_KINK_WIDTH;
    p->grid_bits = 0;
    p->d3d12_range = false;
    p->clock = (aa_clock){NULL, NULL};
}

void aa_optimize_result_chain(aa_optimize_result *first, const aa_optimize_result *then)
{
    aa_optimize_result both = *then;
    both.initial_e2 = first->initial_e2;
    both.iterations += first->iterations;
    both.evaluations += first->evaluations;
    both.seconds += first->seconds;
    *first = both;
}

/* The L&A sec. 5 direction: sum over kernels and angles of W grad E1, terms with
 * W E1 >= t E2 scaled by c1/c0, mapped back to the free variables (mirror signs, shared
 * samples summed). value: W E1 of st's terms. */
static int descent_direction(opt_run *r, opt_state *st, const double *value, double e2,
                             double threshold)
{
    const aa_optimize_params *p = r->params;
    memset(r->dir_x, 0, st->point_count * sizeof *r->dir_x);
    memset(r->dir_y, 0, st->point_count * sizeof *r->dir_y);
    memset(r->dir_w, 0, st->weight_count * sizeof *r->dir_w);
    const opt_gradient_target to = {r->dir_x, r->dir_y, r->dir_w, 0, 0, NULL, NULL};
    for (size_t k = 0; k < st->work.kernel_count; k++) {
        if (opt_poll_cancel(r))
            return AA_ECANCELED;
        for (size_t a = 0; a < r->angle_count; a++) {
            double v = value[k * r->angle_count + a];
            if (v <= 0 || r->weight[a] <= 0)
                continue;
            double c = v >= threshold * e2 ? p->active_ratio : 1.0;
            int rc = opt_run_add_term_gradient(r, st, k, a, c * r->weight[a], &to);
            if (rc)
                return rc;
        }
    }
    return AA_OK;
}

static int validate(const aa_pattern *seed, const aa_metric_params *metric,
                    const aa_optimize_params *p, aa_error *err)
{
    if (!seed || !seed->kernels || seed->kernel_count == 0)
        return aa_error_set(err, AA_EINVAL, "pattern", "a seed pattern is required");
    if (!metric || !metric->filter || !metric->acuity)
        return aa_error_set(err, AA_EINVAL, "metric", "filter and acuity are required");
    if (p->mode != AA_OPTIMIZE_WEIGHTS && p->mode != AA_OPTIMIZE_POSITIONS &&
        p->mode != AA_OPTIMIZE_BOTH)
        return aa_error_set(err, AA_EINVAL, "mode", "mode must be weights, positions or both");
    if (p->method != AA_METHOD_LAINE_AILA && p->method != AA_METHOD_MINIMAX &&
        p->method != AA_METHOD_SMOOTH)
        return aa_error_set(err, AA_EINVAL, "method",
                            "method must be laine-aila, minimax or smooth");
    if (!(p->threshold > 0 && p->threshold <= 1))
        return aa_error_set(err, AA_EINVAL, "threshold", "t must be in (0, 1]");
    if (!(p->step > 0 && p->step < 1))
        return aa_error_set(err, AA_EINVAL, "step", "c0 must be in (0, 1)");
    if (!(p->active_ratio >= 1 && p->active_ratio <= 1e6))
        return aa_error_set(err, AA_EINVAL, "active_ratio", "c1/c0 must be in [1, 1e6]");
    if (p->max_iterations < 1)
        return aa_error_set(err, AA_EINVAL, "max_iterations", "must be at least 1");
    if (!isfinite(p->max_seconds))
        return aa_error_set(err, AA_EINVAL, "max_seconds", "must be finite");
    if (p->stall_iterations < 1)
        return aa_error_set(err, AA_EINVAL, "stall_iterations", "must be at least 1");
    if (!(p->rel_tolerance >= 0 && p->rel_tolerance < 1))
        return aa_error_set(err, AA_EINVAL, "rel_tolerance", "must be in [0, 1)");
    if (!(p->kink_width >= 0 && p->kink_width <= 2))
        return aa_error_set(err, AA_EINVAL, "kink_width", "must be in [0, 2] pixels");
    if (p->grid_bits < 0 || p->grid_bits > 12)
        return aa_error_set(err, AA_EINVAL, "grid.bits", "must be 0..12");
    return AA_OK;
}

/* Snaps the free points to the 1/2^bits grid, as offsets from their pixel's centre
 * (interior points stay strictly inside, D3D12's [-8, 7]/16 range optionally). A point that
 * would land on another is left where it is. */
static void snap_to_grid(opt_state *st, int bits, bool d3d12)
{
    double q = ldexp(1.0, bits);
    bool mirrored = st->work.form == AA_FORM_MIRRORED;
    for (size_t m = 0; m < st->point_count; m++) {
        opt_point *p = &st->points[m];
        opt_point s = *p;
        for (int axis = 0; axis < 2; axis++) {
            double v = axis ? p->y : p->x, lo = axis ? p->lo_y : p->lo_x,
                   hi = axis ? p->hi_y : p->hi_x;
            if (lo == hi)
                continue; /* on an edge or corner in this axis: already exact */
            double centre = mirrored ? 0.0 : floor(lo) + 0.5;
            double o = round((v - centre) * q) / q;
            double lim = 0.5 - 1.0 / q;
            o = fmin(fmax(o, -lim), lim);
            if (d3d12)
                o = fmin(fmax(o, -8.0 / 16.0), 7.0 / 16.0);
            if (axis)
                s.y = centre + o;
            else
                s.x = centre + o;
        }
        bool clash = false;
        for (size_t j = 0; j < st->point_count && !clash; j++)
            clash = j != m && fabs(st->points[j].x - s.x) < 1e-12 &&
                    fabs(st->points[j].y - s.y) < 1e-12;
        if (!clash)
            *p = s;
    }
    opt_state_apply(st);
}

#define NONMONO 10

/* Laine & Aila's step rule with the safeguards of the header comment. */
int opt_descend_laine_aila(opt_loop *L)
{
    const aa_optimize_params *params = L->run.params;
    opt_run *r = &L->run;
    double step = params->step;
    int band = 0, fails = 0, hpos = 0;
    double history[NONMONO];
    for (int h = 0; h < NONMONO; h++)
        history[h] = L->e2;
    double accepted_step = step;
    int rc = descent_direction(r, &L->cur, r->cur_value, L->e2, params->threshold);
    while (!rc && !(rc = opt_loop_tick(L))) {
        L->it++;
        opt_run_take_step(r, &L->trial, &L->cur, step);
        double te2;
        if ((rc = opt_run_eval_e2(r, &L->trial, &te2)))
            break;
        /* Nonmonotone acceptance (Grippo et al. 1986): compare against the largest of the last
         * NONMONO accepted values, so the iterate can cross the kinks of the max; the best
         * pattern is tracked separately, so the result and its trace are still monotone. */
        double ref = L->e2;
        for (int h = 0; h < NONMONO; h++)
            ref = fmax(ref, history[h]);
        if (te2 <= ref && te2 < L->e2 * (1 + 1e-2)) {
            /* Accepted: move, grow the step a little, new direction from here. */
            opt_loop_accept(L, te2);
            history[hpos++ % NONMONO] = L->e2;
            step *= 1.2;
            accepted_step = step;
            band = 0;
            fails = 0;
            if ((rc = descent_direction(r, &L->cur, r->cur_value, L->e2, params->threshold)))
                break;
        } else {
            /* E2 rose: cur is untouched; retry with half the step. At a kink of the max the
             * active terms' summed gradient may not descend for all of them: after 3 failed
             * halvings, widen the band of terms stepped with c1 (t -> 1 - 4^band (1 - t)) so
             * near-active terms steer too, and restart from the last good step size. */
            step *= 0.5;
            if (++fails >= 3 && band < 6) {
                band++;
                fails = 0;
                double t_eff = fmax(0.5, 1 - pow(4.0, band) * (1 - params->threshold));
                if ((rc = descent_direction(r, &L->cur, r->cur_value, L->e2, t_eff)))
                    break;
                step = accepted_step;
            }
        }
        if (opt_loop_stalled(L))
            break;
        if (step < 1e-14)
            break; /* no step along this direction lowers E2: a (nonsmooth) stationary point */
    }
    return rc == 1 ? AA_OK : rc;
}

int aa_optimize(const aa_pattern *seed, const aa_metric_params *metric,
                const aa_optimize_params *params, aa_optimize_progress_fn progress, void *user,
                aa_pattern *best, aa_optimize_result *result, aa_error *err)
{
    memset(best, 0, sizeof *best);
    aa_optimize_params defaults;
    if (!params) {
        aa_optimize_params_default(&defaults);
        params = &defaults;
    }
    if (result)
        memset(result, 0, sizeof *result);
    int rc = validate(seed, metric, params, err);
    if (rc)
        return rc;
    opt_loop L;
    memset(&L, 0, sizeof L);
    L.start = aa_clock_seconds(&params->clock);
    L.err = err;
    rc = opt_state_init(&L.cur, seed, err);
    if (rc)
        return rc;
    if ((rc = opt_state_init(&L.trial, seed, err))) {
        opt_state_free(&L.cur);
        return rc;
    }
    if ((rc = opt_state_init(&L.top, seed, err))) {
        opt_state_free(&L.cur);
        opt_state_free(&L.trial);
        return rc;
    }
    rc = opt_run_init(&L.run, &L.cur, metric, params, err);
    opt_state_apply(&L.cur);
    L.best_e2 = INFINITY; /* until the seed has been evaluated */
    bool cancelled = false;
    L.ps = (opt_progress_state){progress, user, L.start, L.start, 0, true, &params->clock};
    L.run.loop = &L;
    if (!rc)
        rc = opt_run_eval_e2(&L.run, &L.cur, &L.e2);
    double initial = L.e2;
    if (!rc) {
        L.best_e2 = L.mark_e2 = L.e2;
        memcpy(L.run.cur_value, L.run.value,
               L.run.angle_count * L.cur.work.kernel_count * sizeof *L.run.value);
        rc = params->method == AA_METHOD_MINIMAX  ? opt_descend_minimax(&L)
             : params->method == AA_METHOD_SMOOTH ? opt_descend_smooth(&L)
                                                  : opt_descend_laine_aila(&L);
    }
    if (rc == AA_ECANCELED) {
        /* The progress callback asked to stop in the middle of a step: top is intact. */
        rc = AA_OK;
        cancelled = true;
    }
    /* The last improvement may have been rate-limited away: report it, before snapping, so
     * the reported E2 is the pattern's (progress follows the continuous search). */
    if (!rc && progress && !cancelled) {
        L.ps.improved = true;
        opt_report(&L.ps, &L.top, L.best_e2, L.it, L.run.evaluations, 1.0, true);
    }
    if (!rc && params->grid_bits > 0) {
        double before = L.best_e2;
        snap_to_grid(&L.top, params->grid_bits, params->d3d12_range);
        if (result)
            result->e2_before_snap = before;
    }
    if (!rc)
        rc = opt_state_to_pattern(&L.top, best, err);
    aa_evaluation ev;
    memset(&ev, 0, sizeof ev);
    if (!rc)
        rc = aa_evaluate(best, metric, &ev, err);
    if (!rc && result) {
        result->initial_e2 = initial;
        result->e2 = ev.e2;
        if (params->grid_bits == 0)
            result->e2_before_snap = ev.e2;
        result->iterations = L.it;
        result->evaluations = L.run.evaluations;
        result->seconds = aa_clock_seconds(&params->clock) - L.start;
        result->argmax_kernel = ev.argmax_kernel;
        result->argmax_angle_deg = ev.argmax_angle_deg;
    }
    aa_evaluation_free(&ev);
    opt_run_free(&L.run);
    opt_state_free(&L.cur);
    opt_state_free(&L.trial);
    opt_state_free(&L.top);
    if (rc) {
        aa_pattern_free(best);
        return rc;
    }
    if (cancelled)
        return aa_error_set(err, AA_ECANCELED, "", "cancelled by the progress callback");
    return AA_OK;
}
