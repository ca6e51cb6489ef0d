/* The reference's step response across an edge at angle θ (edge_profile.h). */
#include "edge_profile.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aa_core.h"

#define PI 3.14159265358979323846
/* Points per polynomial piece of the integrand h(x) g((a - x c) / s): degree 3 + 4 <= 2 * 4 - 1. */
#define EXACT_GL 4
/* Points per interval of the E1 sweep: (c - g_θ)² has degree 2 * 12 < 2 * 13. */
#define SWEEP_GL (AA_EDGE_PROFILE_DEGREE + 1)

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

static double exact_with_rule(const aa_filter *f, double c, double s, double a, const double *node,
                              const double *weight)
{
    c = fabs(c);
    s = fabs(s);
    if (s < 1e-12 || c < 1e-12)
        return aa_filter_cdf(f, a);
    double R = f->radius;
    if (a <= -(c + s) * R)
        return 0;
    if (a >= (c + s) * R)
        return 1;
    /* The integrand is one polynomial between the filter's knots and the points where
     * (a - x c) / s crosses one. */
    double br[2 * (AA_FILTER_MAX_PIECES + 1) + 2];
    size_t n = 0;
    br[n++] = -R;
    br[n++] = R;
    for (int k = 0; k <= f->pieces; k++) {
        br[n++] = f->knot[k];
        double x = (a - f->knot[k] * s) / c;
        if (x > -R && x < R)
            br[n++] = x;
    }
    qsort(br, n, sizeof br[0], cmp_double);
    double sum = 0;
    for (size_t k = 0; k + 1 < n; k++) {
        double lo = fmax(br[k], -R), hi = fmin(br[k + 1], R);
        if (!(hi > lo))
            continue;
        double mid = (lo + hi) / 2, half = (hi - lo) / 2;
        for (int g = 0; g < EXACT_GL; g++) {
            double x = mid + half * node[g];
            sum += half * weight[g] * aa_filter_eval(f, x) * aa_filter_cdf(f, (a - x * c) / s);
        }
    }
    return sum;
}

double aa_edge_profile_exact(const aa_filter *f, double c, double s, double a)
{
    double node[EXACT_GL], weight[EXACT_GL];
    aa_gauss_legendre(EXACT_GL, node, weight);
    return exact_with_rule(f, c, s, a, node, weight);
}

static int knots_of(const aa_filter *f, double c, double s, double *knot)
{
    double R = (c + s) * f->radius;
    int n = 0;
    if (f->closed_pieces > 0 && f->pieces <= 7) {
        /* Piecewise-cubic filter: g_θ is one polynomial between the sums of scaled knots. */
        double all[8 * 8];
        int m = 0;
        for (int i = 0; i <= f->pieces; i++)
            for (int j = 0; j <= f->pieces; j++)
                all[m++] = f->knot[i] * c + f->knot[j] * s;
        qsort(all, (size_t)m, sizeof all[0], cmp_double);
        for (int i = 0; i < m; i++)
            if (n == 0 || all[i] - knot[n - 1] > 1e-12 * R)
                knot[n++] = all[i];
        if (n > AA_EDGE_PROFILE_MAX_PIECES + 1)
            n = 0; /* cannot happen with <= 7 pieces (64 sums); fall through to equal pieces */
    }
    if (n < 2) {
        n = AA_EDGE_PROFILE_MAX_PIECES + 1;
        for (int i = 0; i < n; i++)
            knot[i] = -R + 2 * R * i / (n - 1);
    }
    knot[0] = -R;
    knot[n - 1] = R;
    return n - 1;
}

void aa_edge_profile_init(aa_edge_profile *p, const aa_filter *f, double theta)
{
    memset(p, 0, sizeof *p);
    p->c = fabs(cos(theta));
    p->s = fabs(sin(theta));
    if (p->c < 1e-15)
        p->c = 0;
    if (p->s < 1e-15)
        p->s = 0;
    p->reach = (p->c + p->s) * f->radius;
    p->pieces = knots_of(f, p->c, p->s, p->knot);
    const int M = AA_EDGE_PROFILE_DEGREE + 1;
    double node[EXACT_GL], weight[EXACT_GL];
    aa_gauss_legendre(EXACT_GL, node, weight);
    aa_gauss_legendre(SWEEP_GL, p->rule_node, p->rule_weight);
    for (int j = 0; j < p->pieces; j++) {
        double lo = p->knot[j], hi = p->knot[j + 1], v[AA_EDGE_PROFILE_DEGREE + 1];
        for (int m = 0; m < M; m++) {
            double t = cos(PI * (m + 0.5) / M);
            v[m] = exact_with_rule(f, p->c, p->s, (lo + hi) / 2 + (hi - lo) / 2 * t, node, weight);
        }
        for (int k = 0; k < M; k++) {
            double sum = 0;
            for (int m = 0; m < M; m++)
                sum += v[m] * cos(PI * k * (m + 0.5) / M);
            p->cheb[j][k] = sum * 2 / M / (k == 0 ? 2 : 1);
        }
    }
}

static double eval_piece(const aa_edge_profile *p, int j, double a)
{
    double lo = p->knot[j], hi = p->knot[j + 1];
    double t = (2 * a - lo - hi) / (hi - lo), b1 = 0, b2 = 0;
    for (int k = AA_EDGE_PROFILE_DEGREE; k >= 1; k--) {
        double b0 = 2 * t * b1 - b2 + p->cheb[j][k];
        b2 = b1;
        b1 = b0;
    }
    return t * b1 - b2 + p->cheb[j][0];
}

/* The piece holding a (clamped to the table). */
static int piece_of(const aa_edge_profile *p, double a)
{
    int lo = 0, hi = p->pieces - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (p->knot[mid] <= a)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

double aa_edge_profile_eval(const aa_edge_profile *p, double a)
{
    if (a <= -p->reach)
        return 0;
    if (a >= p->reach)
        return 1;
    return eval_piece(p, piece_of(p, a), a);
}

typedef struct event {
    double at, w; /* a sample's projection and weight; w = 0 for a knot */
} event;

static int cmp_event(const void *x, const void *y)
{
    return cmp_double(&((const event *)x)->at, &((const event *)y)->at);
}

int aa_edge_profile_e1(const aa_edge_profile *p, const aa_sample *s, size_t n, double ct, double st,
                       double *e1)
{
    *e1 = NAN;
    if (n == 0)
        return AA_EINVAL;
    size_t count = n + (size_t)p->pieces + 1;
    event local[256], *ev = count <= 256 ? local : malloc(count * sizeof *ev);
    if (!ev)
        return AA_ENOMEM;
    double total = 0;
    for (size_t i = 0; i < n; i++) {
        ev[i] = (event){s[i].x * ct + s[i].y * st, s[i].w};
        total += s[i].w;
    }
    for (int j = 0; j <= p->pieces; j++)
        ev[n + (size_t)j] = (event){p->knot[j], 0};
    qsort(ev, count, sizeof ev[0], cmp_event);
    const double *node = p->rule_node, *weight = p->rule_weight;
    /* Left of the first event ĝ = 0 = g_θ; right of the last, ĝ = Σw and g_θ = 1. */
    double c = 0, sum = 0;
    for (size_t e = 0; e + 1 < count; e++) {
        c += ev[e].w;
        double lo = ev[e].at, hi = ev[e + 1].at;
        if (!(hi > lo))
            continue;
        if (hi <= -p->reach) {
            sum += c * c * (hi - lo);
        } else if (lo >= p->reach) {
            sum += (c - 1) * (c - 1) * (hi - lo);
        } else {
            /* Inside one piece of the table: knots are events. */
            int j = piece_of(p, (lo + hi) / 2);
            double mid = (lo + hi) / 2, half = (hi - lo) / 2;
            for (int g = 0; g < SWEEP_GL; g++) {
                double d = c - eval_piece(p, j, mid + half * node[g]);
                sum += half * weight[g] * d * d;
            }
        }
    }
    if (ev != local)
        free(ev);
    *e1 = fabs(total - 1) > 1e-9 ? INFINITY : sqrt(sum);
    return AA_OK;
}
