/* Flicker F1 and its gradient (temporal_flicker.h). */
#include <assert.h>
#include <math.h>
#include <stdlib.h>

#include "temporal_flicker.h"
#include "temporal_eval.h"

/* Insertion sort by (key, index), ties in input order as in the metric: the order carries over
 * from the previous direction, so it is nearly sorted already (qsort has no context argument). */
static void sort_order(const double *key, size_t *order, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        size_t v = order[i];
        size_t j = i;
        while (j > 0 &&
               (key[order[j - 1]] > key[v] || (key[order[j - 1]] == key[v] && order[j - 1] > v))) {
            order[j] = order[j - 1];
            j--;
        }
        order[j] = v;
    }
}

int aa_flicker_scratch_init(aa_flicker_scratch *sc, const aa_temporal *t, size_t m)
{
    assert(t->phase_count >= 1); /* the mean age weight below */
    size_t cap = m ? m : 1;
    sc->p = malloc(cap * sizeof *sc->p);
    sc->order = malloc(cap * sizeof *sc->order);
    sc->d2 = malloc(cap * sizeof *sc->d2);
    sc->dev = malloc(t->phase_count * sizeof *sc->dev);
    if (!sc->p || !sc->order || !sc->dev || !sc->d2)
        return AA_ENOMEM;
    aa_flicker_scratch_reset(sc, m);
    double mean = 0;
    for (size_t j = 0; j < t->phase_count; j++)
        mean += t->age_weight[j];
    mean /= (double)t->phase_count;
    for (size_t j = 0; j < t->phase_count; j++)
        sc->dev[j] = t->age_weight[j] - mean;
    return AA_OK;
}

void aa_flicker_scratch_free(aa_flicker_scratch *sc)
{
    free(sc->p);
    free(sc->order);
    free(sc->dev);
    free(sc->d2);
}

void aa_flicker_scratch_reset(aa_flicker_scratch *sc, size_t m)
{
    for (size_t i = 0; i < m; i++)
        sc->order[i] = i;
}

/* F1^2 = (1/N) sum_p sum_k len_k D_{p,k}^2, D_{p,k} the prefix sum over the sorted samples of
 * phase p's weight minus the mean weight: every term >= 0. Moving the k-th sorted projection
 * lengthens gap k - 1 and shortens gap k: dF1^2/dp = (1/N) sum_p (D_{p,k-1}^2 - D_{p,k}^2). */
double aa_flicker_sorted(const aa_temporal *t, size_t g, double ct, double st,
                         aa_flicker_scratch *sc, double *dp)
{
    assert(g < t->group_count && t->phase_count >= 1);
    const aa_temporal_group *grp = &t->groups[g];
    size_t m = grp->count, N = t->phase_count;
    for (size_t i = 0; i < m; i++)
        sc->p[i] = grp->pos[i].x * ct + grp->pos[i].y * st;
    sort_order(sc->p, sc->order, m);
    for (size_t k = 0; k < m; k++)
        sc->d2[k] = 0;
    double total = 0;
    for (size_t ph = 0; ph < N; ph++) {
        double D = 0, sum = 0;
        for (size_t k = 0; k + 1 < m; k++) {
            size_t s = sc->order[k];
            assert(s < m && grp->frame[s] < N); /* a sample's frame is a phase */
            D += grp->in_frame[s] * sc->dev[(ph + N - grp->frame[s]) % N];
            double len = sc->p[sc->order[k + 1]] - sc->p[s];
            sum += len * D * D;
            sc->d2[k] += D * D;
        }
        total += sum;
    }
    double f1 = sqrt(total / (double)N);
    if (dp) {
        for (size_t k = 0; k < m; k++) {
            double left = k > 0 ? sc->d2[k - 1] : 0, right = k + 1 < m ? sc->d2[k] : 0;
            dp[sc->order[k]] = f1 > 0 ? (left - right) / (2 * (double)N * f1) : 0;
        }
    }
    return f1;
}

int aa_temporal_flicker_at_direction(const aa_temporal *t, size_t g, double ct, double st,
                                     double *f1, double *dp)
{
    assert(g < t->group_count);
    aa_flicker_scratch sc = {0};
    int rc = aa_flicker_scratch_init(&sc, t, t->groups[g].count);
    if (!rc)
        *f1 = aa_flicker_sorted(t, g, ct, st, &sc, dp);
    aa_flicker_scratch_free(&sc);
    return rc;
}

int aa_temporal_flicker_step_at_direction(const aa_temporal *t, size_t g, double ct, double st,
                                          double *f1)
{
    assert(g < t->group_count);
    aa_flicker_scratch sc = {0};
    int rc = aa_flicker_scratch_init(&sc, t, t->groups[g].count);
    if (!rc) {
        /* Phase p against phase p - 1: a sample j frames old in p was j - 1 old in p - 1. */
        size_t N = t->phase_count;
        for (size_t j = 0; j < N; j++)
            sc.dev[j] = t->age_weight[j] - t->age_weight[(j + N - 1) % N];
        *f1 = aa_flicker_sorted(t, g, ct, st, &sc, NULL);
    }
    aa_flicker_scratch_free(&sc);
    return rc;
}
