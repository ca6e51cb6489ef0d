#include "seeds.h"

#include <math.h>
#include <stdlib.h>

static double torus_delta(double d, double T)
{
    /* Shortest signed difference on a circle of length T. */
    d = fmod(d, T);
    if (d > T / 2)
        d -= T;
    else if (d < -T / 2)
        d += T;
    return d;
}

static double wrap_coord(double v, double T)
{
    v = fmod(v, T);
    if (v < 0)
        v += T;
    if (v >= T)
        v = 0;
    return v;
}

static void shuffle(size_t *a, size_t n, aa_rng *rng)
{
    for (size_t i = n; i > 1; i--) {
        size_t j = aa_rng_below(rng, (uint32_t)i);
        size_t t = a[i - 1];
        a[i - 1] = a[j];
        a[j] = t;
    }
}

static int jittered(size_t n, int T, aa_rng *rng, aa_point *out)
{
    size_t gx = (size_t)ceil(sqrt((double)n)), gy = (n + gx - 1) / gx;
    size_t cells = gx * gy;
    size_t *idx = malloc(cells * sizeof *idx);
    if (!idx)
        return AA_ENOMEM;
    for (size_t i = 0; i < cells; i++)
        idx[i] = i;
    shuffle(idx, cells, rng); /* n distinct strata when the grid has spare cells */
    for (size_t i = 0; i < n; i++) {
        size_t cx = idx[i] % gx, cy = idx[i] / gx;
        out[i].x = (cx + aa_rng_uniform(rng)) * T / (double)gx;
        out[i].y = (cy + aa_rng_uniform(rng)) * T / (double)gy;
    }
    free(idx);
    return AA_OK;
}

static int nrooks(size_t n, int T, aa_rng *rng, aa_point *out)
{
    size_t *px = malloc(n * sizeof *px), *py = malloc(n * sizeof *py);
    if (!px || !py) {
        free(px);
        free(py);
        return AA_ENOMEM;
    }
    for (size_t i = 0; i < n; i++)
        px[i] = py[i] = i;
    shuffle(px, n, rng);
    shuffle(py, n, rng);
    for (size_t i = 0; i < n; i++) {
        out[i].x = (px[i] + aa_rng_uniform(rng)) * T / (double)n;
        out[i].y = (py[i] + aa_rng_uniform(rng)) * T / (double)n;
    }
    free(px);
    free(py);
    return AA_OK;
}

static void poisson(size_t n, int T, aa_rng *rng, aa_point *out)
{
    /* Dart throwing with a radius near the densest packing's spacing, shrunk whenever darts
     * keep failing, so it always terminates with n points. */
    double r = 0.75 * T / sqrt((double)n);
    size_t have = 0;
    int failures = 0;
    while (have < n) {
        aa_point c = {aa_rng_uniform(rng) * T, aa_rng_uniform(rng) * T};
        int ok = 1;
        for (size_t j = 0; j < have && ok; j++) {
            double dx = torus_delta(c.x - out[j].x, T), dy = torus_delta(c.y - out[j].y, T);
            ok = dx * dx + dy * dy >= r * r;
        }
        if (ok) {
            out[have++] = c;
            failures = 0;
        } else if (++failures > 200) {
            r *= 0.9;
            failures = 0;
        }
    }
}

int aa_lloyd_torus(aa_point *pts, size_t n, int T, int iterations, int oversample, aa_rng *rng)
{
    if (n == 0 || T < 1 || oversample < 1)
        return AA_EINVAL;
    double *sx = calloc(n, sizeof *sx), *sy = calloc(n, sizeof *sy);
    size_t *cnt = calloc(n, sizeof *cnt);
    if (!sx || !sy || !cnt) {
        free(sx);
        free(sy);
        free(cnt);
        return AA_ENOMEM;
    }
    size_t m = n * (size_t)oversample;
    for (int it = 0; it < iterations; it++) {
        for (size_t i = 0; i < n; i++) {
            sx[i] = sy[i] = 0;
            cnt[i] = 0;
        }
        for (size_t s = 0; s < m; s++) {
            double x = aa_rng_uniform(rng) * T, y = aa_rng_uniform(rng) * T;
            size_t best = 0;
            double bd = INFINITY, bdx = 0, bdy = 0;
            for (size_t i = 0; i < n; i++) {
                double dx = torus_delta(x - pts[i].x, T), dy = torus_delta(y - pts[i].y, T);
                double d = dx * dx + dy * dy;
                if (d < bd) {
                    bd = d;
                    best = i;
                    bdx = dx;
                    bdy = dy;
                }
            }
            /* Accumulate offsets from the site, so the centroid is taken on the torus. */
            sx[best] += bdx;
            sy[best] += bdy;
            cnt[best]++;
        }
        for (size_t i = 0; i < n; i++) {
            if (!cnt[i])
                continue;
            pts[i].x = wrap_coord(pts[i].x + sx[i] / cnt[i], T);
            pts[i].y = wrap_coord(pts[i].y + sy[i] / cnt[i], T);
        }
    }
    free(sx);
    free(sy);
    free(cnt);
    return AA_OK;
}

int aa_seed_points(aa_seed_kind kind, size_t n, int T, aa_rng *rng, aa_point *out)
{
    if (n == 0 || T < 1)
        return AA_EINVAL;
    int rc = AA_OK;
    switch (kind) {
    case AA_SEED_JITTERED:
        rc = jittered(n, T, rng, out);
        break;
    case AA_SEED_NROOKS:
        rc = nrooks(n, T, rng, out);
        break;
    case AA_SEED_POISSON:
        poisson(n, T, rng, out);
        break;
    case AA_SEED_LLOYD:
        for (size_t i = 0; i < n; i++) {
            out[i].x = aa_rng_uniform(rng) * T;
            out[i].y = aa_rng_uniform(rng) * T;
        }
        rc = aa_lloyd_torus(out, n, T, 12, 16, rng); /* enough for seeding */
        break;
    case AA_SEED_UNIFORM:
    default:
        for (size_t i = 0; i < n; i++) {
            out[i].x = aa_rng_uniform(rng) * T;
            out[i].y = aa_rng_uniform(rng) * T;
        }
        break;
    }
    for (size_t i = 0; i < n && !rc; i++) {
        out[i].x = wrap_coord(out[i].x, T);
        out[i].y = wrap_coord(out[i].y, T);
    }
    return rc;
}
