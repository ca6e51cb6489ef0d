/* The minimax step rule (AA_METHOD_MINIMAX): a proximal trust-region method for
 * E2 = max_i f_i(z), f_i = W(theta) E1(theta) of one kernel and angle, z the free variables.
 *
 * Laine & Aila's rule steps along a fixed blend of the near-maximal terms' gradients (c1 for the
 * active ones, c0 for the rest); at a kink of the max, where several terms are equal, that blend
 * rarely lowers all of them at once and the descent stalls (optimizer_perturb.c). Here each step
 * solves for the blend instead: with g_i the gradients of the terms near the maximum, the step
 * d minimises the linear model of the max plus a proximal term,
 *     max_i (f_i + g_i . d) + |d|^2 / (2 delta),
 * whose dual is max over the simplex of  f . lambda - (delta / 2) |sum lambda_i g_i|^2
 * (simplex_qp.h) and d = -delta sum lambda_i g_i: the minimum-norm element of the convex hull of
 * the gradients, shifted by the terms' values, i.e. steepest descent of the max itself. The
 * trust parameter delta grows when E2 falls as the model predicted and shrinks when it does not
 * (the model is first order, and E1 has kinks where projections cross). A step is accepted only
 * when E2 falls, so the run is monotone. Terms enter the model when they are within MM_BAND of
 * the maximum (at most MM_MAX_TERMS of them); coordinates on the boundary of their box that the
 * step would push outward are frozen for that step.
 * Cost per step of P(16,16,4): the gradients of <= 256 terms (~0.7 ms), their Gram matrix
 * (<= 256^2 / 2 sparse dot products, ~3 ms), the QP (O(m) per pairwise Frank-Wolfe iteration)
 * and one E2 evaluation (~1.3 ms). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "optimizer_run.h"
#include "simplex_qp.h"

#define MM_BAND 0.25
#define MM_MAX_TERMS 256
#define MM_FIRST_STEP 0.01 /* pixels: length of the first step */
/* The step's metric is |d_positions|^2 + |d_weights|^2 / MM_WEIGHT_SCALE^2: weights move 10x
 * less per unit of gradient than positions (P(16,16,4) W+P from one Poisson seed: 0.187 with
 * 0.1, 0.192 with 1, 0.240 with 10). Weights-only runs do not depend on it. */
#define MM_WEIGHT_SCALE 0.1

/* The free variables one kernel reads: points [plo, plo + pn), weight slots [wlo, wlo + wn). */
typedef struct mm_span {
    size_t plo, pn, wlo, wn;
} mm_span;

typedef struct mm_term {
    size_t k, a;
    double *g; /* [2 pn + wn] of kernel k: d f / d x, d f / d y, d f / d w */
} mm_term;

typedef struct mm_work {
    mm_span *span;
    size_t stride; /* max 2 pn + wn */
    mm_term *terms;
    double *gbuf;
    double *Q, *f, *lambda, *q;
    size_t *order;
    unsigned char *frozen_x, *frozen_y; /* per point */
} mm_work;

static void mm_free(mm_work *w)
{
    free(w->span);
    free(w->terms);
    free(w->gbuf);
    free(w->Q);
    free(w->f);
    free(w->lambda);
    free(w->q);
    free(w->order);
    free(w->frozen_x);
    free(w->frozen_y);
}

static int mm_init(mm_work *w, const opt_state *st, size_t angle_count, aa_error *err)
{
    memset(w, 0, sizeof *w);
    size_t kc = st->work.kernel_count, total = kc * angle_count;
    w->span = calloc(kc, sizeof *w->span);
    if (!w->span)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t k = 0; k < kc; k++) {
        size_t plo = SIZE_MAX, phi = 0, wlo = SIZE_MAX, whi = 0;
        for (size_t i = 0; i < st->work.kernels[k].count; i++) {
            const opt_ref *r = &st->refs[k][i];
            plo = r->point < plo ? r->point : plo;
            phi = r->point + 1 > phi ? r->point + 1 : phi;
            wlo = r->weight < wlo ? r->weight : wlo;
            whi = r->weight + 1 > whi ? r->weight + 1 : whi;
        }
        if (phi == 0)
            plo = wlo = 0;
        w->span[k] = (mm_span){plo, phi - plo, wlo, whi - wlo};
        size_t need = 2 * w->span[k].pn + w->span[k].wn;
        if (need > w->stride)
            w->stride = need;
    }
    size_t m = total < MM_MAX_TERMS ? total : MM_MAX_TERMS;
    w->terms = calloc(m, sizeof *w->terms);
    w->gbuf = malloc((m * w->stride + 1) * sizeof *w->gbuf);
    w->Q = malloc(m * m * sizeof *w->Q);
    w->f = malloc(m * sizeof *w->f);
    w->lambda = malloc(m * sizeof *w->lambda);
    w->q = malloc(m * sizeof *w->q);
    w->order = malloc(total * sizeof *w->order);
    w->frozen_x = calloc(st->point_count + 1, 1);
    w->frozen_y = calloc(st->point_count + 1, 1);
    if (!w->terms || !w->gbuf || !w->Q || !w->f || !w->lambda || !w->q || !w->order ||
        !w->frozen_x || !w->frozen_y)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    return AA_OK;
}

/* Indices of the terms within the band, largest first, at most MM_MAX_TERMS. */
static size_t select_terms(mm_work *w, const double *value, size_t total, double e2)
{
    size_t n = 0;
    for (size_t i = 0; i < total; i++)
        if (value[i] >= (1 - MM_BAND) * e2)
            w->order[n++] = i;
    /* Insertion sort: C11's qsort has no context argument for the values, and n is small. */
    for (size_t i = 1; i < n; i++) {
        size_t t = w->order[i];
        size_t j = i;
        while (j > 0 && value[w->order[j - 1]] < value[t]) {
            w->order[j] = w->order[j - 1];
            j--;
        }
        w->order[j] = t;
    }
    return n < MM_MAX_TERMS ? n : MM_MAX_TERMS;
}

/* Gradient of term (k, a) at cur, on the free variables of kernel k. */
static int term_gradient(opt_run *r, const opt_state *st, const mm_work *w, mm_term *t)
{
    const mm_span *sp = &w->span[t->k];
    memset(t->g, 0, (2 * sp->pn + sp->wn) * sizeof *t->g);
    const opt_gradient_target to = {t->g,    t->g + sp->pn, t->g + 2 * sp->pn, sp->plo,
                                    sp->wlo, w->frozen_x,   w->frozen_y};
    return opt_run_add_term_gradient(r, st, t->k, t->a, r->weight[t->a], &to);
}

static double span_dot(const mm_work *w, const mm_term *a, const mm_term *b)
{
    const double ws2 = MM_WEIGHT_SCALE * MM_WEIGHT_SCALE;
    const mm_span *sa = &w->span[a->k], *sb = &w->span[b->k];
    double s = 0;
    size_t lo = sa->plo > sb->plo ? sa->plo : sb->plo;
    size_t hi = sa->plo + sa->pn < sb->plo + sb->pn ? sa->plo + sa->pn : sb->plo + sb->pn;
    for (size_t p = lo; p < hi; p++) {
        size_t ia = p - sa->plo, ib = p - sb->plo;
        s += a->g[ia] * b->g[ib] + a->g[sa->pn + ia] * b->g[sb->pn + ib];
    }
    double s2 = 0;
    lo = sa->wlo > sb->wlo ? sa->wlo : sb->wlo;
    hi = sa->wlo + sa->wn < sb->wlo + sb->wn ? sa->wlo + sa->wn : sb->wlo + sb->wn;
    for (size_t q = lo; q < hi; q++)
        s2 += a->g[2 * sa->pn + q - sa->wlo] * b->g[2 * sb->pn + q - sb->wlo];
    return s + ws2 * s2;
}

/* Gradients and Gram matrix of the m selected terms at cur. */
static int build_model(opt_run *r, const opt_state *st, mm_work *w, const double *value, size_t m)
{
    for (size_t j = 0; j < m; j++) {
        mm_term *t = &w->terms[j];
        size_t idx = w->order[j];
        t->k = idx / r->angle_count;
        t->a = idx % r->angle_count;
        t->g = w->gbuf + j * w->stride;
        w->f[j] = value[idx];
        int rc = term_gradient(r, st, w, t);
        if (rc)
            return rc;
    }
    for (size_t i = 0; i < m; i++)
        for (size_t j = i; j < m; j++)
            w->Q[i * m + j] = w->Q[j * m + i] = span_dot(w, &w->terms[i], &w->terms[j]);
    return AA_OK;
}

/* dir := sum lambda_j g_j on the free variables. */
static void direction(opt_run *r, const opt_state *st, const mm_work *w, size_t m)
{
    memset(r->dir_x, 0, st->point_count * sizeof *r->dir_x);
    memset(r->dir_y, 0, st->point_count * sizeof *r->dir_y);
    memset(r->dir_w, 0, st->weight_count * sizeof *r->dir_w);
    for (size_t j = 0; j < m; j++) {
        double l = w->lambda[j];
        if (l == 0)
            continue;
        const mm_term *t = &w->terms[j];
        const mm_span *sp = &w->span[t->k];
        for (size_t p = 0; p < sp->pn; p++) {
            r->dir_x[sp->plo + p] += l * t->g[p];
            r->dir_y[sp->plo + p] += l * t->g[sp->pn + p];
        }
        for (size_t q = 0; q < sp->wn; q++)
            r->dir_w[sp->wlo + q] += l * MM_WEIGHT_SCALE * MM_WEIGHT_SCALE * t->g[2 * sp->pn + q];
    }
}

/* Freezes the coordinates that sit on their box and that the step would push outward; returns
 * whether any was newly frozen. */
static bool freeze_blocked(const opt_run *r, const opt_state *st, mm_work *w)
{
    bool any = false;
    const double tiny = 1e-12;
    for (size_t p = 0; p < st->point_count; p++) {
        const opt_point *pt = &st->points[p];
        /* The step is -delta dir. */
        if (!w->frozen_x[p] && ((pt->x <= pt->lo_x + tiny && r->dir_x[p] > 0) ||
                                (pt->x >= pt->hi_x - tiny && r->dir_x[p] < 0))) {
            w->frozen_x[p] = 1;
            any = true;
        }
        if (!w->frozen_y[p] && ((pt->y <= pt->lo_y + tiny && r->dir_y[p] > 0) ||
                                (pt->y >= pt->hi_y - tiny && r->dir_y[p] < 0))) {
            w->frozen_y[p] = 1;
            any = true;
        }
    }
    return any;
}

/* Solves the step's QP for the current delta; returns the predicted decrease of E2. */
static double solve_step(mm_work *w, size_t m, double delta, double e2)
{
    memset(w->lambda, 0, m * sizeof *w->lambda);
    aa_simplex_qp_solve(m, w->Q, w->f, delta, w->lambda, w->q, 1e-9 * e2, 200 * (long)m + 1000,
                        NULL);
    double model = -INFINITY;
    for (size_t j = 0; j < m; j++)
        model = fmax(model, w->f[j] - delta * w->q[j]);
    return e2 - model;
}

int opt_descend_minimax(opt_loop *L)
{
    opt_run *r = &L->run;
    size_t total = r->angle_count * L->cur.work.kernel_count;
    const double *cur_value = r->cur_value;
    mm_work w;
    int rc = mm_init(&w, &L->cur, r->angle_count, L->err);
    if (rc) {
        mm_free(&w);
        return rc;
    }
    double delta = 0;
    bool done = false;
    while (!rc && !done) {
        /* A new model at cur. */
        size_t m = select_terms(&w, cur_value, total, L->e2);
        memset(w.frozen_x, 0, L->cur.point_count);
        memset(w.frozen_y, 0, L->cur.point_count);
        if (m == 0 || (rc = build_model(r, &L->cur, &w, cur_value, m)))
            break;
        if (delta == 0)
            delta = w.Q[0] > 0 ? MM_FIRST_STEP / sqrt(w.Q[0]) : 1;
        double pred = solve_step(&w, m, delta, L->e2);
        direction(r, &L->cur, &w, m);
        if (freeze_blocked(r, &L->cur, &w)) {
            if ((rc = build_model(r, &L->cur, &w, cur_value, m)))
                break;
            pred = solve_step(&w, m, delta, L->e2);
            direction(r, &L->cur, &w, m);
        }
        /* Steps along this model until one is accepted. */
        for (;;) {
            if (!(pred > 1e-13 * L->e2) || delta < 1e-300) {
                done = true; /* stationary: no direction lowers every near-maximal term */
                break;
            }
            if ((rc = opt_loop_tick(L)))
                break;
            L->it++;
            opt_run_take_step(r, &L->trial, &L->cur, delta);
            double te2;
            if ((rc = opt_run_eval_e2(r, &L->trial, &te2)))
                break;
            double ratio = (L->e2 - te2) / pred;
            if (te2 < L->e2 && ratio >= 0.1) {
                opt_loop_accept(L, te2);
                if (ratio > 0.75)
                    delta *= 2;
                else if (ratio < 0.25)
                    delta *= 0.5;
                break;
            }
            delta *= 0.25;
            pred = solve_step(&w, m, delta, L->e2);
            direction(r, &L->cur, &w, m);
        }
        if (rc)
            break;
        if (opt_loop_stalled(L))
            break;
    }
    mm_free(&w);
    return rc == 1 ? AA_OK : rc;
}
