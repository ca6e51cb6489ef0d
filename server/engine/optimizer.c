#define _POSIX_C_SOURCE 200809L /* clock_gettime(CLOCK_MONOTONIC) for the time budget */
#include "optimizer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "optimizer_state.h"

void aa_optimize_params_default(aa_optimize_params *p)
{
    p->mode = AA_OPTIMIZE_BOTH;
    p->threshold = 0.99;
    p->step = 1e-4;
    p->active_ratio = 100;
    p->max_iterations = 20000;
    p->max_seconds = 10;
    p->stall_iterations = 500;
    p->rel_tolerance = 1e-6;
    p->grid_bits = 0;
    p->d3d12_range = false;
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Everything one run needs besides the state: angles, acuity weights, gradient scratch. */
struct opt_progress_state;
struct opt_run;
static int poll_cancel(const struct opt_run *r);

typedef struct opt_run {
    const aa_metric_params *metric;
    const aa_optimize_params *params;
    size_t angle_count;
    double *theta;                 /* radians */
    double *weight;                /* W(theta) */
    double *value;                 /* W E1 per kernel x angle */
    double *gx, *gy, *gw;          /* per-kernel gradient scratch (max kernel size) */
    double *dir_x, *dir_y, *dir_w; /* descent direction on the free variables */
    aa_metric_workspace ws;
    long evaluations;
    /* Polled between kernels so a cancel is seen within a fraction of a step (a step of
     * P(16,16,4) can take 50+ ms on a loaded machine). */
    struct opt_progress_state *poll_ps;
    const struct opt_state *poll_top;
    const double *poll_best_e2;
    const long *poll_it;
} opt_run;

static void run_free(opt_run *r)
{
    free(r->theta);
    free(r->weight);
    free(r->value);
    free(r->gx);
    free(r->gy);
    free(r->gw);
    free(r->dir_x);
    free(r->dir_y);
    free(r->dir_w);
    aa_metric_workspace_free(&r->ws);
}

static int run_init(opt_run *r, const opt_state *st, const aa_metric_params *metric,
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
    r->weight = malloc(n * sizeof *r->weight);
    r->value = malloc(n * st->work.kernel_count * sizeof *r->value);
    r->gx = malloc(maxk * sizeof *r->gx);
    r->gy = malloc(maxk * sizeof *r->gy);
    r->gw = malloc(maxk * sizeof *r->gw);
    r->dir_x = calloc(st->point_count + 1, sizeof *r->dir_x);
    r->dir_y = calloc(st->point_count + 1, sizeof *r->dir_y);
    r->dir_w = calloc(st->weight_count + 1, sizeof *r->dir_w);
    if (!r->theta || !r->weight || !r->value || !r->gx || !r->gy || !r->gw || !r->dir_x ||
        !r->dir_y || !r->dir_w)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t a = 0; a < n; a++) {
        char field[32];
        if (!isfinite(deg[a])) {
            snprintf(field, sizeof field, "angles[%zu]", a);
            return aa_error_set(err, AA_EINVAL, field, "angle must be finite");
        }
        r->theta[a] = deg[a] * (3.14159265358979323846 / 180.0);
        r->weight[a] = aa_acuity_weight(metric->acuity, deg[a]);
    }
    return AA_OK;
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

/* E2 of the state's current kernels (opt_state_apply first). */
static int eval_e2(opt_run *r, opt_state *st, double *e2)
{
    double best = 0;
    for (size_t k = 0; k < st->work.kernel_count; k++) {
        const aa_kernel *ker = &st->work.kernels[k];
        if (poll_cancel(r))
            return AA_ECANCELED;
        for (size_t a = 0; a < r->angle_count; a++) {
            double e1;
            int rc = aa_e1_at_angle(r->metric->filter, ker->samples, ker->count, r->theta[a],
                                    &r->ws, &e1);
            if (rc)
                return rc;
            double v = r->weight[a] * e1;
            r->value[k * r->angle_count + a] = v;
            if (v > best)
                best = v;
        }
    }
    r->evaluations++;
    *e2 = best;
    return AA_OK;
}

/* The L&A sec. 5 direction: sum over kernels and angles of W grad E1, terms with
 * W E1 >= t E2 scaled by c1/c0, mapped back to the free variables (mirror signs, shared
 * samples summed). r->value must hold the values of the current state. */
static int descent_direction(opt_run *r, opt_state *st, double e2, double threshold)
{
    const aa_optimize_params *p = r->params;
    memset(r->dir_x, 0, st->point_count * sizeof *r->dir_x);
    memset(r->dir_y, 0, st->point_count * sizeof *r->dir_y);
    memset(r->dir_w, 0, st->weight_count * sizeof *r->dir_w);
    bool want_pos = p->mode != AA_OPTIMIZE_WEIGHTS, want_w = p->mode != AA_OPTIMIZE_POSITIONS;
    for (size_t k = 0; k < st->work.kernel_count; k++) {
        const aa_kernel *ker = &st->work.kernels[k];
        if (poll_cancel(r))
            return AA_ECANCELED;
        for (size_t a = 0; a < r->angle_count; a++) {
            double v = r->value[k * r->angle_count + a];
            if (v <= 0 || r->weight[a] <= 0)
                continue;
            double c = v >= threshold * e2 ? p->active_ratio : 1.0;
            double e1;
            int rc = aa_e1_gradient_at_angle(r->metric->filter, ker->samples, ker->count,
                                             r->theta[a], &r->ws, &e1, want_pos ? r->gx : NULL,
                                             want_pos ? r->gy : NULL, want_w ? r->gw : NULL);
            if (rc)
                return rc;
            if (!(e1 > 0))
                continue;
            double f = c * r->weight[a];
            for (size_t i = 0; i < ker->count; i++) {
                const opt_ref *ref = &st->refs[k][i];
                if (want_pos && isfinite(r->gx[i]) && isfinite(r->gy[i])) {
                    r->dir_x[ref->point] += f * ref->sx * r->gx[i];
                    r->dir_y[ref->point] += f * ref->sy * r->gy[i];
                }
                if (want_w && isfinite(r->gw[i]))
                    r->dir_w[ref->weight] += f * r->gw[i];
            }
        }
    }
    return AA_OK;
}

/* trial = base - step * direction, projected onto the sites and renormalised. */
static void take_step(opt_state *trial, const opt_state *base, const opt_run *r, double step)
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

static void copy_vars(opt_state *dst, const opt_state *src)
{
    memcpy(dst->points, src->points, src->point_count * sizeof *src->points);
    memcpy(dst->weights, src->weights, src->weight_count * sizeof *src->weights);
    opt_state_apply(dst);
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

typedef struct opt_progress_state {
    aa_optimize_progress_fn fn;
    void *user;
    double start, last_call;
    bool improved;
    double last_fraction;
} opt_progress_state;

static int report(opt_progress_state *ps, const opt_state *best, double best_e2, long it,
                  long evals, double fraction, bool force)
{
    if (!ps->fn)
        return 0;
    double t = now_seconds();
    if (!force && t - ps->last_call < 0.01)
        return 0;
    ps->last_call = t;
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

static int poll_cancel(const opt_run *r)
{
    if (!r->poll_ps || !r->poll_ps->fn)
        return 0;
    return report(r->poll_ps, r->poll_top, *r->poll_best_e2, *r->poll_it, r->evaluations, -1,
                  false);
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
    double start = now_seconds();
    opt_state cur, trial, top;
    opt_run run;
    memset(&run, 0, sizeof run);
    rc = opt_state_init(&cur, seed, err);
    if (rc)
        return rc;
    if ((rc = opt_state_init(&trial, seed, err))) {
        opt_state_free(&cur);
        return rc;
    }
    if ((rc = opt_state_init(&top, seed, err))) {
        opt_state_free(&cur);
        opt_state_free(&trial);
        return rc;
    }
    rc = run_init(&run, &cur, metric, params, err);
    opt_state_apply(&cur);
    double e2 = 0, best_e2 = INFINITY; /* INFINITY until the seed has been evaluated */
    long it = 0, mark_it = 0;
    bool cancelled = false;
    opt_progress_state ps = {progress, user, start, start, true, 0};
    run.poll_ps = &ps;
    run.poll_top = &top;
    run.poll_best_e2 = &best_e2;
    run.poll_it = &it;
    if (!rc)
        rc = eval_e2(&run, &cur, &e2);
    double initial = e2, mark_e2 = e2;
    if (!rc)
        best_e2 = e2;
    double step = params->step;
    /* cur_value: W E1 of cur, kept so the direction can be recomputed after rejected steps. */
    size_t nvalues = run.angle_count * cur.work.kernel_count;
    double *cur_value = rc ? NULL : malloc(nvalues * sizeof *cur_value);
    if (!rc && !cur_value)
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    if (!rc)
        memcpy(cur_value, run.value, nvalues * sizeof *cur_value);
    int band = 0, fails = 0, hpos = 0;
    double history[NONMONO];
    for (int h = 0; h < NONMONO; h++)
        history[h] = e2;
    double accepted_step = step;
    if (!rc)
        rc = descent_direction(&run, &cur, e2, params->threshold);
    while (!rc && it < params->max_iterations) {
        double t = now_seconds();
        if (params->max_seconds > 0 && t - start >= params->max_seconds)
            break;
        double fraction = (double)it / (double)params->max_iterations;
        if (params->max_seconds > 0)
            fraction = fmax(fraction, (t - start) / params->max_seconds);
        if (report(&ps, &top, best_e2, it, run.evaluations, fmin(fraction, 1), false)) {
            cancelled = true;
            break;
        }
        it++;
        take_step(&trial, &cur, &run, step);
        double te2;
        if ((rc = eval_e2(&run, &trial, &te2)))
            break;
        /* Nonmonotone acceptance (Grippo et al. 1986): compare against the largest of the last
         * NONMONO accepted values, so the iterate can cross the kinks of the max; the best
         * pattern is tracked separately, so the result and its trace are still monotone. */
        double ref = e2;
        for (int h = 0; h < NONMONO; h++)
            ref = fmax(ref, history[h]);
        if (te2 <= ref && te2 < e2 * (1 + 1e-2)) {
            /* Accepted: move, grow the step a little, new direction from here. */
            copy_vars(&cur, &trial);
            memcpy(cur_value, run.value, nvalues * sizeof *cur_value);
            e2 = te2;
            history[hpos++ % NONMONO] = e2;
            step *= 1.2;
            accepted_step = step;
            band = 0;
            fails = 0;
            if (e2 < best_e2) {
                best_e2 = e2;
                copy_vars(&top, &cur);
                ps.improved = true;
            }
            if ((rc = descent_direction(&run, &cur, e2, params->threshold)))
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
                memcpy(run.value, cur_value, nvalues * sizeof *cur_value);
                if ((rc = descent_direction(&run, &cur, e2, t_eff)))
                    break;
                step = accepted_step;
            }
        }
        if (best_e2 < mark_e2 * (1 - params->rel_tolerance)) {
            mark_e2 = best_e2;
            mark_it = it;
        } else if (it - mark_it >= params->stall_iterations) {
            break;
        }
        if (step < 1e-14)
            break; /* no step along this direction lowers E2: a (nonsmooth) stationary point */
    }
    if (rc == AA_ECANCELED) {
        /* The progress callback asked to stop in the middle of a step: cur is intact. */
        rc = AA_OK;
        cancelled = true;
    }
    if (!rc && params->grid_bits > 0) {
        double before = best_e2;
        snap_to_grid(&top, params->grid_bits, params->d3d12_range);
        if (result)
            result->e2_before_snap = before;
    }
    if (!rc)
        rc = opt_state_to_pattern(&top, best, err);
    aa_evaluation ev;
    memset(&ev, 0, sizeof ev);
    if (!rc)
        rc = aa_evaluate(best, metric, &ev, err);
    if (!rc && result) {
        result->initial_e2 = initial;
        result->e2 = ev.e2;
        if (params->grid_bits == 0)
            result->e2_before_snap = ev.e2;
        result->iterations = it;
        result->evaluations = run.evaluations;
        result->seconds = now_seconds() - start;
        result->argmax_kernel = ev.argmax_kernel;
        result->argmax_angle_deg = ev.argmax_angle_deg;
    }
    if (!rc && progress && !cancelled) {
        ps.improved = true;
        report(&ps, &top, best_e2, it, run.evaluations, 1.0, true);
    }
    aa_evaluation_free(&ev);
    free(cur_value);
    run_free(&run);
    opt_state_free(&cur);
    opt_state_free(&trial);
    opt_state_free(&top);
    if (rc) {
        aa_pattern_free(best);
        return rc;
    }
    if (cancelled)
        return aa_error_set(err, AA_ECANCELED, "", "cancelled by the progress callback");
    return AA_OK;
}
