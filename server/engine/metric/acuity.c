#include "acuity.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* data/acuity-naiman.json ("knots", version 2): W(0) and W(45) are pinned by the published E2
 * values; 5..40 are a reconstruction that also fits L&A Table 3 (see data/README.md).
 * tests/engine/test_acuity_data.c checks these against the data file. */
static const double naiman_knots[][2] = {{0, 3.93}, {5, 3.0},  {10, 2.5}, {15, 2.2}, {20, 2.0},
                                         {25, 1.9}, {30, 1.9}, {35, 2.0}, {40, 2.2}, {45, 2.5}};
/* Version 1, data/acuity-naiman.json "alternatives.naiman-envelope": the knots just under the
 * upper bound the fixed patterns allow. */
static const double envelope_knots[][2] = {{0, 3.93},  {5, 3.55},  {10, 3.10}, {15, 2.67},
                                           {20, 2.30}, {25, 1.95}, {30, 1.95}, {35, 2.15},
                                           {40, 2.20}, {45, 2.50}};

void aa_acuity_naiman(aa_acuity *a)
{
    aa_acuity_from_knots(a, naiman_knots, sizeof naiman_knots / sizeof naiman_knots[0], NULL);
    snprintf(a->name, sizeof a->name, "naiman");
    a->version = 2;
}

void aa_acuity_naiman_envelope(aa_acuity *a)
{
    aa_acuity_from_knots(a, envelope_knots, sizeof envelope_knots / sizeof envelope_knots[0], NULL);
    snprintf(a->name, sizeof a->name, "naiman-envelope");
    a->version = 1;
}

const char *const aa_acuity_names[] = {"naiman", "naiman-envelope", "uniform", NULL};

void aa_acuity_uniform(aa_acuity *a)
{
    /* Knots every 5 degrees over [0, 45] so that the default angle set is 0, 5, ..., 175. */
    double knots[10][2];
    for (int i = 0; i < 10; i++) {
        knots[i][0] = 5.0 * i;
        knots[i][1] = 1;
    }
    aa_acuity_from_knots(a, (const double(*)[2])knots, 10, NULL);
    snprintf(a->name, sizeof a->name, "uniform");
    a->version = 1;
}

int aa_acuity_by_name(aa_acuity *a, const char *name, aa_error *err)
{
    if (!strcmp(name, "naiman"))
        aa_acuity_naiman(a);
    else if (!strcmp(name, "naiman-envelope"))
        aa_acuity_naiman_envelope(a);
    else if (!strcmp(name, "uniform"))
        aa_acuity_uniform(a);
    else
        return aa_error_set(err, AA_EINVAL, "name", "unknown acuity table '%.40s'", name);
    return AA_OK;
}

typedef struct knot {
    double angle, weight;
    size_t index;
} knot;

static int knot_cmp(const void *pa, const void *pb)
{
    const knot *a = pa, *b = pb;
    return (a->angle > b->angle) - (a->angle < b->angle);
}

int aa_acuity_from_knots(aa_acuity *a, const double (*knots)[2], size_t count, aa_error *err)
{
    char field[48];
    if (count == 0)
        return aa_error_set(err, AA_EINVAL, "knots", "an acuity table needs at least one knot");
    if (count > AA_ACUITY_MAX_KNOTS)
        return aa_error_set(err, AA_ERANGE, "knots", "at most %d knots", AA_ACUITY_MAX_KNOTS);
    knot sorted[AA_ACUITY_MAX_KNOTS];
    bool folded = true;
    for (size_t i = 0; i < count; i++) {
        double ang = knots[i][0], w = knots[i][1];
        if (!isfinite(ang) || ang < 0 || ang >= 180) {
            snprintf(field, sizeof field, "knots[%zu][0]", i);
            return aa_error_set(err, AA_EINVAL, field, "knot angle must be in [0, 180) degrees");
        }
        if (!isfinite(w) || w < 0) {
            snprintf(field, sizeof field, "knots[%zu][1]", i);
            return aa_error_set(err, AA_EINVAL, field, "knot weight must be finite and >= 0");
        }
        if (ang > 45)
            folded = false;
        sorted[i] = (knot){ang, w, i};
    }
    qsort(sorted, count, sizeof sorted[0], knot_cmp);
    for (size_t i = 1; i < count; i++) {
        if (sorted[i].angle - sorted[i - 1].angle < 1e-9) {
            snprintf(field, sizeof field, "knots[%zu][0]", sorted[i].index);
            return aa_error_set(err, AA_EINVAL, field, "duplicate knot angle %g", sorted[i].angle);
        }
    }
    memset(a, 0, sizeof *a);
    snprintf(a->name, sizeof a->name, "custom");
    a->folded = folded;
    a->count = count;
    for (size_t i = 0; i < count; i++) {
        a->angle_deg[i] = sorted[i].angle;
        a->weight[i] = sorted[i].weight;
    }
    return AA_OK;
}

double aa_acuity_weight(const aa_acuity *a, double theta_deg)
{
    size_t n = a->count;
    if (n == 1)
        return a->weight[0];
    double d;
    if (a->folded) {
        d = fmod(theta_deg, 90.0);
        if (d < 0)
            d += 90.0;
        if (d > 45.0)
            d = 90.0 - d;
        if (d <= a->angle_deg[0])
            return a->weight[0];
        if (d >= a->angle_deg[n - 1])
            return a->weight[n - 1];
    } else {
        d = fmod(theta_deg, 180.0);
        if (d < 0)
            d += 180.0;
        /* Wrap-around segment between the last knot and the first + 180. */
        if (d < a->angle_deg[0] || d >= a->angle_deg[n - 1]) {
            double x0 = a->angle_deg[n - 1], x1 = a->angle_deg[0] + 180.0;
            double x = d < a->angle_deg[0] ? d + 180.0 : d;
            double t = (x - x0) / (x1 - x0);
            return a->weight[n - 1] + t * (a->weight[0] - a->weight[n - 1]);
        }
    }
    size_t lo = 0, hi = n - 1; /* angle[lo] <= d < angle[hi] */
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (a->angle_deg[mid] <= d)
            lo = mid;
        else
            hi = mid;
    }
    double t = (d - a->angle_deg[lo]) / (a->angle_deg[hi] - a->angle_deg[lo]);
    return a->weight[lo] + t * (a->weight[hi] - a->weight[lo]);
}

static int double_cmp(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

size_t aa_acuity_default_angles(const aa_acuity *a, double *out, size_t cap)
{
    double all[4 * AA_ACUITY_MAX_KNOTS];
    size_t n = 0;
    for (size_t i = 0; i < a->count; i++) {
        double k = a->angle_deg[i];
        if (!a->folded) {
            all[n++] = k;
            continue;
        }
        double images[4] = {k, 90 - k, 90 + k, 180 - k};
        for (int j = 0; j < 4; j++) {
            double v = images[j];
            if (v >= 180 - 1e-9)
                v -= 180;
            if (v < 0)
                v += 180;
            all[n++] = v;
        }
    }
    qsort(all, n, sizeof all[0], double_cmp);
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (m > 0 && all[i] - all[m - 1] < 1e-9)
            continue;
        all[m++] = all[i];
    }
    if (m > cap)
        m = cap;
    memcpy(out, all, m * sizeof out[0]);
    return m;
}
