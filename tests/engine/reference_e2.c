/* Independent E2 for the tests (see reference_e2.h). */
#include "reference_e2.h"

#include <math.h>
#include <stdlib.h>

/* data/acuity-naiman.json knots (version 2) at 0, 5, ..., 45 degrees. */
static const double naiman_knots[10] = {3.93, 3.0, 2.5, 2.2, 2.0, 1.9, 1.9, 2.0, 2.2, 2.5};

double ref_fold_deg(double t)
{
    t = fmod(t, 90.0);
    if (t < 0)
        t += 90.0;
    return t > 45.0 ? 90.0 - t : t;
}

double ref_naiman_weight(double theta_deg)
{
    double t = ref_fold_deg(theta_deg);
    int k = (int)(t / 5.0);
    if (k >= 9)
        return naiman_knots[9];
    double f = (t - 5.0 * k) / 5.0;
    return naiman_knots[k] + f * (naiman_knots[k + 1] - naiman_knots[k]);
}

void ref_mirror(const ref_sample *src, size_t count, int m, ref_sample *out)
{
    for (size_t i = 0; i < count; i++) {
        out[i] = src[i];
        if (m & 1)
            out[i].x = -out[i].x;
        if (m & 2)
            out[i].y = -out[i].y;
    }
}

long double ref_kernel_e2(const ref_filter *f, const ref_sample *s, size_t n, double *argmax_deg)
{
    double *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *w = malloc(n * sizeof *w);
    for (size_t i = 0; i < n; i++)
        x[i] = s[i].x, y[i] = s[i].y, w[i] = s[i].w;
    long double best = -1.0L;
    for (int k = 0; k < 36; k++) {
        double deg = 5.0 * k;
        long double v = ref_naiman_weight(deg) *
                        ref_e1_at_angle(f, x, y, w, n, (double)(deg * (REF_PI / 180.0L)));
        if (v > best) {
            best = v;
            if (argmax_deg)
                *argmax_deg = deg;
        }
    }
    free(x);
    free(y);
    free(w);
    return best;
}
