#include "family.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "enumerate.h"
#include "seeds.h"

static const char *skip_space(const char *p)
{
    while (*p && isspace((unsigned char)*p))
        p++;
    return p;
}

static int perfect_root(long v)
{
    long r = lround(sqrt((double)v));
    return r * r == v ? (int)r : -1;
}

int aa_family_parse(const char *text, aa_family *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    if (!text)
        return aa_error_set(err, AA_EINVAL, "family", "family is required");
    const char *p = skip_space(text);
    if (*p != 'P' && *p != 'p')
        return aa_error_set(err, AA_EINVAL, "family", "expected \"P(s,r,n)\"");
    p = skip_space(p + 1);
    if (*p++ != '(')
        return aa_error_set(err, AA_EINVAL, "family", "expected \"P(s,r,n)\"");
    char *end;
    long s = strtol(p, &end, 10);
    if (end == p)
        return aa_error_set(err, AA_EINVAL, "family", "s must be an integer");
    p = skip_space(end);
    if (*p++ != ',')
        return aa_error_set(err, AA_EINVAL, "family", "expected \"P(s,r,n)\"");
    long r = strtol(p, &end, 10);
    if (end == p)
        return aa_error_set(err, AA_EINVAL, "family", "r must be an integer");
    p = skip_space(end);
    bool border = false;
    if (*p == '+') {
        border = true;
        p = skip_space(p + 1);
    }
    if (*p++ != ',')
        return aa_error_set(err, AA_EINVAL, "family", "expected \"P(s,r,n)\"");
    double n = strtod(p, &end);
    if (end == p || !isfinite(n))
        return aa_error_set(err, AA_EINVAL, "family", "n must be a number");
    p = skip_space(end);
    if (*p++ != ')' || *skip_space(p))
        return aa_error_set(err, AA_EINVAL, "family", "expected \"P(s,r,n)\"");
    int T = s >= 1 && s <= AA_MAX_TILE * AA_MAX_TILE ? perfect_root(s) : -1;
    if (T < 1)
        return aa_error_set(err, AA_EINVAL, "family", "s must be a perfect square in 1..%d",
                            AA_MAX_TILE * AA_MAX_TILE);
    int K = r >= 1 && r <= AA_MAX_KERNEL_SIZE * AA_MAX_KERNEL_SIZE ? perfect_root(r) : -1;
    if (K < 1)
        return aa_error_set(err, AA_EINVAL, "family", "r must be a perfect square in 1..%d",
                            AA_MAX_KERNEL_SIZE * AA_MAX_KERNEL_SIZE);
    if (n <= 0)
        return aa_error_set(err, AA_EINVAL, "family", "n must be positive");
    out->tile = T;
    out->kernel_size = K;
    out->border = border;
    out->mirrored = T == 2 && K == 1 && border;
    out->cost = n;
    double samples = n * T * T;
    if (out->mirrored) {
        if (fabs(n * 4 - round(n * 4)) > 1e-9)
            return aa_error_set(err, AA_EINVAL, "family", "P(4,1+,n) needs n a multiple of 0.25");
        if (n > 16)
            return aa_error_set(err, AA_ERANGE, "family", "n must be at most 16");
    } else {
        if (fabs(samples - round(samples)) > 1e-9)
            return aa_error_set(err, AA_EINVAL, "family",
                                "n * s must be a whole number of samples");
        if (samples > AA_MAX_KERNEL_SAMPLES / 4 || samples < 1)
            return aa_error_set(err, AA_ERANGE, "family", "n * s must be in 1..%d",
                                AA_MAX_KERNEL_SAMPLES / 4);
    }
    aa_family_label(out->label, sizeof out->label, (size_t)T * T, K, border, n);
    return AA_OK;
}

static const char *const seed_names[] = {"uniform", "jittered", "n-rooks", "poisson", "lloyd"};

int aa_seed_distribution_parse(const char *name, aa_seed_distribution *out)
{
    for (int k = 0; k < 5; k++) {
        if (name && !strcmp(name, seed_names[k])) {
            *out = (aa_seed_distribution)k;
            return AA_OK;
        }
    }
    return AA_EINVAL;
}

const char *aa_seed_distribution_name(aa_seed_distribution k)
{
    return (unsigned)k < 5 ? seed_names[k] : "unknown";
}

/* Border families P(s,r+,n) only differ from P(s,r,n) when samples sit on pixel edges, so a
 * quarter of their seed samples are moved onto the nearest vertical or horizontal edge. */
static void snap_some_to_edges(aa_point *pts, size_t n, aa_rng *rng)
{
    for (size_t i = 0; i < n; i++) {
        if (aa_rng_below(rng, 4) != 0)
            continue;
        aa_point q = pts[i];
        if (aa_rng_below(rng, 2))
            q.x = floor(q.x);
        else
            q.y = floor(q.y);
        bool clash = false;
        for (size_t j = 0; j < n && !clash; j++)
            clash = j != i && fabs(pts[j].x - q.x) < 1e-6 && fabs(pts[j].y - q.y) < 1e-6;
        if (!clash)
            pts[i] = q;
    }
}

int aa_family_seed(const aa_family *family, aa_seed_distribution distribution,
                   const aa_filter *filter, aa_rng *rng, aa_pattern *out, aa_error *err)
{
    return aa_family_seed_radius(family, distribution, 0, filter, rng, out, err);
}

int aa_family_seed_radius(const aa_family *family, aa_seed_distribution distribution,
                          double poisson_radius, const aa_filter *filter, aa_rng *rng,
                          aa_pattern *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    if (family->mirrored) {
        aa_mirrored_config *configs;
        size_t count;
        int rc = aa_enumerate_mirrored(family->cost, &configs, &count, err);
        if (rc)
            return rc;
        if (count == 0) {
            free(configs);
            return aa_error_set(err, AA_EINVAL, "family", "no configuration of this cost");
        }
        aa_mirrored_config c = configs[aa_rng_below(rng, (uint32_t)count)];
        free(configs);
        return aa_mirrored_config_seed(&c, distribution, filter, rng, out, err);
    }
    int T = family->tile;
    size_t n = (size_t)llround(family->cost * T * T);
    aa_point *pts = malloc(n * sizeof *pts);
    if (!pts)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    int rc = aa_seed_points_radius(distribution, n, T, poisson_radius, rng, pts);
    if (rc) {
        free(pts);
        if (rc == AA_ERANGE)
            return aa_error_set(err, rc, "poisson_radius",
                                "dart throwing at radius %g px finds no room for %zu points in "
                                "a %dx%d tile: use a smaller radius",
                                poisson_radius, n, T, T);
        return aa_error_set(err, rc, "", "seed generation failed");
    }
    /* Keep seeds off the pixel grid unless deliberately placed there. */
    for (size_t i = 0; i < n; i++) {
        double fx = pts[i].x - floor(pts[i].x), fy = pts[i].y - floor(pts[i].y);
        if (fx < 1e-6)
            pts[i].x += 1e-3;
        if (fy < 1e-6)
            pts[i].y += 1e-3;
    }
    if (family->border)
        snap_some_to_edges(pts, n, rng);
    aa_tile_spec spec = {T, family->kernel_size, family->border, n, pts, NULL, NULL, filter};
    rc = aa_pattern_from_tile(out, &spec, 0, err);
    free(pts);
    return rc;
}
