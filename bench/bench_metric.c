/* E1/E2 benchmark: ns per kernel-angle of the exact evaluation (the closed form with its
 * quadrature fallback, aa_e1_at_direction AUTO) for 4, 16 and 64 samples, beside the previous
 * method as the engine ran it (cos/sin per call, sort from the input order, piecewise
 * Gauss-Legendre) and an in-run baseline that evaluates the same integral by a straightforward
 * dense quadrature: the midpoint rule with N uniform points over the span [min(p, -r), max(p, r)],
 * ghat by a pointer walk over the sorted projections, g by aa_filter_cdf. N is chosen per sample
 * count so that the baseline's median relative error (measured here against the exact value) is
 * about 1e-6; the achieved error is printed. Then whole-pattern E2 (aa_evaluate on the default 36
 * angles) for Quincunx and a P(16,16,4) pattern (4x4 tile, 4 jittered samples per pixel, 4x4
 * kernels, weights from the filter), each beside the dense-quadrature estimate for the same
 * kernel-angles, and beside the per-call path (aa_e1_at_direction per kernel-angle, as aa_evaluate
 * ran before the kernel x angle block), and the blocks alone with the re-sort aa_evaluate chose
 * (the rank pass where the CPU has AVX2 or AVX-512, order.h) beside the insertion pass only. Then
 * the whole-pattern gradient of the mean weighted E1 (every kernel-angle, factor W(theta) /
 * (kernels x angles)): the block (aa_e1_gradient_kernel_block) beside the block with the
 * insertion pass only, the per-call gradient and the previous method. Times are
 * thread CPU time (other processes share the machine); the load average is printed with them.
 * Figures vary with the machine; the ratios are the point. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime(CLOCK_THREAD_CPUTIME_ID) */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "aa_metric.h"
#include "aa_pattern.h"

#define PI_D 3.14159265358979323846
#define KERNELS 64
#define ANGLES 36

static uint64_t rng_state = 12345;

static double rng_uniform(double lo, double hi)
{
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return lo + (hi - lo) * ((double)(z >> 11) * 0x1.0p-53);
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The 1-minute load average (Linux), printed beside the timings; NaN where unknown. */
static double load_average(void)
{
    double l = NAN;
    FILE *fp = fopen("/proc/loadavg", "r");
    if (fp) {
        if (fscanf(fp, "%lf", &l) != 1)
            l = NAN;
        fclose(fp);
    }
    return l;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

typedef struct proj {
    double p, w;
} proj;

static int cmp_proj(const void *a, const void *b)
{
    return cmp_double(&((const proj *)a)->p, &((const proj *)b)->p);
}

/* The straightforward evaluation: midpoint rule on n_points uniform cells. */
static double e1_dense_midpoint(const aa_filter *f, const aa_sample *s, size_t n, double theta,
                                long n_points)
{
    proj *pr = malloc(n * sizeof *pr);
    double c = cos(theta), sn = sin(theta);
    for (size_t i = 0; i < n; i++)
        pr[i] = (proj){s[i].x * c + s[i].y * sn, s[i].w};
    qsort(pr, n, sizeof *pr, cmp_proj);
    double lo = fmin(pr[0].p, -f->radius), hi = fmax(pr[n - 1].p, f->radius);
    double h = (hi - lo) / (double)n_points, acc = 0.0, ghat = 0.0;
    size_t j = 0;
    for (long k = 0; k < n_points; k++) {
        double a = lo + (k + 0.5) * h;
        while (j < n && pr[j].p <= a)
            ghat += pr[j++].w;
        double d = ghat - aa_filter_cdf(f, a);
        acc += d * d;
    }
    free(pr);
    return sqrt(acc * h);
}

static void random_kernel(aa_sample *s, size_t n)
{
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) {
        s[i] = (aa_sample){rng_uniform(-1.0, 1.0), rng_uniform(-1.0, 1.0), rng_uniform(0.1, 1.0)};
        sum += s[i].w;
    }
    for (size_t i = 0; i < n; i++)
        s[i].w /= sum;
}

/* The plain closed form, written for this benchmark as a reader of docs/metric.md 2b would:
 * cos/sin of theta, the projections on the stack, an insertion sort, then one uncompensated
 * pass of E1^2 = V + sum (c - 1/2)^2 len + 2 sum w Gamma(p) inside (-r, r), c^2 len left of it
 * and (c - 1)^2 len right of it, Gamma by Horner from the filter's tables. No workspace, no
 * error estimate, no fallback: the floor a single-angle call of the library is compared with
 * (issue 33, point 7). n <= 64. */
static double gamma_plain(const aa_filter *f, double p)
{
    int j = (int)((p + f->radius) * f->closed_inv_width);
    j = j < 0 ? 0 : (j >= f->closed_pieces ? f->closed_pieces - 1 : j);
    double x = p - f->closed_mid[j], v = 0;
    for (int k = AA_FILTER_CLOSED_DEGREE; k >= 0; k--)
        v = v * x + f->closed_gamma[j][k];
    return v;
}

static double e1_plain(const aa_filter *f, const aa_sample *s, size_t n, double theta)
{
    double p[64], w[64], ct = cos(theta), st = sin(theta);
    for (size_t i = 0; i < n; i++) {
        double q = s[i].x * ct + s[i].y * st, qw = s[i].w;
        size_t k = i;
        for (; k > 0 && p[k - 1] > q; k--) {
            p[k] = p[k - 1];
            w[k] = w[k - 1];
        }
        p[k] = q;
        w[k] = qw;
    }
    double r = f->radius, e = f->closed_var, c = 0, a = -r;
    size_t k = 0;
    if (n > 0 && p[0] <= -r) {
        a = p[0];
        for (; k < n && p[k] <= -r; k++) {
            e += c * c * (p[k] - a);
            c += w[k];
            a = p[k];
        }
        e += c * c * (-r - a);
        a = -r;
    }
    for (; k < n && p[k] < r; k++) {
        double u = c - 0.5;
        e += u * u * (p[k] - a) + 2 * w[k] * gamma_plain(f, p[k]);
        c += w[k];
        a = p[k];
    }
    e += (c - 0.5) * (c - 0.5) * (r - a);
    a = r;
    for (; k < n; k++) {
        e += (c - 1) * (c - 1) * (p[k] - a);
        c += w[k];
        a = p[k];
    }
    return sqrt(e > 0 ? e : 0);
}

/* ns per call of aa_e1_at_angle (the public single-angle entry: each call a new angle, as a
 * caller evaluating one kernel-angle at a time makes it) beside e1_plain on the same calls, and
 * the largest relative difference between the two. The two alternate in rounds of 8192 calls
 * (1-5 ms each), so that both see the same load from other processes; the ratio is the median of
 * the rounds' ratios, the times the medians of their rounds. Every call of a round has its own
 * kernel and angle: with a few hundred repeated ones the branch predictor learns the insertion
 * sorts' branches (measured: the plain form at 4 samples took 50-85 ns with 256 kernels, 109-116
 * ns with 8192), which a caller meeting new kernels does not get. */
static void bench_single_calls(const aa_filter *f, size_t n)
{
    enum { CALL_KERNELS = 8192, ROUNDS = 61 };
    uint64_t saved_state = rng_state; /* the later sections draw the same patterns as before */
    aa_sample *ks = malloc(CALL_KERNELS * n * sizeof *ks);
    static double theta[CALL_KERNELS];
    for (size_t k = 0; k < CALL_KERNELS; k++) {
        random_kernel(ks + k * n, n);
        theta[k] = rng_uniform(0.0, PI_D);
    }
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    volatile double sink = 0.0;
    static double round_ns[2][ROUNDS], ratio[ROUNDS];
    double diff = 0.0;
    for (int r = 0; r < ROUNDS; r++) {
        for (int variant = 0; variant < 2; variant++) {
            double t0 = now_s();
            for (size_t k = 0; k < CALL_KERNELS; k++) {
                double e = 0.0;
                if (variant == 0)
                    aa_e1_at_angle(f, ks + k * n, n, theta[k], &ws, &e);
                else
                    e = e1_plain(f, ks + k * n, n, theta[k]);
                sink += e;
            }
            round_ns[variant][r] = 1e9 * (now_s() - t0) / CALL_KERNELS;
        }
        ratio[r] = round_ns[0][r] / round_ns[1][r];
    }
    qsort(round_ns[0], ROUNDS, sizeof(double), cmp_double);
    qsort(round_ns[1], ROUNDS, sizeof(double), cmp_double);
    qsort(ratio, ROUNDS, sizeof(double), cmp_double);
    for (size_t k = 0; k < CALL_KERNELS; k++) {
        double e = 0.0;
        aa_e1_at_angle(f, ks + k * n, n, theta[k], &ws, &e);
        diff = fmax(diff, fabs(e - e1_plain(f, ks + k * n, n, theta[k])) / e);
    }
    printf("single calls, %2zu samples: aa_e1_at_angle %6.1f ns | plain closed form %6.1f ns | "
           "ratio %.2fx (quartiles %.2f-%.2f; target <= 1.2x at 4 and 8) | max rel. difference "
           "%.1e\n",
           n, round_ns[0][ROUNDS / 2], round_ns[1][ROUNDS / 2], ratio[ROUNDS / 2],
           ratio[ROUNDS / 4], ratio[3 * ROUNDS / 4], diff);
    aa_metric_workspace_free(&ws);
    free(ks);
    rng_state = saved_state;
    (void)sink;
}

typedef struct size_result {
    size_t n;
    double exact_ns, old_ns, dense_ns;
} size_result;

/* One call as the engine made it before issue 15: cos/sin per call, the sort from the input
 * order, the piecewise Gauss-Legendre sweep. */
static void e1_old(const aa_filter *f, const aa_sample *s, size_t n, double theta,
                   aa_metric_workspace *ws, double *e)
{
    double c, sn;
    aa_metric_direction(theta, &c, &sn);
    ws->order_of = NULL;
    aa_e1_at_direction(f, s, n, c, sn, AA_E1_QUADRATURE, ws, e);
}

/* ns per kernel-angle over every kernel at every angle (kernel-major, as aa_evaluate does). */
static double time_calls(const aa_filter *f, const aa_sample *ks, size_t n, bool old,
                         aa_metric_workspace *ws, const double *dc, const double *ds)
{
    volatile double sink = 0.0;
    long calls = 0;
    double t0 = now_s(), t1;
    do {
        for (size_t k = 0; k < KERNELS; k++)
            for (int a = 0; a < ANGLES; a++) {
                double e = 0.0;
                if (old)
                    e1_old(f, ks + k * n, n, a * (PI_D / ANGLES), ws, &e);
                else
                    aa_e1_at_direction(f, ks + k * n, n, dc[a], ds[a], AA_E1_AUTO, ws, &e);
                sink += e;
                calls++;
            }
        t1 = now_s();
    } while (t1 - t0 < 0.3);
    (void)sink;
    return 1e9 * (t1 - t0) / (double)calls;
}

static size_result bench_size(const aa_filter *f, size_t n, long n_points)
{
    aa_sample *ks = malloc(KERNELS * n * sizeof *ks);
    for (size_t k = 0; k < KERNELS; k++)
        random_kernel(ks + k * n, n);
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    double dc[ANGLES], ds[ANGLES];
    for (int a = 0; a < ANGLES; a++)
        aa_metric_direction(a * (PI_D / ANGLES), &dc[a], &ds[a]);
    double exact_ns = time_calls(f, ks, n, false, &ws, dc, ds);
    double share = (double)ws.closed_calls / (double)(ws.closed_calls + ws.fallback_calls);
    double old_ns = time_calls(f, ks, n, true, &ws, dc, ds);
    volatile double sink = 0.0;

    /* baseline on a few kernel-angles (it is slow), with its error against the exact value;
     * also the largest difference between the closed form and the old method */
    enum { SAMPLES = 5 };
    double errs[SAMPLES], dense_time = 0.0, diff = 0.0;
    for (int i = 0; i < SAMPLES; i++) {
        const aa_sample *s = ks + (size_t)i * n;
        double theta = (7 * i + 3) * (PI_D / ANGLES), exact = 0.0, old = 0.0;
        aa_e1_at_angle(f, s, n, theta, &ws, &exact);
        e1_old(f, s, n, theta, &ws, &old);
        diff = fmax(diff, fabs(exact - old) / old);
        double d0 = now_s();
        double dense = e1_dense_midpoint(f, s, n, theta, n_points);
        dense_time += now_s() - d0;
        errs[i] = fabs(dense - exact) / exact;
        sink += dense;
    }
    qsort(errs, SAMPLES, sizeof errs[0], cmp_double);
    double dense_ns = 1e9 * dense_time / SAMPLES;
    printf("E1 per kernel-angle, %2zu samples: closed form %7.1f ns (closed form taken %5.1f%%, "
           "else quadrature) | previous method %7.1f ns (%.2fx) | dense midpoint (N = 2^%d) "
           "%10.0f ns, median rel. error %.1e (max %.1e) (%.0fx) | closed vs previous: max rel. "
           "difference %.1e\n",
           n, exact_ns, 100 * share, old_ns, old_ns / exact_ns, (int)lround(log2((double)n_points)),
           dense_ns, errs[SAMPLES / 2], errs[SAMPLES - 1], dense_ns / exact_ns, diff);
    aa_metric_workspace_free(&ws);
    free(ks);
    (void)sink;
    return (size_result){n, exact_ns, old_ns, dense_ns};
}

/* Whole-pattern E2 the way aa_evaluate computed it before (per-call cos/sin, sort from the
 * input order, quadrature). */
static double e2_old(const aa_pattern *p, const aa_acuity *acuity, const aa_filter *f,
                     aa_metric_workspace *ws)
{
    double angles[AA_MAX_ANGLES], e2 = 0.0;
    size_t na = aa_acuity_default_angles(acuity, angles, AA_MAX_ANGLES);
    for (size_t k = 0; k < p->kernel_count; k++)
        for (size_t a = 0; a < na; a++) {
            double e1 = 0.0;
            e1_old(f, p->kernels[k].samples, p->kernels[k].count, angles[a] * (PI_D / 180), ws,
                   &e1);
            e2 = fmax(e2, aa_acuity_weight(acuity, angles[a]) * e1);
        }
    return e2;
}

/* Whole-pattern E2 by single calls (aa_e1_at_direction per kernel-angle, kernel-major, sort
 * reused between neighbouring angles): aa_evaluate before the kernel x angle block. */
static double e2_per_call(const aa_pattern *p, const aa_filter *f, const double *dc,
                          const double *ds, const double *weight, size_t na,
                          aa_metric_workspace *ws)
{
    double e2 = 0.0;
    for (size_t k = 0; k < p->kernel_count; k++)
        for (size_t a = 0; a < na; a++) {
            double e1 = 0.0;
            aa_e1_at_direction(f, p->kernels[k].samples, p->kernels[k].count, dc[a], ds[a],
                               AA_E1_AUTO, ws, &e1);
            e2 = fmax(e2, weight[a] * e1);
        }
    return e2;
}

/* Whole-pattern E2 by kernel x angle blocks (aa_evaluate's loop) with ws's order_pass. */
static double e2_blocks(const aa_pattern *p, const aa_filter *f, const double *dc, const double *ds,
                        const double *weight, size_t na, aa_metric_workspace *ws)
{
    double e2 = 0.0, e1[AA_MAX_ANGLES];
    for (size_t k = 0; k < p->kernel_count; k++) {
        aa_e1_kernel_block(f, p->kernels[k].samples, p->kernels[k].count, dc, ds, na, AA_E1_AUTO,
                           ws, e1);
        for (size_t a = 0; a < na; a++)
            e2 = fmax(e2, weight[a] * e1[a]);
    }
    return e2;
}

static const char *order_pass_name(aa_order_pass pass)
{
    switch (pass) {
    case AA_ORDER_RANK_AVX512:
        return "rank pass (AVX-512)";
    case AA_ORDER_RANK_AVX2:
        return "rank pass (AVX2)";
    default:
        return "insertion pass";
    }
}

/* The gradient of the mean of W E1 over every kernel-angle, per kernel into g (3 x 64 doubles
 * per kernel: dx, dy, dw). how: 0 the block, 1 per-call AUTO, 2 the previous method (per call,
 * sort from the input order, quadrature), 3 the block with the insertion pass only (ws's
 * order_pass, set by the caller). */
static void gradient_whole(const aa_pattern *p, const aa_filter *f, const double *dc,
                           const double *ds, const double *factor, size_t na, int how,
                           aa_metric_workspace *ws, double *g)
{
    double e1[AA_MAX_ANGLES], gx[64], gy[64], gw[64];
    for (size_t k = 0; k < p->kernel_count; k++) {
        const aa_kernel *ker = &p->kernels[k];
        double *out = g + k * 192;
        memset(out, 0, 192 * sizeof *out);
        if (how == 0 || how == 3) {
            aa_e1_gradient_kernel_block(f, ker->samples, ker->count, dc, ds, na, factor, AA_E1_AUTO,
                                        ws, e1, out, out + 64, out + 128);
            continue;
        }
        for (size_t a = 0; a < na; a++) {
            double e = 0.0;
            if (how == 2)
                ws->order_of = NULL;
            aa_e1_gradient_at_direction(f, ker->samples, ker->count, dc[a], ds[a],
                                        how == 2 ? AA_E1_QUADRATURE : AA_E1_AUTO, ws, &e, gx, gy,
                                        gw);
            if (!(e > 0))
                continue;
            for (size_t i = 0; i < ker->count; i++) {
                out[i] += factor[a] * gx[i];
                out[64 + i] += factor[a] * gy[i];
                out[128 + i] += factor[a] * gw[i];
            }
        }
    }
}

/* CPU microseconds per whole-pattern gradient by how (gradient_whole), into g. */
static double time_gradient(const aa_pattern *p, const aa_filter *f, const double *dc,
                            const double *ds, const double *factor, size_t na, int how, double *g)
{
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    if (how == 3)
        ws.order_pass = AA_ORDER_INSERTION;
    long runs = 0;
    double t0 = now_s(), t1;
    do {
        gradient_whole(p, f, dc, ds, factor, na, how, &ws, g);
        runs++;
        t1 = now_s();
    } while (t1 - t0 < 0.3);
    aa_metric_workspace_free(&ws);
    return 1e6 * (t1 - t0) / (double)runs;
}

static void bench_gradient(const char *label, const aa_pattern *p, const aa_filter *f,
                           const aa_acuity *acuity)
{
    double angles[AA_MAX_ANGLES], dc[AA_MAX_ANGLES], ds[AA_MAX_ANGLES], factor[AA_MAX_ANGLES];
    size_t na = aa_acuity_default_angles(acuity, angles, AA_MAX_ANGLES);
    for (size_t a = 0; a < na; a++) {
        aa_metric_direction(angles[a] * (PI_D / 180), &dc[a], &ds[a]);
        factor[a] = aa_acuity_weight(acuity, angles[a]) / (double)(na * p->kernel_count);
    }
    for (size_t k = 0; k < p->kernel_count; k++)
        if (p->kernels[k].count > 64) {
            printf("whole-pattern gradient %s: kernels of more than 64 samples not benchmarked\n",
                   label);
            return;
        }
    size_t len = 192 * p->kernel_count;
    double *g[4];
    for (int h = 0; h < 4; h++)
        g[h] = calloc(len, sizeof(double));
    double us[4];
    for (int h = 0; h < 4; h++)
        us[h] = time_gradient(p, f, dc, ds, factor, na, h, g[h]);
    double diff[2] = {0, 0}, scale = 0;
    for (size_t i = 0; i < len; i++)
        scale = fmax(scale, fabs(g[2][i]));
    for (int h = 0; h < 2; h++)
        for (size_t i = 0; i < len; i++)
            diff[h] = fmax(diff[h], fabs(g[h][i] - g[2][i]) / scale);
    printf("whole-pattern gradient %-12s %s (mean W E1, %zu kernels x %zu angles; load %.2f): "
           "kernel x angle block %.1f us | block, insertion pass only %.1f us (%.2fx) | per-call "
           "%.1f us (%.2fx) | previous method %.1f us (%.2fx) | max difference from the previous "
           "method, relative to its largest component: block %.1e, per-call %.1e\n",
           label, p->family, p->kernel_count, na, load_average(), us[0], us[3], us[3] / us[0],
           us[1], us[1] / us[0], us[2], us[2] / us[0], diff[0], diff[1]);
    for (int h = 0; h < 4; h++)
        free(g[h]);
}

static void bench_pattern(const char *label, const aa_pattern *p, const aa_filter *f,
                          const aa_acuity *acuity, double dense_ns_per_kernel_angle)
{
    aa_metric_params mp = {.filter = f, .acuity = acuity};
    aa_evaluation ev;
    aa_error err;
    long runs = 0;
    double e2 = 0.0, t0 = now_s(), t1;
    do {
        if (aa_evaluate(p, &mp, &ev, &err) != AA_OK) {
            printf("%s: aa_evaluate failed: %s\n", label, err.message);
            return;
        }
        e2 = ev.e2;
        aa_evaluation_free(&ev);
        runs++;
        t1 = now_s();
    } while (t1 - t0 < 0.3);
    double us = 1e6 * (t1 - t0) / (double)runs;
    aa_metric_workspace ws;
    aa_metric_workspace_init(&ws);
    double e2o = 0.0;
    runs = 0;
    t0 = now_s();
    do {
        e2o = e2_old(p, acuity, f, &ws);
        runs++;
        t1 = now_s();
    } while (t1 - t0 < 0.3);
    double old_us = 1e6 * (t1 - t0) / (double)runs;
    double pc_angles[AA_MAX_ANGLES], dc[AA_MAX_ANGLES], ds[AA_MAX_ANGLES], wt[AA_MAX_ANGLES];
    size_t pna = aa_acuity_default_angles(acuity, pc_angles, AA_MAX_ANGLES);
    for (size_t a = 0; a < pna; a++) {
        aa_metric_direction(pc_angles[a] * (PI_D / 180), &dc[a], &ds[a]);
        wt[a] = aa_acuity_weight(acuity, pc_angles[a]);
    }
    double e2pc = 0.0;
    runs = 0;
    t0 = now_s();
    do {
        e2pc = e2_per_call(p, f, dc, ds, wt, pna, &ws);
        runs++;
        t1 = now_s();
    } while (t1 - t0 < 0.3);
    double pc_us = 1e6 * (t1 - t0) / (double)runs;
    /* aa_evaluate's blocks by hand, with the re-sort it chose (AUTO) and with the insertion
     * pass only (the re-sort before the rank pass), one after the other */
    double blk_us[2], e2blk[2];
    for (int q = 0; q < 2; q++) {
        aa_metric_workspace_free(&ws);
        aa_metric_workspace_init(&ws);
        ws.order_pass = q == 0 ? AA_ORDER_AUTO : AA_ORDER_INSERTION;
        runs = 0;
        t0 = now_s();
        do {
            e2blk[q] = e2_blocks(p, f, dc, ds, wt, pna, &ws);
            runs++;
            t1 = now_s();
        } while (t1 - t0 < 0.3);
        blk_us[q] = 1e6 * (t1 - t0) / (double)runs;
    }
    /* which re-sort the blocks ran (AUTO), and how often */
    aa_metric_workspace_free(&ws);
    aa_metric_workspace_init(&ws);
    e2_blocks(p, f, dc, ds, wt, pna, &ws);
    aa_order_pass used = ws.kernel_pass;
    double resorts = (double)(ws.rank_passes + ws.insertion_passes);
    double rank_share = resorts > 0 ? (double)ws.rank_passes / resorts : 0;
    /* the share of kernel-angles the closed form took */
    aa_metric_workspace_free(&ws);
    aa_metric_workspace_init(&ws);
    double angles[AA_MAX_ANGLES];
    size_t na = aa_acuity_default_angles(acuity, angles, AA_MAX_ANGLES);
    for (size_t k = 0; k < p->kernel_count; k++)
        for (size_t a = 0; a < na; a++) {
            double e1;
            aa_e1_at_angle(f, p->kernels[k].samples, p->kernels[k].count, angles[a] * (PI_D / 180),
                           &ws, &e1);
        }
    double share = (double)ws.closed_calls / (double)(ws.closed_calls + ws.fallback_calls);
    aa_metric_workspace_free(&ws);
    size_t ka = p->kernel_count * na;
    double dense_us = 1e-3 * dense_ns_per_kernel_angle * (double)ka;
    printf("whole-pattern E2 %-18s %s: E2 = %.6f (per-call %.6f, insertion only %.6f, previous "
           "%.6f), %zu kernels x %zu angles (load %.2f): %.1f us per evaluation (%.0f ns per "
           "kernel-angle, closed form taken %.0f%%) | per-call path %.1f us (%.2fx) | previous "
           "method %.1f us (%.2fx) | dense-quadrature estimate %.0f us (%.0fx) | the blocks alone: "
           "%.1f us with %s (%.0f%% of the angles after each kernel's first), %.1f us with the "
           "insertion pass only (%.2fx)\n",
           label, p->family, e2, e2pc, e2blk[1], e2o, p->kernel_count, na, load_average(), us,
           1e3 * us / (double)ka, 100 * share, pc_us, pc_us / us, old_us, old_us / us, dense_us,
           dense_us / us, blk_us[0],
           used == AA_ORDER_INSERTION ? "the insertion pass" : order_pass_name(used),
           100 * (used == AA_ORDER_INSERTION ? 1 - rank_share : rank_share), blk_us[1],
           blk_us[1] / blk_us[0]);
}

int main(void)
{
    aa_filter f;
    aa_acuity acuity;
    aa_filter_default(&f);
    aa_acuity_naiman(&acuity);
    printf("bench_metric: Mitchell-Netravali (1/3, 1/3), Naiman acuity; random kernels in "
           "[-1,1]^2, positive weights; thread CPU time; load average %.2f at the start\n",
           load_average());
    /* N per size: the midpoint rule's error comes from the jumps of ghat (O(h) each), so more
     * samples need more points for the same ~1e-6. */
    size_result r4 = bench_size(&f, 4, 1L << 21);
    size_result r16 = bench_size(&f, 16, 1L << 21);
    size_result r64 = bench_size(&f, 64, 1L << 20);
    (void)r16;
    for (size_t n = 4; n <= 64; n *= 2)
        bench_single_calls(&f, n);

    aa_pattern q;
    aa_error err;
    if (aa_pattern_from_preset(&q, aa_preset_find("quincunx"), &err) != AA_OK)
        return 1;
    bench_pattern("Quincunx", &q, &f, &acuity, r4.dense_ns);
    aa_pattern_free(&q);

    aa_point pts[64];
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 4; k++)
                pts[(j * 4 + i) * 4 + k] = (aa_point){i + 0.5 * (k % 2) + rng_uniform(0.0, 0.5),
                                                      j + 0.5 * (k / 2) + rng_uniform(0.0, 0.5)};
    aa_tile_spec spec = {
        .tile = 4, .kernel_size = 4, .count = 64, .samples = pts, .weight_filter = &f};
    aa_pattern p16;
    if (aa_pattern_from_tile(&p16, &spec, 0, &err) != AA_OK) {
        printf("P(16,16,4): %s (%s)\n", err.message, err.field);
        return 1;
    }
    bench_pattern("jittered 4x4 tile", &p16, &f, &acuity, r64.dense_ns);
    bench_gradient("jittered 4x4", &p16, &f, &acuity);
    aa_pattern_free(&p16);
    return 0;
}
