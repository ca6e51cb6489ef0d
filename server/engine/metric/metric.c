/* Exact E1: the closed form with its error estimate, and the quadrature sweep it falls back to;
 * see metric.h for the formulas and precision, docs/metric.md for the derivation. */
#include "metric.h"
#include "order.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void aa_metric_workspace_init(aa_metric_workspace *ws)
{
    memset(ws, 0, sizeof *ws);
}

/* Closed-form error estimate. The terms are summed with compensation (closed_form), so E1^2's
 * error is about eps * spread, spread = sqrt(sum of the squared terms), and E1's relative error
 * about eps * cond / 2 with cond = spread / E1^2. Measured in tests/engine/test_metric_exactness
 * (13,000 kernels, n up to 1024, cancelling cases included): at most 2.01 eps * cond, printed
 * there. The estimate takes SAFETY = 4 eps * cond. */
#define AA_E1_CLOSED_SAFETY 4.0

void aa_metric_workspace_free(aa_metric_workspace *ws)
{
    free(ws->p);
    free(ws->w);
    free(ws->in_x);
    free(ws->in_y);
    free(ws->in_w);
    free(ws->in_p);
    free(ws->index);
    free(ws->tail);
    free(ws->cdf);
    free(ws->u);
    free(ws->len);
    free(ws->padded);
    memset(ws, 0, sizeof *ws);
}

static int grow_doubles(double **a, size_t cap)
{
    double *q = realloc(*a, cap * sizeof *q);
    if (!q)
        return AA_ENOMEM;
    *a = q;
    return AA_OK;
}

static int reserve(aa_metric_workspace *ws, size_t n)
{
    if (n <= ws->capacity)
        return AA_OK;
    size_t cap = ws->capacity ? ws->capacity : 16;
    while (cap < n)
        cap *= 2;
    if (grow_doubles(&ws->p, cap) || grow_doubles(&ws->w, cap) || grow_doubles(&ws->in_x, cap) ||
        grow_doubles(&ws->in_y, cap) || grow_doubles(&ws->in_w, cap) ||
        grow_doubles(&ws->in_p, cap) || grow_doubles(&ws->tail, cap) ||
        grow_doubles(&ws->cdf, cap) || grow_doubles(&ws->u, cap) || grow_doubles(&ws->len, cap))
        return AA_ENOMEM;
    /* The rank pass loads 64-byte windows at every offset of this buffer; a load that crosses a
     * page boundary costs several plain ones (measured: a P(16,16,4) evaluation took 430 us
     * instead of 340 us when the buffer straddled a page). Starting it at a page keeps kernels
     * of up to 480 samples inside one. Its contents need not survive the growth. */
    size_t bytes = (cap + 2 * AA_ORDER_WINDOW) * sizeof(double);
    free(ws->padded);
    ws->padded = aligned_alloc(4096, (bytes + 4095) / 4096 * 4096);
    if (!ws->padded)
        return AA_ENOMEM;
    /* index has a second half: scratch for the sorts (order.c) */
    uint32_t *ix = realloc(ws->index, 2 * cap * sizeof *ix);
    if (!ix)
        return AA_ENOMEM;
    ws->index = ix;
    ws->capacity = cap;
    return AA_OK;
}

/* cos and sin with the axis and diagonal directions exact, so that samples that tie at
 * 0, 45, 90 ... degrees tie in floating point too. */
void aa_metric_direction(double theta, double *c, double *s)
{
    double cc = cos(theta), ss = sin(theta);
    if (fabs(cc) < 1e-15) {
        cc = 0;
        ss = ss > 0 ? 1 : -1;
    } else if (fabs(ss) < 1e-15) {
        ss = 0;
        cc = cc > 0 ? 1 : -1;
    } else if (fabs(fabs(cc) - fabs(ss)) < 1e-15) {
        cc = copysign(0.70710678118654752440, cc);
        ss = copysign(0.70710678118654752440, ss);
    }
    *c = cc;
    *s = ss;
}

/* Projects the kernel on (ct, st) into ws's arrays, sorted by (p, index). Starts from the order
 * of the previous call when it was for the same samples (neighbouring angles of one kernel):
 * the samples are read again in that order (the caller may have moved them) and re-sorted
 * (order.h); else a first sort from the input order. */
static void project_sorted(const aa_sample *s, size_t n, double ct, double st,
                           aa_metric_workspace *ws)
{
    if (ws->order_of == (const void *)s && ws->order_n == n) {
        for (size_t k = 0; k < n; k++) {
            const aa_sample *q = &s[ws->index[k]];
            ws->p[k] = q->x * ct + q->y * st;
        }
        aa_order_resort(ws, n);
    } else {
        for (size_t i = 0; i < n; i++)
            ws->in_p[i] = s[i].x * ct + s[i].y * st;
        aa_order_fresh(ws, n);
    }
    for (size_t k = 0; k < n; k++)
        ws->w[k] = s[ws->index[k]].w;
    ws->order_of = s;
    ws->order_n = n;
}

/* The block's projection: the kernel's coordinates as arrays in input order (in_x, in_y), one
 * contiguous loop (vectorised), then the keys gathered into the previous angle's order and
 * re-sorted (order.h), then the weights gathered into the new order. */
static void project_block(size_t n, double ct, double st, bool first, aa_metric_workspace *ws)
{
    double *restrict q = ws->in_p;
    const double *restrict x = ws->in_x, *restrict y = ws->in_y;
    for (size_t i = 0; i < n; i++)
        q[i] = x[i] * ct + y[i] * st;
    if (first) {
        aa_order_fresh(ws, n);
    } else {
        for (size_t k = 0; k < n; k++)
            ws->p[k] = q[ws->index[k]];
        aa_order_resort(ws, n);
    }
    for (size_t k = 0; k < n; k++)
        ws->w[k] = ws->in_w[ws->index[k]];
}

/* Integral over [u, v] of (c - g)^2 (and of (c - g) when want_linear) where g is filter
 * piece j, or the constant 0 (j < 0) / 1 (j >= pieces). */
static void segment_integral(const aa_filter *f, int j, double c, double u, double v, double *sq,
                             double *lin)
{
    double len = v - u;
    if (j < 0 || j >= f->pieces) {
        double d = j < 0 ? c : c - 1;
        *sq += d * d * len;
        *lin += d * len;
        return;
    }
    /* Map the rule's nodes straight into the piece's Chebyshev variable: t = alpha + beta*x. */
    double lo = f->knot[j], hi = f->knot[j + 1], inv = 1.0 / (hi - lo);
    double alpha = (u + v - lo - hi) * inv, beta = len * inv;
    const double *cf = f->cheb[j];
    int deg = f->degree;
    double s2 = 0, s1 = 0;
    for (int k = 0; k <= deg; k++) {
        double t = alpha + beta * f->rule_node[k], t2 = 2 * t, b1 = 0, b2 = 0;
        for (int m = deg; m >= 1; m--) {
            double b0 = t2 * b1 - b2 + cf[m];
            b2 = b1;
            b1 = b0;
        }
        double d = c - (t * b1 - b2 + cf[0]);
        s2 += f->rule_weight[k] * d * d;
        s1 += f->rule_weight[k] * d;
    }
    *sq += s2 * 0.5 * len;
    *lin += s1 * 0.5 * len;
}

/* The quadrature sweep over ws->p, ws->w (sorted). When tail is wanted, ws->tail[k] = integral of
 * (ghat - g) from -inf to the k-th sorted projection. Returns E1^2. */
static double sweep(const aa_filter *f, size_t n, aa_metric_workspace *ws, bool want_tail)
{
    const double *pp = ws->p, *pw = ws->w;
    const double *knot = f->knot;
    int pieces = f->pieces;
    double lo = fmin(pp[0], knot[0]), hi = fmax(pp[n - 1], knot[pieces]);
    /* j: piece of the filter that the current point a lies in (-1 before the support). */
    int j = lo < knot[0] ? -1 : 0;
    double a = lo, c = 0, sq = 0, lin = 0;
    size_t i = 0;
    while (i < n && pp[i] <= a) {
        if (want_tail)
            ws->tail[i] = lin;
        c += pw[i++];
    }
    while (a < hi) {
        double next_knot = j + 1 <= pieces ? knot[j + 1] : INFINITY;
        double b = i < n ? fmin(pp[i], next_knot) : next_knot;
        if (b > hi)
            b = hi;
        if (b > a)
            segment_integral(f, j, c, a, b, &sq, &lin);
        a = b;
        while (j + 1 <= pieces && knot[j + 1] <= a)
            j++;
        while (i < n && pp[i] <= a) {
            if (want_tail)
                ws->tail[i] = lin;
            c += pw[i++];
        }
        if (i >= n && j >= pieces)
            break; /* beyond both: ghat = 1 = g (weights sum to 1) */
    }
    return sq;
}

/* The table piece of a in (-r, r): its coefficients, and a's offset from its middle in *s. */
static inline const double *closed_piece(const aa_filter *f, double a, double *s)
{
    int j = (int)((a + f->radius) * f->closed_inv_width);
    j = j < 0 ? 0 : (j >= f->closed_pieces ? f->closed_pieces - 1 : j);
    *s = a - f->closed_mid[j];
    return f->closed_gamma[j];
}

/* Gamma(a) and gamma(a) = Gamma'(a) = g(a) - 1/2 for a in (-r, r), from the tables. */
static inline double closed_gamma(const aa_filter *f, double a, double *gamma)
{
    double s;
    const double *c = closed_piece(f, a, &s);
    double v = c[AA_FILTER_CLOSED_DEGREE], d = 0;
    for (int k = AA_FILTER_CLOSED_DEGREE - 1; k >= 0; k--) {
        d = d * s + v;
        v = v * s + c[k];
    }
    *gamma = d;
    return v;
}

/* Gamma(a) alone (the E1-only sweep). */
static inline double closed_gamma_value(const aa_filter *f, double a)
{
    double s;
    const double *c = closed_piece(f, a, &s);
    double v = c[AA_FILTER_CLOSED_DEGREE];
    for (int k = AA_FILTER_CLOSED_DEGREE - 1; k >= 0; k--)
        v = v * s + c[k];
    return v;
}

/* Sums of the closed form over ws->p, ws->w (sorted). The line is cut at -r and r: left of -r the
 * integrand is c^2, right of r (c - 1)^2 (no cancellation); in between E1^2's share is
 * V + sum (c - 1/2)^2 len + 2 sum w Gamma(p), whose terms cancel down to E1^2. They are summed
 * with a compensated (TwoSum) accumulator, so the summation adds about eps E1^2; what remains
 * is each term's own rounding, a few eps of it, independent between terms: the error is about
 * eps sqrt(sum of the squared terms), which is the "spread" kept for the estimate. */
typedef struct closed_sums {
    double e1sq;   /* E1^2 */
    double spread; /* sqrt(sum of the squared terms) */
} closed_sums;

typedef struct compensated {
    double sum, comp, sq;
} compensated;

static inline void add_term(compensated *acc, double t)
{
    double x = acc->sum + t, z = x - acc->sum;
    acc->comp += (acc->sum - (x - z)) + (t - z);
    acc->sum = x;
    acc->sq += t * t;
}

/* c += w with the rounding error kept in *lo: the prefix sums enter the closed form through
 * (c - 1/2)^2, whose terms are far larger than E1^2, so their rounding must not add up over n
 * samples (the quadrature needs no such care: there c enters as c - g, small). */
static inline void add_weight(double *c, double *lo, double w)
{
    double x = *c + w, z = x - *c;
    *lo += (*c - (x - z)) + (w - z);
    *c = x;
}

/* Two lanes of double (SSE2 on x86-64, NEON on arm64; plain scalar code elsewhere): the closed
 * form's per-sample work is independent between samples once the prefix sums are known, so two
 * samples share each arithmetic instruction. Every lane operation is the scalar one (no FMA: ISO C
 * without contraction), so a lane computes exactly what the scalar code computes. */
typedef double v2d __attribute__((vector_size(16)));

typedef struct compensated2 {
    v2d sum, comp, sq;
} compensated2;

static inline void add_term2(compensated2 *acc, v2d t)
{
    v2d x = acc->sum + t, z = x - acc->sum;
    acc->comp += (acc->sum - (x - z)) + (t - z);
    acc->sum = x;
    acc->sq += t * t;
}

/* x added to acc's compensated sum (its square is already in a spread). */
static inline void fold_sum(compensated *acc, double x)
{
    double y = acc->sum + x, z = y - acc->sum;
    acc->comp += (acc->sum - (y - z)) + (x - z);
    acc->sum = y;
}

static inline v2d load2(const double *a)
{
    v2d v;
    memcpy(&v, a, sizeof v);
    return v;
}

static inline void store2(double *a, v2d v)
{
    memcpy(a, &v, sizeof v);
}

/* The inside samples [k, kb) of one table piece (coefficients cf, middle mid), two at a time;
 * an odd last sample is paired with an empty lane (u = len = w = 0, s = 0), whose terms are
 * exact zeros. ws->u, ws->len hold u_k and len_k from the prefix pass; with want_prefix
 * ws->tail[k] holds the running integral of the constant parts, from which Gamma(p_k) is taken,
 * and ws->cdf[k] gets g(p_k). */
static inline void closed_piece_run(const double *cf, double mid, size_t k, size_t kb,
                                    aa_metric_workspace *ws, compensated2 *acc, compensated2 *gam,
                                    const bool want_prefix)
{
    const double *pp = ws->p, *pw = ws->w, *uu = ws->u, *ll = ws->len;
    v2d vm = {mid, mid}, two = {2, 2}, half = {0.5, 0.5};
    v2d c[AA_FILTER_CLOSED_DEGREE + 1];
    for (int m = 0; m <= AA_FILTER_CLOSED_DEGREE; m++)
        c[m] = (v2d){cf[m], cf[m]};
    for (; k < kb; k += 2) {
        bool pair = k + 1 < kb;
        v2d p, u, len, w;
        if (pair) {
            p = load2(pp + k);
            u = load2(uu + k);
            len = load2(ll + k);
            w = load2(pw + k);
        } else {
            p = (v2d){pp[k], mid};
            u = (v2d){uu[k], 0};
            len = (v2d){ll[k], 0};
            w = (v2d){pw[k], 0};
        }
        add_term2(acc, u * u * len);
        v2d s = p - vm, v = c[AA_FILTER_CLOSED_DEGREE], d = {0, 0};
        for (int m = AA_FILTER_CLOSED_DEGREE - 1; m >= 0; m--) {
            if (want_prefix)
                d = d * s + v;
            v = v * s + c[m];
        }
        add_term2(gam, two * w * v);
        if (want_prefix) {
            v2d g = half + d, pre = (pair ? load2(ws->tail + k) : (v2d){ws->tail[k], 0}) - v;
            if (pair) {
                store2(ws->cdf + k, g);
                store2(ws->tail + k, pre);
            } else {
                ws->cdf[k] = g[0];
                ws->tail[k] = pre[0];
            }
        }
    }
}

/* The table pieces' ends among the inside samples [k, end): ends[j] is the first position whose
 * piece, floor((p + r) * inv), exceeds j (end for the last piece). The piece index is monotone in
 * p (sorted), so bisections find them, with steps that depend on the length alone (a scan would
 * mispredict at each piece's end), all pieces' searches interleaved (each step waits for a load
 * and a comparison: one search alone is bound by that latency). */
static inline void piece_ends(const double *pp, size_t k, size_t end, double r, double inv,
                              int pieces, size_t *ends)
{
    const double *base[AA_FILTER_CLOSED_MAX_PIECES];
    double next[AA_FILTER_CLOSED_MAX_PIECES];
    int searched = pieces - 1;
    ends[searched] = end;
    if (k == end) {
        for (int j = 0; j < searched; j++)
            ends[j] = end;
        return;
    }
    for (int j = 0; j < searched; j++) {
        base[j] = pp + k;
        next[j] = j + 1;
    }
    size_t len = end - k;
    while (len > 1) {
        size_t half = len / 2;
        for (int j = 0; j < searched; j++)
            base[j] = (base[j][half] + r) * inv < next[j] ? base[j] + half : base[j];
        len -= half;
    }
    for (int j = 0; j < searched; j++)
        ends[j] = (size_t)(base[j] - pp) + ((base[j][0] + r) * inv < next[j]);
}

/* Up to this many samples inside the support, the closed form runs in one lane (one pass): the
 * two-lane form's setup (a second pass, the pieces' ends, broadcast coefficients) costs more than
 * it saves there (bench_metric's 4 and 16 samples). */
#define AA_CLOSED_ONE_LANE_MAX 16

/* want_prefix is a constant at each call site (closed_form_e1, closed_form_prefix): the E1-only
 * copy skips the prefix integrals. */
static inline __attribute__((always_inline)) closed_sums
closed_form_impl(const aa_filter *f, const double *pp, const double *pw, size_t n,
                 aa_metric_workspace *ws, const bool want_prefix, const bool small)
{
    double *prefix = ws->tail, r = f->radius, c = 0, lo = 0, lin = 0;
    compensated acc = {f->closed_var, 0, f->closed_var * f->closed_var};
    compensated gam = {0, 0, 0}; /* the Gamma terms (one lane): a second dependency chain */
    /* The inside terms in two lanes each: (c - 1/2)^2 len, and 2 w Gamma(p) (a second chain). */
    compensated2 accv = {{0, 0}, {0, 0}, {0, 0}}, gamv = {{0, 0}, {0, 0}, {0, 0}};
    /* The sorted samples fall into three runs: p <= -r, inside, p >= r. One loop each, no
     * region tests inside them. ws->tail[k] gets P_k = integral_{-inf}^{p_k} (ghat - g) for the
     * weight gradient: the running integral of the constant parts minus Gamma(p_k). */
    size_t i0 = 0, i1 = n;
    while (i0 < n && !(pp[i0] > -r))
        i0++;
    while (i1 > i0 && !(pp[i1 - 1] < r))
        i1--;
    double a = i0 > 0 ? pp[0] : -r;
    for (size_t k = 0; k < i0; k++) {
        double cc = c + lo, len = pp[k] - a;
        add_term(&acc, cc * cc * len);
        lin += cc * len;
        if (want_prefix) {
            prefix[k] = lin;
            ws->cdf[k] = 0;
        }
        add_weight(&c, &lo, pw[k]);
        a = pp[k];
    }
    if (i0 > 0) {
        double cc = c + lo, len = -r - a;
        add_term(&acc, cc * cc * len);
        lin += cc * len;
        a = -r;
    }
    bool two_lanes = !small && i1 - i0 > AA_CLOSED_ONE_LANE_MAX;
    if (!two_lanes) {
        /* few samples inside: one pass over the samples (the two-lane setup would cost more).
         * The two sums run side by side in the lanes of one vector, acc in lane 0, gam in lane 1
         * (gam is still zero here): each lane does add_term's operations on its own term. */
        compensated2 both = {{acc.sum, 0}, {acc.comp, 0}, {acc.sq, 0}};
        for (size_t k = i0; k < i1; k++) {
            double p = pp[k], u = (c - 0.5) + lo, len = p - a;
            lin += u * len;
            double big;
            if (want_prefix) {
                double gamma;
                big = closed_gamma(f, p, &gamma);
                ws->cdf[k] = 0.5 + gamma; /* g(p), as cdf_at computes it */
                prefix[k] = lin - big;
            } else {
                big = closed_gamma_value(f, p);
            }
            /* (u * u) * len and (2 * w) * big, as add_term's callers compute them */
            add_term2(&both, (v2d){u, 2} * (v2d){u, pw[k]} * (v2d){len, big});
            add_weight(&c, &lo, pw[k]);
            a = p;
        }
        acc = (compensated){both.sum[0], both.comp[0], both.sq[0]};
        gam = (compensated){both.sum[1], both.comp[1], both.sq[1]};
    } else {
        /* First the serial part: the prefix sums (u_k = c_k - 1/2 before sample k) and the
         * lengths, then per table piece the independent per-sample work in two lanes. The piece
         * of a sample is closed_piece's, floor((p + r) / width) clamped (piece_ends). */
        double *uu = ws->u, *ll = ws->len;
        for (size_t k = i0; k < i1; k++) {
            double p = pp[k], u = (c - 0.5) + lo, len = p - a;
            uu[k] = u;
            ll[k] = len;
            if (want_prefix) {
                lin += u * len;
                prefix[k] = lin;
            }
            add_weight(&c, &lo, pw[k]);
            a = p;
        }
        size_t ends[AA_FILTER_CLOSED_MAX_PIECES], k = i0;
        piece_ends(pp, i0, i1, r, f->closed_inv_width, f->closed_pieces, ends);
        for (int j = 0; j < f->closed_pieces; j++) {
            closed_piece_run(f->closed_gamma[j], f->closed_mid[j], k, ends[j], ws, &accv, &gamv,
                             want_prefix);
            k = ends[j];
        }
    }
    double u = (c - 0.5) + lo, len = r - a;
    add_term(&acc, u * u * len);
    lin += u * len;
    a = r;
    for (size_t m = i1; m < n; m++) {
        double d = (c - 1) + lo, l = pp[m] - a;
        add_term(&acc, d * d * l);
        lin += d * l;
        if (want_prefix) {
            prefix[m] = lin;
            ws->cdf[m] = 1;
        }
        add_weight(&c, &lo, pw[m]);
        a = pp[m];
    }
    if (want_prefix)
        ws->cdf_valid = true;
    /* Beyond the last sample the integrand is (c - 1)^2 = 0 when the weights sum to 1. */
    double spread2 = acc.sq + gam.sq;
    fold_sum(&acc, gam.sum);
    acc.comp += gam.comp;
    if (two_lanes) {
        spread2 += (accv.sq[0] + accv.sq[1]) + (gamv.sq[0] + gamv.sq[1]);
        fold_sum(&acc, accv.sum[0]);
        fold_sum(&acc, accv.sum[1]);
        fold_sum(&acc, gamv.sum[0]);
        fold_sum(&acc, gamv.sum[1]);
        acc.comp += (accv.comp[0] + accv.comp[1]) + (gamv.comp[0] + gamv.comp[1]);
    }
    return (closed_sums){acc.sum + acc.comp, sqrt(spread2)};
}

static closed_sums closed_form_e1(const aa_filter *f, size_t n, aa_metric_workspace *ws)
{
    return closed_form_impl(f, ws->p, ws->w, n, ws, false, false);
}

static closed_sums closed_form_prefix(const aa_filter *f, size_t n, aa_metric_workspace *ws)
{
    return closed_form_impl(f, ws->p, ws->w, n, ws, true, false);
}

/* Whether the closed form's error estimate is within AA_E1_CLOSED_REL_ERROR (metric.h). */
static bool closed_acceptable(const closed_sums *cs)
{
    return cs->spread * AA_E1_CLOSED_SAFETY * 0x1.0p-52 <= AA_E1_CLOSED_REL_ERROR * cs->e1sq;
}

/* E1^2 by the method over ws's sorted arrays. With want_prefix (gradients), ws->tail[k] holds
 * the prefix integral P_k of the k-th sorted sample afterwards, and where the closed form ran,
 * ws->cdf[k] = g(p_k) (cdf_valid), a by-product of its Gamma evaluation. */
static double e1_squared_sorted(const aa_filter *f, size_t n, aa_e1_method method,
                                aa_metric_workspace *ws, bool want_prefix)
{
    ws->cdf_valid = false;
    if (method != AA_E1_QUADRATURE && f->closed_pieces > 0) {
        closed_sums cs = want_prefix ? closed_form_prefix(f, n, ws) : closed_form_e1(f, n, ws);
        ws->closed_condition = cs.spread / cs.e1sq;
        if (method == AA_E1_CLOSED || closed_acceptable(&cs)) {
            ws->closed_calls++;
            return cs.e1sq > 0 ? cs.e1sq : 0;
        }
        ws->fallback_calls++;
    }
    return sweep(f, n, ws, want_prefix);
}

static double e1_squared(const aa_filter *f, const aa_sample *s, size_t n, double ct, double st,
                         aa_e1_method method, aa_metric_workspace *ws, bool want_prefix)
{
    project_sorted(s, n, ct, st, ws);
    return e1_squared_sorted(f, n, method, ws, want_prefix);
}

/* Kernels of at most this many samples take e1_small on single calls (issue 33, point 7). */
#define AA_E1_SMALL_MAX 16

/* The n projections q (weights qw) into p, w in (p, index) order, the order of the general path's
 * sorts (ties keep input order), without a branch on the data: entry i goes to the number of
 * entries before it in that order, counted over all pairs (each pair adds one to exactly one of
 * its two counts). With n a constant at the call site the loops unroll into straight-line
 * comparisons (a counting network). The projections must not be NaN (no order: ranks collide). */
static inline __attribute__((always_inline)) void rank_sort(const double *q, const double *qw,
                                                            size_t n, double *p, double *w)
{
    unsigned place[AA_E1_SMALL_MAX] = {0};
    for (size_t i = 0; i < n; i++)
        for (size_t j = i + 1; j < n; j++) {
            unsigned after = q[j] < q[i]; /* j sorts before i */
            place[i] += after;
            place[j] += after ^ 1;
        }
    for (size_t i = 0; i < n; i++) {
        p[place[i]] = q[i];
        w[place[i]] = qw[i];
    }
}

/* The stable insertion sort: beyond 8 samples (where the n(n-1)/2 comparisons of rank_sort cost
 * more than its saved mispredicts: bench_metric at 16 samples), and for projections that include
 * NaN: the general path's first sort (an insertion sort at these sizes, order.c) leaves a NaN
 * where this one does. Without NaN it gives rank_sort's order. */
static void insertion_sort(const double *q, const double *qw, size_t n, double *p, double *w)
{
    for (size_t i = 0; i < n; i++) {
        size_t k = i;
        for (; k > 0 && p[k - 1] > q[i]; k--) {
            p[k] = p[k - 1];
            w[k] = w[k - 1];
        }
        p[k] = q[i];
        w[k] = qw[i];
    }
}

/* E1^2 of a small kernel by the closed form (filters with tables, method not QUADRATURE), with the
 * workspace's projection machinery (index arrays, the order kept between calls, the gathers)
 * replaced by a branch-free sort on the stack. Bit for bit the general path's value: the same
 * products, the same (p, index) order, the same closed_form_impl arithmetic. Only a badly
 * conditioned closed form (rare) copies into ws for the sweep. */
static int e1_small(const aa_filter *f, const aa_sample *s, size_t n, double ct, double st,
                    aa_e1_method method, aa_metric_workspace *ws, double *e1sq)
{
    assert(n >= 1 && n <= AA_E1_SMALL_MAX && f->closed_pieces > 0);
    double q[AA_E1_SMALL_MAX], qw[AA_E1_SMALL_MAX], p[AA_E1_SMALL_MAX], w[AA_E1_SMALL_MAX];
    double any_nan = 0; /* NaN when a projection is (or two infinities of opposite signs) */
    for (size_t i = 0; i < n; i++) {
        q[i] = s[i].x * ct + s[i].y * st;
        qw[i] = s[i].w;
        any_nan += q[i];
    }
    if (isnan(any_nan))
        insertion_sort(q, qw, n, p, w);
    else if (n == 4)
        rank_sort(q, qw, 4, p, w);
    else if (n == 8)
        rank_sort(q, qw, 8, p, w);
    else if (n < 8)
        rank_sort(q, qw, n, p, w);
    else
        insertion_sort(q, qw, n, p, w);
    ws->order_of = NULL; /* ws's arrays no longer hold this kernel's order */
    ws->cdf_valid = false;
    closed_sums cs = closed_form_impl(f, p, w, n, ws, false, true);
    ws->closed_condition = cs.spread / cs.e1sq;
    if (method == AA_E1_CLOSED || closed_acceptable(&cs)) {
        ws->closed_calls++;
        *e1sq = cs.e1sq > 0 ? cs.e1sq : 0;
        return AA_OK;
    }
    ws->fallback_calls++;
    if (reserve(ws, n))
        return AA_ENOMEM;
    memcpy(ws->p, p, n * sizeof *p);
    memcpy(ws->w, w, n * sizeof *w);
    *e1sq = sweep(f, n, ws, false);
    return AA_OK;
}

int aa_e1_at_direction(const aa_filter *f, const aa_sample *s, size_t n, double ct, double st,
                       aa_e1_method method, aa_metric_workspace *ws, double *e1)
{
    if (n == 0 || !isfinite(ct) || !isfinite(st))
        return AA_EINVAL;
    if (n <= AA_E1_SMALL_MAX && method != AA_E1_QUADRATURE && f->closed_pieces > 0) {
        double e1sq;
        int rc = e1_small(f, s, n, ct, st, method, ws, &e1sq);
        if (rc == AA_OK)
            *e1 = sqrt(e1sq);
        return rc;
    }
    return aa_e1_sorted_at_direction(f, s, n, ct, st, method, ws, e1);
}

int aa_e1_sorted_at_direction(const aa_filter *f, const aa_sample *s, size_t n, double ct,
                              double st, aa_e1_method method, aa_metric_workspace *ws, double *e1)
{
    if (n == 0 || !isfinite(ct) || !isfinite(st))
        return AA_EINVAL;
    if (reserve(ws, n))
        return AA_ENOMEM;
    *e1 = sqrt(e1_squared(f, s, n, ct, st, method, ws, false));
    return AA_OK;
}

int aa_e1_at_angle(const aa_filter *f, const aa_sample *s, size_t n, double theta,
                   aa_metric_workspace *ws, double *e1)
{
    if (!isfinite(theta))
        return AA_EINVAL;
    double ct, st;
    aa_metric_direction(theta, &ct, &st);
    return aa_e1_at_direction(f, s, n, ct, st, AA_E1_AUTO, ws, e1);
}

/* g(p) for the position gradient: the closed-form tables where the filter has them. */
static double cdf_at(const aa_filter *f, double p)
{
    if (f->closed_pieces == 0)
        return aa_filter_cdf(f, p);
    if (p <= -f->radius)
        return 0;
    if (p >= f->radius)
        return 1;
    double gamma;
    closed_gamma(f, p, &gamma);
    return 0.5 + gamma;
}

/* The gradient at one direction from ws's sorted arrays and tail (E1 = e): written to dx, dy, dw
 * (each may be NULL), or added times factor when accumulate. */
static void gradient_sorted(const aa_filter *f, size_t n, double ct, double st, double e,
                            double factor, bool accumulate, const aa_metric_workspace *ws,
                            double *dx, double *dy, double *dw)
{
    double inv = e > 0 ? 1.0 / e : 0;
    const double *pp = ws->p, *pw = ws->w;
    const uint32_t *ix = ws->index;
    if (accumulate && dx && dy && ws->cdf_valid) {
        /* the block's common case, the same arithmetic without the per-entry tests */
        const double *cdf = ws->cdf;
        double sorted_before = 0;
        for (size_t k = 0; k < n; k++) {
            double w = pw[k], dp = w * (2 * cdf[k] - 2 * sorted_before - w) * 0.5 * inv;
            uint32_t i = ix[k];
            dx[i] = dx[i] + factor * (dp * ct);
            dy[i] = dy[i] + factor * (dp * st);
            sorted_before += w;
        }
    } else if (dx || dy) {
        double sorted_before = 0; /* S_i: weight sorted before i */
        for (size_t k = 0; k < n; k++) {
            double w = pw[k];
            double g = ws->cdf_valid ? ws->cdf[k] : cdf_at(f, pp[k]);
            double dp = w * (2 * g - 2 * sorted_before - w) * 0.5 * inv;
            if (dx)
                dx[ix[k]] = accumulate ? dx[ix[k]] + factor * (dp * ct) : dp * ct;
            if (dy)
                dy[ix[k]] = accumulate ? dy[ix[k]] + factor * (dp * st) : dp * st;
            sorted_before += w;
        }
    }
    if (dw) {
        /* raw_i = (1/E1) integral_{p_i}^{inf} (ghat - g) = const - P_i / E1 (docs/metric.md 4):
         * projected onto sum(w) = 1 the constant drops out. */
        double mean = 0;
        for (size_t k = 0; k < n; k++)
            mean += ws->tail[k];
        mean /= (double)n;
        if (accumulate) {
            for (size_t k = 0; k < n; k++)
                dw[ix[k]] += factor * ((mean - ws->tail[k]) * inv);
        } else {
            for (size_t k = 0; k < n; k++)
                dw[ix[k]] = (mean - ws->tail[k]) * inv;
        }
    }
}

int aa_e1_gradient_at_direction(const aa_filter *f, const aa_sample *s, size_t n, double ct,
                                double st, aa_e1_method method, aa_metric_workspace *ws, double *e1,
                                double *dx, double *dy, double *dw)
{
    if (n == 0 || !isfinite(ct) || !isfinite(st))
        return AA_EINVAL;
    if (reserve(ws, n))
        return AA_ENOMEM;
    double e = sqrt(e1_squared(f, s, n, ct, st, method, ws, dx || dy || dw));
    *e1 = e;
    gradient_sorted(f, n, ct, st, e, 1, false, ws, dx, dy, dw);
    return AA_OK;
}

/* The kernel x angle block: one copy of the samples into the arrays, then per direction a
 * vectorised projection, a re-sort (order.h), the E1 sums and (when factor[a] != 0 and wanted)
 * the gradient accumulated. */
static int kernel_block(const aa_filter *f, const aa_sample *s, size_t n, const double *dir_c,
                        const double *dir_s, size_t na, const double *factor, aa_e1_method method,
                        aa_metric_workspace *ws, double *e1, double *gx, double *gy, double *gw)
{
    if (n == 0)
        return AA_EINVAL;
    for (size_t a = 0; a < na; a++)
        if (!isfinite(dir_c[a]) || !isfinite(dir_s[a]))
            return AA_EINVAL;
    if (reserve(ws, n))
        return AA_ENOMEM;
    bool want_grad = factor && (gx || gy || gw);
    for (size_t i = 0; i < n; i++) {
        ws->in_x[i] = s[i].x;
        ws->in_y[i] = s[i].y;
        ws->in_w[i] = s[i].w;
    }
    for (size_t a = 0; a < na; a++) {
        double ct = dir_c[a], st = dir_s[a];
        project_block(n, ct, st, a == 0, ws);
        bool grad = want_grad && factor[a] != 0;
        double e = sqrt(e1_squared_sorted(f, n, method, ws, grad));
        e1[a] = e;
        if (grad && e > 0)
            gradient_sorted(f, n, ct, st, e, factor[a], true, ws, gx, gy, gw);
    }
    /* the arrays hold s's order now: a following single call may start from it */
    ws->order_of = s;
    ws->order_n = n;
    return AA_OK;
}

int aa_e1_kernel_block(const aa_filter *f, const aa_sample *s, size_t n, const double *dir_c,
                       const double *dir_s, size_t na, aa_e1_method method, aa_metric_workspace *ws,
                       double *e1)
{
    return kernel_block(f, s, n, dir_c, dir_s, na, NULL, method, ws, e1, NULL, NULL, NULL);
}

int aa_e1_gradient_kernel_block(const aa_filter *f, const aa_sample *s, size_t n,
                                const double *dir_c, const double *dir_s, size_t na,
                                const double *factor, aa_e1_method method, aa_metric_workspace *ws,
                                double *e1, double *gx, double *gy, double *gw)
{
    return kernel_block(f, s, n, dir_c, dir_s, na, factor, method, ws, e1, gx, gy, gw);
}

int aa_e1_gradient_at_angle(const aa_filter *f, const aa_sample *s, size_t n, double theta,
                            aa_metric_workspace *ws, double *e1, double *dx, double *dy, double *dw)
{
    if (!isfinite(theta))
        return AA_EINVAL;
    double ct, st;
    aa_metric_direction(theta, &ct, &st);
    return aa_e1_gradient_at_direction(f, s, n, ct, st, AA_E1_AUTO, ws, e1, dx, dy, dw);
}
