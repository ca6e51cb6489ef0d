/* The exact L-infinity star discrepancy in 2-D. The supremum over anchored boxes is reached on
 * the grid of candidate corners: a in {x_i} u {1}, b in {y_j} u {1}. At a corner (a, b) the
 * lower deviation is ab - #{x < a, y < b}/n (open box, approached from inside) and the upper one
 * #{x <= a, y <= b}/n - ab (closed box). Sweeping a upwards keeps the y of the points left of
 * a in two sorted arrays (x < a and x <= a); for each a one pass over the sorted y candidates
 * counts both boxes with two pointers: O(n^2) in all (Dobkin & Eppstein's O(n log^2 n) is not
 * needed at n <= 4096). */
#include "point_set.h"

#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static int cmp_point_x(const void *a, const void *b)
{
    double x = ((const aa_point *)a)->x, y = ((const aa_point *)b)->x;
    return x < y ? -1 : x > y;
}

/* Inserts v into the sorted array a of *len entries. */
static void insert_sorted(double *a, size_t *len, double v)
{
    size_t i = *len;
    while (i > 0 && a[i - 1] > v) {
        a[i] = a[i - 1];
        i--;
    }
    a[i] = v;
    (*len)++;
}

/* The largest deviation over the y candidates for one a, given the y of the points with x < a
 * (open, no_len entries) and x <= a (closed, nc_len entries), both sorted. */
static double column_deviation(double a, const double *ys, size_t ny, const double *open,
                               size_t no_len, const double *closed, size_t nc_len, double inv_n)
{
    double worst = 0;
    size_t io = 0, ic = 0;
    for (size_t k = 0; k <= ny; k++) {
        double b = k < ny ? ys[k] : 1.0;
        while (io < no_len && open[io] < b)
            io++;
        while (ic < nc_len && closed[ic] <= b)
            ic++;
        double area = a * b, lower = area - (double)io * inv_n, upper = (double)ic * inv_n - area;
        if (lower > worst)
            worst = lower;
        if (upper > worst)
            worst = upper;
    }
    return worst;
}

int aa_point_set_star_discrepancy(const aa_point *pts, size_t n, double *out, aa_error *err)
{
    int rc = aa_point_set_check(pts, n, err);
    if (rc)
        return rc;
    aa_point *by_x = malloc(n * sizeof *by_x);
    double *ys = malloc(n * sizeof *ys), *open = malloc(n * sizeof *open),
           *closed = malloc(n * sizeof *closed);
    if (!by_x || !ys || !open || !closed) {
        free(by_x);
        free(ys);
        free(open);
        free(closed);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    memcpy(by_x, pts, n * sizeof *by_x);
    qsort(by_x, n, sizeof *by_x, cmp_point_x);
    for (size_t i = 0; i < n; i++)
        ys[i] = pts[i].y;
    qsort(ys, n, sizeof *ys, cmp_double);
    double inv_n = 1.0 / (double)n, worst = 0;
    size_t no_len = 0, nc_len = 0;
    for (size_t i = 0; i < n;) {
        double a = by_x[i].x;
        /* open: x < a, i.e. the points before i; closed gains the points with x == a. */
        size_t j = i;
        while (j < n && by_x[j].x == a)
            insert_sorted(closed, &nc_len, by_x[j++].y);
        double d = column_deviation(a, ys, n, open, no_len, closed, nc_len, inv_n);
        if (d > worst)
            worst = d;
        for (size_t k = i; k < j; k++)
            insert_sorted(open, &no_len, by_x[k].y);
        i = j;
    }
    /* a = 1: every point is left of it, open and closed alike. */
    double d = column_deviation(1.0, ys, n, open, no_len, closed, nc_len, inv_n);
    *out = d > worst ? d : worst;
    free(by_x);
    free(ys);
    free(open);
    free(closed);
    return AA_OK;
}
