/* Reads "n" then n lines "x y" (nan allowed) and prints aa_spearman_of's "rho n p_value" with
 * 17 digits: the C side of spearman_scipy.py. */
#include <stdio.h>
#include <stdlib.h>

#include "aa_core.h"

int main(void)
{
    size_t n;
    if (scanf("%zu", &n) != 1)
        return 2;
    double *x = malloc((n ? n : 1) * sizeof *x), *y = malloc((n ? n : 1) * sizeof *y);
    if (!x || !y)
        return 2;
    for (size_t i = 0; i < n; i++)
        if (scanf("%lf %lf", &x[i], &y[i]) != 2)
            return 2;
    aa_spearman_result s;
    if (aa_spearman_of(x, y, n, &s))
        return 1;
    printf("%.17g %zu %.17g\n", s.rho, s.n, s.p_value);
    free(x);
    free(y);
    return 0;
}
