#include "simplex_qp.h"

#include <math.h>
#include <string.h>

int aa_simplex_qp_solve(size_t m, const double *Q, const double *f, double delta, double *lambda,
                        double *q, double tol, long max_iterations, aa_simplex_qp_result *result)
{
    if (m == 0 || !(delta > 0))
        return -1;
    double sum = 0;
    for (size_t i = 0; i < m; i++)
        sum += lambda[i];
    if (!(fabs(sum - 1) < 1e-9)) {
        size_t top = 0;
        for (size_t i = 1; i < m; i++)
            if (f[i] > f[top])
                top = i;
        memset(lambda, 0, m * sizeof *lambda);
        lambda[top] = 1;
    }
    for (size_t i = 0; i < m; i++) {
        double s = 0;
        for (size_t j = 0; j < m; j++)
            if (lambda[j] != 0)
                s += Q[i * m + j] * lambda[j];
        q[i] = s;
    }
    long it = 0;
    double gap = INFINITY;
    for (; it < max_iterations; it++) {
        /* grad_i = f_i - delta q_i; FW vertex s = argmax grad, away vertex v = argmin over the
         * support. */
        size_t s = 0, v = m;
        double gs = -INFINITY, gv = INFINITY, dot = 0;
        for (size_t i = 0; i < m; i++) {
            double g = f[i] - delta * q[i];
            if (g > gs) {
                gs = g;
                s = i;
            }
            if (lambda[i] > 0) {
                dot += lambda[i] * g;
                if (g < gv) {
                    gv = g;
                    v = i;
                }
            }
        }
        gap = gs - dot;
        if (gap <= tol || v == m || s == v)
            break;
        double curvature = delta * (Q[s * m + s] - 2 * Q[s * m + v] + Q[v * m + v]);
        double step = lambda[v];
        if (curvature > 0 && (gs - gv) / curvature < step)
            step = (gs - gv) / curvature;
        if (!(step > 0))
            break;
        lambda[s] += step;
        lambda[v] -= step;
        if (lambda[v] < 1e-300)
            lambda[v] = 0;
        for (size_t i = 0; i < m; i++)
            q[i] +=
                step * (Q[s * m + i] - Q[v * m + i]); /* Q is symmetric: rows read contiguously */
    }
    if (result) {
        double obj = 0;
        for (size_t i = 0; i < m; i++)
            obj += lambda[i] * (f[i] - 0.5 * delta * q[i]);
        result->objective = obj;
        result->gap = gap;
        result->iterations = it;
    }
    return 0;
}
