#include "enumerate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "seeds.h"

double aa_mirrored_config_cost(const aa_mirrored_config *c)
{
    int q = 0; /* in quarters of a sample */
    for (int i = 0; i < 4; i++)
        q += c->corners[i] + 2 * c->edges[i];
    q += 4 * c->interior;
    return q / 4.0;
}

void aa_mirrored_config_transform(const aa_mirrored_config *c, int g, aa_mirrored_config *out)
{
    aa_mirrored_config r;
    int rot = g % 4;
    for (int i = 0; i < 4; i++) {
        r.corners[(i + rot) % 4] = c->corners[i];
        r.edges[(i + rot) % 4] = c->edges[i];
    }
    r.interior = c->interior;
    if (g >= 4) {
        /* x -> -x swaps corners 0<->1, 2<->3 and edges 1<->3 (bottom and top stay). */
        aa_mirrored_config m = r;
        m.corners[0] = r.corners[1];
        m.corners[1] = r.corners[0];
        m.corners[2] = r.corners[3];
        m.corners[3] = r.corners[2];
        m.edges[1] = r.edges[3];
        m.edges[3] = r.edges[1];
        r = m;
    }
    *out = r;
}

static int config_cmp(const aa_mirrored_config *a, const aa_mirrored_config *b)
{
    for (int i = 0; i < 4; i++)
        if (a->corners[i] != b->corners[i])
            return a->corners[i] < b->corners[i] ? -1 : 1;
    for (int i = 0; i < 4; i++)
        if (a->edges[i] != b->edges[i])
            return a->edges[i] < b->edges[i] ? -1 : 1;
    return (a->interior > b->interior) - (a->interior < b->interior);
}

static int config_qsort_cmp(const void *a, const void *b)
{
    return config_cmp(a, b);
}

void aa_mirrored_config_canonical(const aa_mirrored_config *c, aa_mirrored_config *out)
{
    aa_mirrored_config best = *c, t;
    for (int g = 1; g < 8; g++) {
        aa_mirrored_config_transform(c, g, &t);
        if (config_cmp(&t, &best) < 0)
            best = t;
    }
    *out = best;
}

int aa_enumerate_mirrored(double cost, aa_mirrored_config **out, size_t *count, aa_error *err)
{
    *out = NULL;
    *count = 0;
    if (!isfinite(cost) || cost <= 0 || cost > AA_ENUMERATE_MAX_COST)
        return aa_error_set(err, AA_EINVAL, "cost", "cost must be in (0, %g]",
                            AA_ENUMERATE_MAX_COST);
    double qd = cost * 4;
    if (fabs(qd - round(qd)) > 1e-9)
        return aa_error_set(err, AA_EINVAL, "cost", "cost must be a multiple of 0.25");
    int q = (int)round(qd);
    size_t cap = 64, n = 0;
    aa_mirrored_config *list = malloc(cap * sizeof *list);
    if (!list)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (int mask = 0; mask < 16; mask++) {
        aa_mirrored_config c = {{0}, {0}, 0};
        int cq = 0;
        for (int i = 0; i < 4; i++) {
            c.corners[i] = (mask >> i) & 1;
            cq += c.corners[i];
        }
        int rest = q - cq; /* quarters left for edges (2 each) and interior (4 each) */
        if (rest < 0)
            continue;
        int emax = rest / 2;
        for (int e0 = 0; e0 <= emax; e0++)
            for (int e1 = 0; e0 + e1 <= emax; e1++)
                for (int e2 = 0; e0 + e1 + e2 <= emax; e2++)
                    for (int e3 = 0; e0 + e1 + e2 + e3 <= emax; e3++) {
                        int left = rest - 2 * (e0 + e1 + e2 + e3);
                        if (left % 4)
                            continue;
                        c.edges[0] = e0;
                        c.edges[1] = e1;
                        c.edges[2] = e2;
                        c.edges[3] = e3;
                        c.interior = left / 4;
                        aa_mirrored_config canon;
                        aa_mirrored_config_canonical(&c, &canon);
                        if (config_cmp(&canon, &c) != 0)
                            continue; /* count each orbit once, at its canonical member */
                        if (n == cap) {
                            aa_mirrored_config *grown = realloc(list, 2 * cap * sizeof *list);
                            if (!grown) {
                                free(list);
                                return aa_error_set(err, AA_ENOMEM, "", "out of memory");
                            }
                            list = grown;
                            cap *= 2;
                        }
                        list[n++] = c;
                    }
    }
    qsort(list, n, sizeof *list, config_qsort_cmp);
    *out = list;
    *count = n;
    return AA_OK;
}

/* Interior positions stay this far from the pixel border so their site is unambiguous. */
#define INTERIOR_MARGIN 1e-3

int aa_mirrored_config_seed(const aa_mirrored_config *c, aa_seed_distribution distribution,
                            const aa_filter *filter, aa_rng *rng, aa_pattern *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    int total = c->interior;
    for (int i = 0; i < 4; i++) {
        if (c->corners[i] < 0 || c->corners[i] > 1 || c->edges[i] < 0)
            return aa_error_set(err, AA_EINVAL, "config", "corner counts are 0 or 1, edges >= 0");
        total += c->corners[i] + c->edges[i];
    }
    if (c->interior < 0 || total <= 0 || total > AA_MAX_KERNEL_SAMPLES)
        return aa_error_set(err, AA_EINVAL, "config", "the configuration places no sample");
    aa_sample *s = malloc((size_t)total * sizeof *s);
    aa_point *pts = c->interior ? malloc((size_t)c->interior * sizeof *pts) : NULL;
    if (!s || (c->interior && !pts)) {
        free(s);
        free(pts);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    static const double cx[4] = {-0.5, 0.5, 0.5, -0.5}, cy[4] = {-0.5, -0.5, 0.5, 0.5};
    size_t n = 0;
    for (int i = 0; i < 4; i++)
        if (c->corners[i])
            s[n++] = (aa_sample){cx[i], cy[i], 0};
    for (int e = 0; e < 4; e++) {
        for (int k = 0; k < c->edges[e]; k++) {
            /* Stratified along the edge so samples on one edge never coincide. */
            double t = (k + 0.05 + 0.9 * aa_rng_uniform(rng)) / c->edges[e] - 0.5;
            t = fmin(fmax(t, -0.5 + INTERIOR_MARGIN), 0.5 - INTERIOR_MARGIN);
            aa_sample v = e == 0   ? (aa_sample){t, -0.5, 0}
                          : e == 1 ? (aa_sample){0.5, t, 0}
                          : e == 2 ? (aa_sample){t, 0.5, 0}
                                   : (aa_sample){-0.5, t, 0};
            s[n++] = v;
        }
    }
    int rc = AA_OK;
    if (c->interior) {
        rc = aa_seed_points(distribution, (size_t)c->interior, 1, rng, pts);
        for (int k = 0; k < c->interior && !rc; k++) {
            double x = pts[k].x - 0.5, y = pts[k].y - 0.5;
            double lim = 0.5 - INTERIOR_MARGIN;
            s[n++] = (aa_sample){fmin(fmax(x, -lim), lim), fmin(fmax(y, -lim), lim), 0};
        }
    }
    if (rc) {
        free(s);
        free(pts);
        return aa_error_set(err, rc, "", "seed generation failed");
    }
    double sum = 0;
    for (size_t i = 0; i < n; i++) {
        s[i].w = aa_filter_eval(filter, s[i].x) * aa_filter_eval(filter, s[i].y);
        sum += s[i].w;
    }
    if (fabs(sum) < 1e-12)
        for (size_t i = 0; i < n; i++)
            s[i].w = 1.0 / (double)n;
    rc = aa_pattern_from_mirrored(out, s, n, AA_PATTERN_NORMALIZE, err);
    free(s);
    free(pts);
    return rc;
}
