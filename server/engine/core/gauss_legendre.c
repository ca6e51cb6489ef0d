#include "gauss_legendre.h"

#include <assert.h>
#include <math.h>

void aa_gauss_legendre(int m, double *node, double *weight)
{
    assert(m >= 1 && node && weight);
    const long double pi = 3.141592653589793238462643383279502884L;
    for (int i = 0; i < m; i++) {
        /* Tricomi's initial guess, then Newton on P_m. */
        long double x = cosl(pi * (i + 0.75L) / (m + 0.5L));
        long double dp = 1;
        for (int it = 0; it < 100; it++) {
            long double p0 = 1, p1 = x;
            for (int k = 2; k <= m; k++) {
                long double pk = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = pk;
            }
            long double pm = m == 1 ? x : p1, pm1 = m == 1 ? 1 : p0;
            dp = m * (x * pm - pm1) / (x * x - 1);
            long double dx = pm / dp;
            x -= dx;
            if (fabsl(dx) < 1e-19L)
                break;
        }
        /* Nodes come out descending; store ascending. */
        node[m - 1 - i] = (double)x;
        weight[m - 1 - i] = (double)(2 / ((1 - x * x) * dp * dp));
    }
}
