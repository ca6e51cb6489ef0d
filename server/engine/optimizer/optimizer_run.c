#define _POSIX_C_SOURCE 200809L /* clock_gettime(CLOCK_MONOTONIC) for the time budget */
#include "optimizer_run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void opt_run_free(opt_run *r)
{
    free(r->theta);
    free(r->dir_c);
    free(r->weight);
    free(r->value);
    free(r->smoothed);
    free(r->cur_value);
    free(r->gx);
    free(r->gy);
    free(r->gw);
    free(r->dir_x);
    free(r->dir_y);
    free(r->dir_w);
    aa_metric_workspace_free(&r->ws);
}

int opt_run_init(opt_run *r, const opt_state *st, const aa_metric_params *metric,
                 const aa_optimize_params *params, aa_error *err)
{
    memset(r, 0, sizeof *r);
    r->metric = metric;
    r->params = params;
    aa_metric_workspace_init(&r->ws);
    double defaults[AA_MAX_ANGLES];
    const double *deg = metric->angles_deg;
    size_t n = metric->angle_count;
    if (!deg) {
        n = aa_acuity_default_angles(metric->acuity, defaults, AA_MAX_ANGLES);
        deg = defaults;
    }
    if (n == 0 || n > AA_MAX_ANGLES)
        return aa_error_set(err, AA_EINVAL, "angles", "1..%d angles are needed", AA_MAX_ANGLES);
    size_t maxk = 1;
    for (size_t k = 0; k < st->work.kernel_count; k++)
        if (st->work.kernels[k].count > maxk)
            maxk = st->work.kernels[k].count;
    r->angle_count = n;
    r->theta = malloc(n * sizeof *r->theta);
    r->dir_c = malloc(2 * n * sizeof *r->dir_c);
    r->dir_s = r->dir_c ? r->dir_c + n : NULL;
    r->weight = malloc(n * sizeof *r->weight);
    r->value = malloc(n * st->work.kernel_count * sizeof *r->value);
    r->cur_value = malloc(n * st->work.kernel_count * sizeof *r->cur_value);
    r->smoothed = malloc(n * st->work.kernel_count * sizeof *r->smoothed);
    r->gx = malloc(maxk * sizeof *r->gx);
    r->gy = malloc(maxk * sizeof *r->gy);
    r->gw = malloc(maxk * sizeof *r->gw);
    r->dir_x = calloc(st->point_count + 1, sizeof *r->dir_x);
    r->dir_y = calloc(st->point_count + 1, sizeof *r->dir_y);
    r->dir_w = calloc(st->weight_count + 1, sizeof *r->dir_w);
    if (!r->theta || !r->dir_c || !r->weight || !r->value || !r->cur_value || !r->smoothed ||
        !r->gx || !r->gy || !r->gw || !r->dir_x || !r->dir_y || !r->dir_w)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t a = 0; a < n; a++) {
        char field[32];
        if (!isfinite(deg[a])) {
            snprintf(field, sizeof field, "angles[%zu]", a);
            return aa_error_set(err, AA_EINVAL, field, "angle must be finite");
        }
        r->theta[a] = deg[a] * (3.14159265358979323846 / 180.0);
        aa_metric_direction(r->theta[a], &r->dir_c[a], &r->dir_s[a]);
        r->weight[a] = aa_acuity_weight(metric->acuity, deg[a]);
    }
    return AA_OK;
}

int opt_run_eval_e2(opt_run *r, opt_state *st, double *e2)
{
    double best = 0;
    for (size_t k = 0; k < st->work.kernel_count; k++) {
        const aa_kernel *ker = &st->work.kernels[k];
        if (opt_poll_cancel(r))
            return AA_ECANCELED;
        for (size_t a = 0; a < r->angle_count; a++) {
            double e1, e1s; /* aa_e1_smoothed_at_direction: e1s = e1 at width 0 */
            int rc = aa_e1_smoothed_at_direction(r->metric->filter, ker->samples, ker->count,
                                                 r->dir_c[a], r->dir_s[a], r->kink_width, &r->ws,
                                                 &e1, &e1s);
            if (rc)
                return rc;
            double v = r->weight[a] * e1;
            r->value[k * r->angle_count + a] = v;
            r->smoothed[k * r->angle_count + a] = r->weight[a] * e1s;
            if (v > best)
                best = v;
        }
    }
    r->evaluations++;
    *e2 = best;
    return AA_OK;
}

int opt_run_add_term_gradient(opt_run *r, const opt_state *st, size_t k, size_t a, double factor,
                              const opt_gradient_target *to)
{
    const aa_kernel *ker = &st->work.kernels[k];
    bool want_pos = r->params->mode != AA_OPTIMIZE_WEIGHTS;
    bool want_w = r->params->mode != AA_OPTIMIZE_POSITIONS;
    double e1_exact, e1; /* e1: of the function whose gradient this is (E1 at width 0) */
    int rc = aa_e1_smoothed_gradient_at_direction(r->metric->filter, ker->samples, ker->count,
                                                  r->dir_c[a], r->dir_s[a], r->kink_width, &r->ws,
                                                  &e1_exact, &e1, want_pos ? r->gx : NULL,
                                                  want_pos ? r->gy : NULL, want_w ? r->gw : NULL);
    if (rc || !(e1 > 0))
        return rc; /* E1 = 0: a minimum of this term, its gradient is not defined */
    for (size_t i = 0; i < ker->count; i++) {
        const opt_ref *ref = &st->refs[k][i];
        const opt_point *pt = &st->points[ref->point];
        if (want_pos && isfinite(r->gx[i]) && isfinite(r->gy[i])) {
            size_t m = ref->point;
            if (pt->lo_x < pt->hi_x && !(to->frozen_x && to->frozen_x[m]))
                to->x[m - to->point_base] += factor * ref->sx * r->gx[i];
            if (pt->lo_y < pt->hi_y && !(to->frozen_y && to->frozen_y[m]))
                to->y[m - to->point_base] += factor * ref->sy * r->gy[i];
        }
        if (want_w && isfinite(r->gw[i]))
            to->w[ref->weight - to->weight_base] += factor * r->gw[i];
    }
    return AA_OK;
}

void opt_run_take_step(const opt_run *r, opt_state *trial, const opt_state *base, double step)
{
    for (size_t m = 0; m < base->point_count; m++) {
        opt_point *p = &trial->points[m];
        *p = base->points[m];
        p->x -= step * r->dir_x[m];
        p->y -= step * r->dir_y[m];
        opt_point_clamp(p);
    }
    for (size_t s = 0; s < base->weight_count; s++)
        trial->weights[s] = base->weights[s] - step * r->dir_w[s];
    opt_state_normalize_weights(trial);
    opt_state_apply(trial);
}

void opt_state_copy_vars(opt_state *dst, const opt_state *src)
{
    memcpy(dst->points, src->points, src->point_count * sizeof *src->points);
    memcpy(dst->weights, src->weights, src->weight_count * sizeof *src->weights);
    opt_state_apply(dst);
}

int opt_report(opt_progress_state *ps, const opt_state *best, double best_e2, long it, long evals,
               double fraction, bool force)
{
    if (!ps->fn)
        return 0;
    double t = aa_clock_seconds(ps->clock);
    if (!force && t - ps->last_call < 0.01)
        return 0;
    ps->last_call = t;
    if (fraction < 0)
        fraction = ps->last_fraction; /* a poll: the fraction must not step back */
    ps->last_fraction = fraction;
    aa_pattern snap;
    aa_error e;
    bool have = opt_state_to_pattern(best, &snap, &e) == AA_OK;
    aa_optimize_progress pr = {t - ps->start,      it, evals, best_e2, fraction, ps->improved,
                               have ? &snap : NULL};
    ps->improved = false;
    int stop = ps->fn(ps->user, &pr);
    if (have)
        aa_pattern_free(&snap);
    return stop;
}

int opt_poll_cancel(const opt_run *r)
{
    opt_loop *L = r->loop;
    if (!L || !L->ps.fn)
        return 0;
    return opt_report(&L->ps, &L->top, L->best_e2, L->it, r->evaluations, -1 /* no estimate */,
                      false);
}

int opt_loop_tick(opt_loop *L)
{
    const aa_optimize_params *p = L->run.params;
    if (L->it >= p->max_iterations)
        return 1;
    double t = aa_clock_seconds(&p->clock);
    if (p->max_seconds > 0 && t - L->start >= p->max_seconds)
        return 1;
    double fraction = (double)L->it / (double)p->max_iterations;
    if (p->max_seconds > 0)
        fraction = fmax(fraction, (t - L->start) / p->max_seconds);
    if (opt_report(&L->ps, &L->top, L->best_e2, L->it, L->run.evaluations, fmin(fraction, 1),
                   false))
        return AA_ECANCELED;
    return AA_OK;
}

bool opt_loop_stalled(opt_loop *L)
{
    const aa_optimize_params *p = L->run.params;
    if (L->best_e2 < L->mark_e2 * (1 - p->rel_tolerance)) {
        L->mark_e2 = L->best_e2;
        L->mark_it = L->it;
        return false;
    }
    return L->it - L->mark_it >= p->stall_iterations;
}

static bool samples_distinct(const opt_state *st)
{
    /* Twice the constructors' tolerance, so the pattern built from the state passes them. */
    const double tol = 2 * AA_POSITION_EPS;
    for (size_t k = 0; k < st->work.kernel_count; k++) {
        const aa_kernel *ker = &st->work.kernels[k];
        for (size_t i = 0; i < ker->count; i++)
            for (size_t j = 0; j < i; j++)
                if (fabs(ker->samples[i].x - ker->samples[j].x) <= tol &&
                    fabs(ker->samples[i].y - ker->samples[j].y) <= tol)
                    return false;
    }
    return true;
}

bool opt_loop_offer_best(opt_loop *L, const opt_state *st, double e2)
{
    if (!(e2 < L->best_e2) || !samples_distinct(st))
        return false;
    L->best_e2 = e2;
    opt_state_copy_vars(&L->top, st);
    L->ps.improved = true;
    return true;
}

void opt_loop_accept(opt_loop *L, double te2)
{
    opt_state_copy_vars(&L->cur, &L->trial);
    memcpy(L->run.cur_value, L->run.value,
           L->run.angle_count * L->cur.work.kernel_count * sizeof *L->run.value);
    L->e2 = te2;
    opt_loop_offer_best(L, &L->cur, L->e2);
}

int opt_chained_progress_forward(void *user, const aa_optimize_progress *p)
{
    opt_chained_progress *c = user;
    aa_optimize_progress q = *p;
    q.seconds += c->seconds;
    q.iterations += c->iterations;
    q.evaluations += c->evaluations;
    double f = c->fraction;
    if (c->budget_iterations > 0)
        f = fmax(f, (double)q.iterations / (double)c->budget_iterations);
    if (c->budget_seconds > 0)
        f = fmax(f, q.seconds / c->budget_seconds);
    c->fraction = q.fraction = fmin(f, 1);
    return c->fn(c->user, &q);
}
