#include "seeds.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

static double torus_delta(double d, double T)
{
    /* Shortest signed difference on a circle of length T. */
    assert(T > 0);
    d = fmod(d, T);
    if (d > T / 2)
        d -= T;
    else if (d < -T / 2)
        d += T;
    return d;
}

static double wrap_coord(double v, double T)
{
    assert(T > 0);
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

const char *aa_seed_generator_name(aa_seed_distribution distribution)
{
    switch (distribution) {
    case AA_SEED_POISSON:
        return AA_POISSON_GENERATOR;
    case AA_SEED_JITTERED:
        return "jittered-grid";
    case AA_SEED_NROOKS:
        return "n-rooks";
    case AA_SEED_LLOYD:
        return "lloyd-torus";
    case AA_SEED_UNIFORM:
    default:
        return "uniform";
    }
}

double aa_poisson_default_radius(double spp)
{
    return AA_POISSON_RADIUS_FACTOR / sqrt(spp);
}

/* One dart throw: uniform darts on the torus, each kept when no kept point is closer than r,
 * until n are kept or max_darts were thrown. A grid of cells no smaller than r makes each test
 * look at the 3x3 cells around the dart only. Returns how many points were kept. */
static size_t throw_darts(size_t n, int T, double r, size_t max_darts, aa_rng *rng, aa_point *out,
                          int *head, int *next, int cells)
{
    double cell = T / (double)cells;
    for (int i = 0; i < cells * cells; i++)
        head[i] = -1;
    size_t have = 0;
    for (size_t d = 0; d < max_darts && have < n; d++) {
        aa_point c = {aa_rng_uniform(rng) * T, aa_rng_uniform(rng) * T};
        int cx = (int)(c.x / cell), cy = (int)(c.y / cell);
        cx = cx < cells ? cx : cells - 1;
        cy = cy < cells ? cy : cells - 1;
        int ok = 1, span = cells >= 3 ? 1 : 0; /* cells is 1 or >= 3 */
        for (int oy = -span; oy <= span && ok; oy++)
            for (int ox = -span; ox <= span && ok; ox++) {
                int gx = (cx + ox + cells) % cells, gy = (cy + oy + cells) % cells;
                for (int j = head[gy * cells + gx]; j >= 0 && ok; j = next[j]) {
                    double dx = torus_delta(c.x - out[j].x, T);
                    double dy = torus_delta(c.y - out[j].y, T);
                    ok = dx * dx + dy * dy >= r * r;
                }
            }
        if (ok) {
            out[have] = c;
            next[have] = head[cy * cells + cx];
            head[cy * cells + cx] = (int)have;
            have++;
        }
    }
    return have;
}

/* Dart throwing on the torus at the stated radius r (tile units), as the classic Poisson-disk
 * construction (Cook 1986; L&A Table 3's Poisson disk): no two points closer than r. A throw
 * that jams (no room left before n points) starts again; a radius too large for n points ends
 * with AA_ERANGE rather than a silently smaller radius. */
static int poisson(size_t n, int T, double r, aa_rng *rng, aa_point *out)
{
    if (!(r >= 0) || !isfinite(r))
        return AA_EINVAL;
    int cells = r > 0 ? (int)floor(T / r) : 1;
    if (cells < 1)
        cells = 1;
    if ((size_t)cells * (size_t)cells > 4 * n + 16)
        cells = (int)floor(sqrt(4.0 * (double)n + 16.0));
    if (cells < 3) /* the 3x3 neighbourhood would wrap onto itself: one cell holds all */
        cells = 1;
    int *head = malloc((size_t)cells * (size_t)cells * sizeof *head);
    int *next = malloc(n * sizeof *next);
    if (!head || !next || n > INT32_MAX) {
        free(head);
        free(next);
        return AA_ENOMEM;
    }
    int rc = AA_ERANGE;
    for (int attempt = 0; attempt < AA_POISSON_THROWS && rc; attempt++)
        if (throw_darts(n, T, r, AA_POISSON_DARTS_PER_POINT * n + 1000, rng, out, head, next,
                        cells) == n)
            rc = AA_OK;
    free(head);
    free(next);
    return rc;
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

int aa_seed_points(aa_seed_distribution distribution, size_t n, int T, aa_rng *rng, aa_point *out)
{
    return aa_seed_points_radius(distribution, n, T, 0, rng, out);
}

int aa_seed_points_radius(aa_seed_distribution distribution, size_t n, int T, double poisson_radius,
                          aa_rng *rng, aa_point *out)
{
    if (n == 0 || T < 1)
        return AA_EINVAL;
    int rc = AA_OK;
    switch (distribution) {
    case AA_SEED_JITTERED:
        rc = jittered(n, T, rng, out);
        break;
    case AA_SEED_NROOKS:
        rc = nrooks(n, T, rng, out);
        break;
    case AA_SEED_POISSON:
        /* The radius is in pixels; 0: the default for this density. */
        rc = poisson(n, T,
                     poisson_radius > 0
                         ? poisson_radius
                         : aa_poisson_default_radius((double)n / ((double)T * (double)T)),
                     rng, out);
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
