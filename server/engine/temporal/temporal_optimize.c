/* A first optimizer of temporal jitter sequences (temporal_optimize.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "temporal_flicker.h"
#include "temporal_optimize.h"

#define DEG2RAD (3.14159265358979323846 / 180.0)

typedef struct opt_ctx {
    aa_temporal t;
    aa_point **rel; /* [group][sample]: the sample's position minus its frame's offset */
    const aa_metric_params *mp;
    size_t na;
    double *angles, *weight, *dc, *ds;
    aa_metric_workspace ws;
    aa_sample *kernel;
    double *gx, *gy, *e1, *factor;
    double flicker_weight;              /* lambda */
    double flicker_cap;                 /* > 0: penalise F2 above it only */
    const aa_temporal_resolve *resolve; /* NULL: frame weights fixed */
    double **ux, **uy;   /* [group][sample]: d(h(dx) h(dy))/d(offset x, y) (resolve) */
    double **norm;       /* [group][frame]: sum of h(dx) h(dy) (resolve) */
    double **sux, **suy; /* [group][frame]: sums of ux, uy (resolve) */
    double *gw;
    aa_flicker_scratch fs;
    double *f1, *dp; /* [group][angle], [sample] */
    long evaluations;
    /* The run's progress (aa_temporal_optimize only; params NULL elsewhere). */
    const aa_temporal_opt_params *params;
    double t0;
    long starts;
    const aa_point *best; /* NULL until a start ended */
    double best_score, best_e2;
} opt_ctx;

static double run_seconds(const opt_ctx *c)
{
    return aa_clock_seconds(&c->params->clock) - c->t0;
}

static double run_fraction(const opt_ctx *c, double seconds)
{
    const aa_temporal_opt_params *p = c->params;
    double f = 0;
    if (p->max_starts > 0)
        f = (double)c->starts / (double)p->max_starts;
    if (p->max_seconds > 0)
        f = fmax(f, seconds / p->max_seconds);
    return fmin(f, 1);
}

/* Progress within a start (start -1): AA_ECANCELED when the callback asks to stop. */
static int tick(opt_ctx *c)
{
    if (!c->params || !c->params->progress)
        return AA_OK;
    double t = run_seconds(c);
    aa_temporal_opt_progress pr = {.fraction = run_fraction(c, t),
                                   .start = -1,
                                   .best_score = c->best_score,
                                   .best_e2 = c->best_e2,
                                   .best = c->best,
                                   .starts = c->starts,
                                   .evaluations = c->evaluations,
                                   .seconds = t};
    return c->params->progress(c->params->progress_user, &pr) ? AA_ECANCELED : AA_OK;
}

static void ctx_free(opt_ctx *c)
{
    for (size_t g = 0; g < c->t.group_count; g++) {
        if (c->rel)
            free(c->rel[g]);
        if (c->ux) {
            free(c->ux[g]);
            free(c->norm[g]);
        }
    }
    free(c->rel);
    free(c->ux);
    free(c->uy);
    free(c->norm);
    free(c->sux);
    free(c->suy);
    free(c->gw);
    aa_temporal_free(&c->t);
    free(c->angles);
    free(c->weight);
    free(c->dc);
    free(c->kernel);
    free(c->gx);
    free(c->e1);
    free(c->factor);
    free(c->f1);
    free(c->dp);
    aa_flicker_scratch_free(&c->fs);
    aa_metric_workspace_free(&c->ws);
}

static int ctx_init(opt_ctx *c, const aa_point *jitter, size_t n, aa_blend blend,
                    const aa_pattern *frame, const aa_temporal_resolve *resolve,
                    const aa_metric_params *mp, aa_error *err)
{
    memset(c, 0, sizeof *c);
    aa_metric_workspace_init(&c->ws);
    c->mp = mp;
    c->resolve = resolve;
    aa_temporal_spec spec = {
        .count = n, .jitter = jitter, .frame = frame, .resolve = resolve, .blend = blend};
    int rc = aa_temporal_build(&c->t, &spec, err);
    if (rc)
        return rc;
    if (!mp || !mp->filter || !mp->acuity)
        return aa_error_set(err, AA_EINVAL, "", "metric parameters need a filter and an acuity");
    c->angles = malloc(AA_MAX_ANGLES * sizeof *c->angles);
    if (!c->angles)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    if (mp->angles_deg) {
        if (mp->angle_count == 0 || mp->angle_count > AA_MAX_ANGLES)
            return aa_error_set(err, AA_ERANGE, "angles", "1 to %d angles", AA_MAX_ANGLES);
        memcpy(c->angles, mp->angles_deg, mp->angle_count * sizeof *c->angles);
        c->na = mp->angle_count;
    } else {
        c->na = aa_acuity_default_angles(mp->acuity, c->angles, AA_MAX_ANGLES);
    }
    size_t m = 0, G = c->t.group_count;
    for (size_t g = 0; g < G; g++)
        m = c->t.groups[g].count > m ? c->t.groups[g].count : m;
    c->weight = malloc(c->na * sizeof *c->weight);
    c->dc = malloc(2 * c->na * sizeof *c->dc);
    c->kernel = malloc(m * sizeof *c->kernel);
    c->gx = malloc(2 * m * sizeof *c->gx);
    c->e1 = malloc((n * G + 1) * c->na * sizeof *c->e1); /* + a scratch row */
    c->factor = malloc(c->na * sizeof *c->factor);
    c->rel = calloc(G, sizeof *c->rel);
    c->f1 = malloc(G * c->na * sizeof *c->f1);
    c->dp = malloc(m * sizeof *c->dp);
    c->gw = malloc(m * sizeof *c->gw);
    if (resolve) {
        c->ux = calloc(G, sizeof *c->ux);
        c->uy = calloc(G, sizeof *c->uy);
        c->norm = calloc(G, sizeof *c->norm);
        c->sux = calloc(G, sizeof *c->sux);
        c->suy = calloc(G, sizeof *c->suy);
        if (!c->ux || !c->uy || !c->norm || !c->sux || !c->suy)
            return aa_error_set(err, AA_ENOMEM, "", "out of memory");
        for (size_t g = 0; g < G; g++) {
            /* One block per group: ux, uy [count] each; norm, sux, suy [n] each. */
            c->ux[g] = malloc(2 * c->t.groups[g].count * sizeof **c->ux);
            c->norm[g] = malloc(3 * n * sizeof **c->norm);
            if (!c->ux[g] || !c->norm[g])
                return aa_error_set(err, AA_ENOMEM, "", "out of memory");
            c->uy[g] = c->ux[g] + c->t.groups[g].count;
            c->sux[g] = c->norm[g] + n;
            c->suy[g] = c->norm[g] + 2 * n;
        }
    }
    if (!c->weight || !c->dc || !c->kernel || !c->gx || !c->e1 || !c->factor || !c->rel || !c->f1 ||
        !c->dp || aa_flicker_scratch_init(&c->fs, &c->t, m))
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    c->ds = c->dc + c->na;
    c->gy = c->gx + m;
    for (size_t a = 0; a < c->na; a++) {
        c->weight[a] = aa_acuity_weight(mp->acuity, c->angles[a]);
        aa_metric_direction(c->angles[a] * DEG2RAD, &c->dc[a], &c->ds[a]);
    }
    for (size_t g = 0; g < G; g++) {
        const aa_temporal_group *grp = &c->t.groups[g];
        c->rel[g] = malloc(grp->count * sizeof **c->rel);
        if (!c->rel[g])
            return aa_error_set(err, AA_ENOMEM, "", "out of memory");
        for (size_t s = 0; s < grp->count; s++)
            c->rel[g][s] = (aa_point){grp->pos[s].x - jitter[grp->frame[s]].x,
                                      grp->pos[s].y - jitter[grp->frame[s]].y};
    }
    return AA_OK;
}

/* h'(x) by central differences (the resolve filters are smooth inside their support). */
static double filter_slope(const aa_filter *f, double x)
{
    const double e = 1e-6;
    return (aa_filter_eval(f, x + e) - aa_filter_eval(f, x - e)) / (2 * e);
}

static void set_offsets(opt_ctx *c, const aa_point *o)
{
    size_t N = c->t.phase_count;
    for (size_t g = 0; g < c->t.group_count; g++) {
        aa_temporal_group *grp = &c->t.groups[g];
        for (size_t s = 0; s < grp->count; s++)
            grp->pos[s] = (aa_point){c->rel[g][s].x + o[grp->frame[s]].x,
                                     c->rel[g][s].y + o[grp->frame[s]].y};
        if (!c->resolve)
            continue;
        /* The frame weights h(dx) h(dy) / sum about the output pixel's centre (the group's
         * positions are relative to it), and their derivatives in the frame's offset. */
        const aa_filter *h = &c->resolve->filter;
        for (size_t f = 0; f < N; f++)
            c->norm[g][f] = c->sux[g][f] = c->suy[g][f] = 0;
        for (size_t s = 0; s < grp->count; s++) {
            double hx = aa_filter_eval(h, grp->pos[s].x), hy = aa_filter_eval(h, grp->pos[s].y);
            size_t f = grp->frame[s];
            grp->in_frame[s] = hx * hy;
            c->ux[g][s] = filter_slope(h, grp->pos[s].x) * hy;
            c->uy[g][s] = hx * filter_slope(h, grp->pos[s].y);
            c->norm[g][f] += hx * hy;
            c->sux[g][f] += c->ux[g][s];
            c->suy[g][f] += c->uy[g][s];
        }
        for (size_t s = 0; s < grp->count; s++)
            grp->in_frame[s] /= c->norm[g][grp->frame[s]];
    }
}

/* Phase p's kernel with every sample (zero weights too: the gradient maps sample s to its
 * frame by index). */
static size_t full_kernel(const opt_ctx *c, size_t g, size_t p)
{
    const aa_temporal_group *grp = &c->t.groups[g];
    size_t N = c->t.phase_count;
    for (size_t s = 0; s < grp->count; s++)
        c->kernel[s] = (aa_sample){grp->pos[s].x, grp->pos[s].y,
                                   c->t.age_weight[(p + N - grp->frame[s]) % N] * grp->in_frame[s]};
    return grp->count;
}

/* lambda times the power mean of W F1 over groups and angles (its maximum, F2, when q = 0),
 * added to *value, and its gradient added to grad (when not NULL); *f2 the true F2. */
static void flicker_term(opt_ctx *c, double q, double *value, double *f2, aa_point *grad)
{
    size_t G = c->t.group_count, na = c->na;
    double mx = 0;
    for (size_t g = 0; g < G; g++) {
        aa_flicker_scratch_reset(&c->fs, c->t.groups[g].count);
        for (size_t a = 0; a < na; a++) {
            c->f1[g * na + a] = aa_flicker_sorted(&c->t, g, c->dc[a], c->ds[a], &c->fs, NULL);
            mx = fmax(mx, c->weight[a] * c->f1[g * na + a]);
        }
    }
    *f2 = mx;
    double cap = c->flicker_cap;
    if (q == 0 || !(mx > 0)) {
        *value += c->flicker_weight * (cap > 0 ? fmax(0, mx - cap) : mx);
        return;
    }
    double K = (double)(G * na), sum = 0;
    for (size_t i = 0; i < G * na; i++)
        sum += pow(c->weight[i % na] * c->f1[i] / mx, q);
    double M = mx * pow(sum / K, 1 / q);
    *value += c->flicker_weight * (cap > 0 ? fmax(0, M - cap) : M);
    if (!grad || (cap > 0 && M <= cap))
        return;
    for (size_t g = 0; g < G; g++) {
        const aa_temporal_group *grp = &c->t.groups[g];
        aa_flicker_scratch_reset(&c->fs, grp->count);
        for (size_t a = 0; a < na; a++) {
            double v = c->weight[a] * c->f1[g * na + a];
            if (!(v > 0))
                continue;
            double factor = c->flicker_weight * c->weight[a] * pow(v / M, q - 1) / K;
            aa_flicker_sorted(&c->t, g, c->dc[a], c->ds[a], &c->fs, c->dp);
            for (size_t s = 0; s < grp->count; s++) {
                grad[grp->frame[s]].x += factor * c->dp[s] * c->dc[a];
                grad[grp->frame[s]].y += factor * c->dp[s] * c->ds[a];
            }
        }
    }
}

/* M_q of the offsets o (plus lambda times the flicker's) and, when grad is not NULL, its
 * gradient per offset; *e2 the true maximum and, with lambda > 0, *score = E2 + lambda F2.
 * q = 0: the maxima only. */
static int objective_e2(opt_ctx *c, const aa_point *o, double q, double *value, double *e2,
                        aa_point *grad);

static int objective(opt_ctx *c, const aa_point *o, double q, double *value, double *score,
                     aa_point *grad)
{
    double e2 = 0;
    int rc = objective_e2(c, o, q, value, &e2, grad);
    *score = e2;
    if (!rc && c->flicker_weight > 0) {
        double f2;
        flicker_term(c, q, value, &f2, grad);
        *score = e2 + c->flicker_weight * (c->flicker_cap > 0 ? fmax(0, f2 - c->flicker_cap) : f2);
    }
    return rc;
}

static int objective_e2(opt_ctx *c, const aa_point *o, double q, double *value, double *e2,
                        aa_point *grad)
{
    set_offsets(c, o);
    size_t N = c->t.phase_count, G = c->t.group_count, na = c->na;
    double mx = 0;
    int rc = AA_OK;
    for (size_t p = 0; p < N && !rc; p++) {
        for (size_t g = 0; g < G && !rc; g++) {
            size_t n = full_kernel(c, g, p);
            double *row = c->e1 + (p * G + g) * na;
            rc = aa_e1_kernel_block(c->mp->filter, c->kernel, n, c->dc, c->ds, na, AA_E1_AUTO,
                                    &c->ws, row);
            for (size_t a = 0; a < na && !rc; a++)
                mx = fmax(mx, c->weight[a] * row[a]);
        }
    }
    c->evaluations++;
    if (rc)
        return rc;
    *e2 = mx;
    if (q == 0 || !(mx > 0)) {
        *value = mx;
        return AA_OK;
    }
    double K = (double)(N * G * na), sum = 0;
    for (size_t i = 0; i < N * G * na; i++)
        sum += pow(c->weight[i % na] * c->e1[i] / mx, q);
    double M = mx * pow(sum / K, 1 / q);
    *value = M;
    if (!grad)
        return AA_OK;
    for (size_t f = 0; f < N; f++)
        grad[f] = (aa_point){0, 0};
    for (size_t p = 0; p < N && !rc; p++) {
        for (size_t g = 0; g < G && !rc; g++) {
            const double *row = c->e1 + (p * G + g) * na;
            for (size_t a = 0; a < na; a++)
                c->factor[a] = c->weight[a] * pow(c->weight[a] * row[a] / M, q - 1) / K;
            size_t n = full_kernel(c, g, p);
            memset(c->gx, 0, n * sizeof *c->gx);
            memset(c->gy, 0, n * sizeof *c->gy);
            memset(c->gw, 0, n * sizeof *c->gw);
            rc = aa_e1_gradient_kernel_block(c->mp->filter, c->kernel, n, c->dc, c->ds, na,
                                             c->factor, AA_E1_AUTO, &c->ws, c->e1 + N * G * na,
                                             c->gx, c->gy, c->resolve ? c->gw : NULL);
            const aa_temporal_group *grp = &c->t.groups[g];
            for (size_t s = 0; s < n; s++) {
                size_t f = grp->frame[s];
                grad[f].x += c->gx[s];
                grad[f].y += c->gy[s];
                if (!c->resolve)
                    continue;
                /* Kernel weight a_f u_s / S_f: its derivative in the offset is
                 * a_f (u'_s - w_s S'_f) / S_f with w_s = u_s / S_f; these moves keep sum w = 1,
                 * along which the metric's projected weight gradient is exact. */
                double af = c->t.age_weight[(p + N - f) % N] / c->norm[g][f];
                grad[f].x += c->gw[s] * af * (c->ux[g][s] - grp->in_frame[s] * c->sux[g][f]);
                grad[f].y += c->gw[s] * af * (c->uy[g][s] - grp->in_frame[s] * c->suy[g][f]);
            }
        }
    }
    return rc;
}

static double clamp(double v, double h)
{
    return v < -h ? -h : v > h ? h : v;
}

/* Descent on M_q for q = 8 .. 2048 (the last levels sharpen the maximum: 15 s runs at N = 8
 * gave 0.2906 / 0.2900 / 0.2898 stopping at 128 / 512 / 2048); o is updated in place. */
static int descend(opt_ctx *c, aa_point *o, double half, int steps, aa_point *trial, aa_point *grad)
{
    size_t N = c->t.phase_count;
    for (double q = 8; q <= 2048; q *= 2) {
        double F, e2;
        int rc = tick(c);
        if (!rc)
            rc = objective(c, o, q, &F, &e2, grad);
        double step = 0.05 * half * 2;
        for (int it = 0; it < steps && !rc && step > 1e-7; it++) {
            double gmax = 0;
            for (size_t f = 0; f < N; f++)
                gmax = fmax(gmax, fmax(fabs(grad[f].x), fabs(grad[f].y)));
            if (!(gmax > 0))
                break;
            for (size_t f = 0; f < N; f++)
                trial[f] = (aa_point){clamp(o[f].x - step * grad[f].x / gmax, half),
                                      clamp(o[f].y - step * grad[f].y / gmax, half)};
            double Ft, e2t;
            rc = objective(c, trial, q, &Ft, &e2t, NULL);
            if (!rc && Ft < F) {
                memcpy(o, trial, N * sizeof *o);
                rc = objective(c, o, q, &F, &e2, grad);
                step *= 1.5;
            } else {
                step *= 0.5;
            }
        }
        if (rc)
            return rc;
    }
    return AA_OK;
}

/* The grid multiple nearest v that lies in [-half, half]. */
static double snap(double v, double step, double half)
{
    double k = nearbyint(v / step);
    if (k * step > half)
        k = floor(half / step);
    if (k * step < -half)
        k = ceil(-half / step);
    return k * step;
}

/* Snaps o to the grid, then moves single coordinates by one grid step while the true objective
 * drops (at most 64 sweeps over the 2N coordinates). */
static int snap_and_polish(opt_ctx *c, aa_point *o, double half, double step, aa_point *trial)
{
    size_t N = c->t.phase_count;
    for (size_t f = 0; f < N; f++)
        o[f] = (aa_point){snap(o[f].x, step, half), snap(o[f].y, step, half)};
    double F, best;
    int rc = objective(c, o, 0, &F, &best, NULL);
    bool moved = true;
    for (int sweep = 0; sweep < 64 && moved && !rc; sweep++) {
        moved = false;
        rc = tick(c);
        for (size_t f = 0; f < N && !rc; f++) {
            for (int axis = 0; axis < 2 && !rc; axis++) {
                for (int dir = -1; dir <= 1 && !rc; dir += 2) {
                    memcpy(trial, o, N * sizeof *o);
                    double *v = axis ? &trial[f].y : &trial[f].x;
                    double nv = *v + dir * step;
                    if (fabs(nv) > half + 1e-12)
                        continue;
                    *v = nv;
                    double score;
                    rc = objective(c, trial, 0, &F, &score, NULL);
                    if (!rc && score < best) {
                        best = score;
                        memcpy(o, trial, N * sizeof *o);
                        moved = true;
                    }
                }
            }
        }
    }
    return rc;
}

/* Next permutation of a[0..n-1] in lexicographic order; false after the last. */
static bool next_permutation(size_t *a, size_t n)
{
    if (n < 2)
        return false;
    size_t i = n - 1;
    while (i > 0 && a[i - 1] >= a[i])
        i--;
    if (i == 0)
        return false;
    size_t j = n - 1;
    while (a[j] <= a[i - 1])
        j--;
    size_t t = a[i - 1];
    a[i - 1] = a[j];
    a[j] = t;
    for (size_t l = i, r = n - 1; l < r; l++, r--) {
        t = a[l];
        a[l] = a[r];
        a[r] = t;
    }
    return true;
}

/* The best cyclic order of o (offset 0 first), by true E2; o is reordered in place. */
static int best_order(opt_ctx *c, aa_point *o, aa_point *trial, double *best_e2)
{
    size_t N = c->t.phase_count;
    size_t perm[8], best[8];
    for (size_t i = 0; i < N; i++)
        perm[i] = best[i] = i;
    double F, e2;
    int rc = objective(c, o, 0, &F, best_e2, NULL);
    for (long k = 1; !rc && next_permutation(perm + 1, N - 1); k++) {
        if (k % 512 == 0 && (rc = tick(c)))
            break;
        for (size_t i = 0; i < N; i++)
            trial[i] = o[perm[i]];
        rc = objective(c, trial, 0, &F, &e2, NULL);
        if (!rc && e2 < *best_e2) {
            *best_e2 = e2;
            memcpy(best, perm, N * sizeof *best);
        }
    }
    for (size_t i = 0; i < N; i++)
        trial[i] = o[best[i]];
    memcpy(o, trial, N * sizeof *o);
    return rc;
}

/* The order of o by pairwise swaps (N > 8): sweeps over every pair, a swap kept when the true
 * objective drops, until a sweep keeps none or `sweeps` ran; o is reordered in place. */
static int swap_order(opt_ctx *c, aa_point *o, aa_point *trial, int sweeps)
{
    size_t N = c->t.phase_count;
    double F, best, score;
    int rc = objective(c, o, 0, &F, &best, NULL);
    bool kept = true;
    long k = 0;
    for (int sweep = 0; sweep < sweeps && kept && !rc; sweep++) {
        kept = false;
        for (size_t i = 0; i + 1 < N && !rc; i++) {
            for (size_t j = i + 1; j < N && !rc; j++) {
                if (++k % 64 == 0 && (rc = tick(c)))
                    break;
                memcpy(trial, o, N * sizeof *o);
                trial[i] = o[j];
                trial[j] = o[i];
                rc = objective(c, trial, 0, &F, &score, NULL);
                if (!rc && score < best) {
                    best = score;
                    memcpy(o, trial, N * sizeof *o);
                    kept = true;
                }
            }
        }
    }
    return rc;
}

int aa_temporal_e2(const aa_point *jitter, size_t n, aa_blend blend, const aa_pattern *frame,
                   const aa_temporal_resolve *resolve, const aa_metric_params *metric, double *e2,
                   aa_error *err)
{
    opt_ctx c;
    int rc = ctx_init(&c, jitter, n, blend, frame, resolve, metric, err);
    double F;
    if (!rc)
        rc = objective(&c, jitter, 0, &F, e2, NULL);
    ctx_free(&c);
    return rc;
}

int aa_temporal_power_mean(const aa_point *jitter, size_t n, aa_blend blend,
                           const aa_pattern *frame, const aa_temporal_resolve *resolve,
                           const aa_metric_params *metric, double q, double flicker_weight,
                           double *value, aa_point *grad, aa_error *err)
{
    opt_ctx c;
    int rc = ctx_init(&c, jitter, n, blend, frame, resolve, metric, err);
    c.flicker_weight = flicker_weight;
    double score;
    if (!rc && !(q >= 1 && q <= 1024))
        rc = aa_error_set(err, AA_EINVAL, "q", "q must be in [1, 1024]");
    if (!rc)
        rc = objective(&c, jitter, q, value, &score, grad);
    ctx_free(&c);
    return rc;
}

int aa_temporal_optimize(const aa_temporal_opt_params *p, aa_point *best,
                         aa_temporal_opt_result *result, aa_error *err)
{
    memset(result, 0, sizeof *result);
    if (!(isfinite(p->range) && p->range > 0 && p->range <= 16))
        return aa_error_set(err, AA_EINVAL, "jitter_range", "range must be in (0, 16]");
    if (p->max_starts <= 0 && !(p->max_seconds > 0))
        return aa_error_set(err, AA_EINVAL, "max_iterations", "give max_starts or max_seconds");
    size_t N = p->count;
    if (N == 0 || N > AA_TEMPORAL_MAX_PHASES)
        return aa_error_set(err, AA_ERANGE, "jitter", "1 to %d offsets", AA_TEMPORAL_MAX_PHASES);
    double half = p->range / 2;
    aa_point *o = malloc(3 * N * sizeof *o), *trial = o ? o + N : NULL,
             *grad = o ? o + 2 * N : NULL;
    if (!o)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    aa_rng rng;
    aa_rng_seed(&rng, p->seed, 30);
    for (size_t f = 0; f < N; f++)
        o[f] = p->start ? p->start[f]
                        : (aa_point){(aa_rng_uniform(&rng) - 0.5) * p->range,
                                     (aa_rng_uniform(&rng) - 0.5) * p->range};
    opt_ctx c;
    int rc = ctx_init(&c, o, N, p->blend, p->frame, p->resolve, p->metric, err);
    if (!rc && !(isfinite(p->flicker_weight) && p->flicker_weight >= 0 && p->flicker_weight <= 1e3))
        rc = aa_error_set(err, AA_EINVAL, "flicker_weight", "lambda must be in [0, 1000]");
    if (!rc && !(p->grid_step >= 0 && p->grid_step <= p->range / 2))
        rc = aa_error_set(err, AA_EINVAL, "grid", "the grid step must be in [0, range / 2]");
    if (!rc && p->resolve && p->flicker_weight > 0)
        rc = aa_error_set(err, AA_EINVAL, "flicker_weight",
                          "a flicker weight with a resolve is not supported yet");
    c.flicker_weight = rc ? 0 : p->flicker_weight;
    c.flicker_cap = isfinite(p->flicker_cap) && p->flicker_cap > 0 ? p->flicker_cap : 0;
    c.params = p;
    c.t0 = aa_clock_seconds(&p->clock);
    c.best_score = c.best_e2 = INFINITY;
    result->score = INFINITY;
    int steps = p->descent_steps > 0 ? p->descent_steps : 60;
    bool exponential = p->blend.kind == AA_BLEND_EXPONENTIAL && p->swap_sweeps >= 0;
    bool reorder = N <= 8 && N > 2 && exponential;
    int sweeps = N > 8 && exponential ? (p->swap_sweeps > 0 ? p->swap_sweeps : 4) : 0;
    for (long s = 0; !rc; s++) {
        if (p->max_starts > 0 && s >= p->max_starts)
            break;
        if (p->max_seconds > 0 && s > 0 && run_seconds(&c) >= p->max_seconds)
            break;
        /* Odd starts (with hop > 0) hop from the best so far: each offset moved by up to
         * hop * range; even starts are uniform. */
        bool hop = p->hop > 0 && s % 2 == 1 && isfinite(result->score);
        for (size_t f = 0; f < N && s > 0; f++)
            o[f] = hop ? (aa_point){best[f].x + (2 * aa_rng_uniform(&rng) - 1) * p->hop * p->range,
                                    best[f].y + (2 * aa_rng_uniform(&rng) - 1) * p->hop * p->range}
                       : (aa_point){(aa_rng_uniform(&rng) - 0.5) * p->range,
                                    (aa_rng_uniform(&rng) - 0.5) * p->range};
        for (size_t f = 0; f < N; f++)
            o[f] = (aa_point){clamp(o[f].x, half), clamp(o[f].y, half)};
        double e2, F, initial, f2 = 0;
        rc = objective(&c, o, 0, &F, &initial, NULL);
        if (!rc)
            rc = descend(&c, o, half, steps, trial, grad);
        if (!rc && (reorder || sweeps > 0)) {
            rc = reorder ? best_order(&c, o, trial, &e2) : swap_order(&c, o, trial, sweeps);
            if (!rc)
                rc = descend(&c, o, half, steps, trial, grad);
        }
        if (!rc && p->grid_step > 0)
            rc = snap_and_polish(&c, o, half, p->grid_step, trial);
        double score = 0;
        if (!rc)
            rc = objective(&c, o, 0, &F, &score, NULL);
        if (!rc)
            rc = objective_e2(&c, o, 0, &F, &e2, NULL);
        if (!rc)
            flicker_term(&c, 0, &F, &f2, NULL);
        if (rc)
            break;
        if (s == 0)
            result->first_score = score;
        if (score < result->score) {
            result->score = score;
            memcpy(best, o, N * sizeof *best);
            c.best = best;
            c.best_score = score;
            c.best_e2 = e2;
        }
        result->starts = c.starts = s + 1;
        if (p->progress) {
            double t = run_seconds(&c);
            aa_temporal_opt_progress pr = {.fraction = run_fraction(&c, t),
                                           .start = s,
                                           .start_from = s == 0 && p->start ? 0
                                                         : hop              ? 2
                                                                            : 1,
                                           .start_initial_score = initial,
                                           .start_score = score,
                                           .start_e2 = e2,
                                           .start_f2 = f2,
                                           .best_score = c.best_score,
                                           .best_e2 = c.best_e2,
                                           .best = best,
                                           .starts = c.starts,
                                           .evaluations = c.evaluations,
                                           .seconds = t};
            if (p->progress(p->progress_user, &pr))
                rc = AA_ECANCELED;
        }
    }
    if (!rc && result->starts > 0) {
        /* The winner's E2 and F2 apart. */
        double F;
        rc = objective_e2(&c, best, 0, &F, &result->e2, NULL);
        if (!rc)
            flicker_term(&c, 0, &F, &result->f2, NULL);
    }
    if (rc == AA_ECANCELED)
        aa_error_set(err, rc, "", "cancelled");
    else if (rc && (!err || !err->code))
        aa_error_set(err, rc, "", "the objective cannot be evaluated");
    result->evaluations = c.evaluations;
    result->seconds = c.params ? run_seconds(&c) : 0;
    ctx_free(&c);
    free(o);
    return rc;
}
