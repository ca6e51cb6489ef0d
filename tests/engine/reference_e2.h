/* Independent E2 for the tests: the Naiman acuity knots written out from
 * data/acuity-naiman.json with their own folding and interpolation, mirrored P(4,1+,n) kernels
 * built by hand, and E2 = max W E1 with the reference E1 (reference_metric.h). */
#ifndef AALAB_TESTS_REFERENCE_E2_H
#define AALAB_TESTS_REFERENCE_E2_H

#include <stddef.h>

#include "reference_metric.h"

typedef struct ref_sample {
    double x, y, w;
} ref_sample;

/* W(theta) of data/acuity-naiman.json: fold into [0, 45] by the square's symmetries, then
 * linear between the knots 0, 5, ..., 45. */
double ref_naiman_weight(double theta_deg);
/* Fold an angle in degrees into [0, 45]. */
double ref_fold_deg(double theta_deg);

/* The four kernels of a mirrored P(4,1+,n) pattern from one pixel's samples: mirror index m
 * (0: as given, 1: x negated, 2: y negated, 3: both). out has count entries. */
void ref_mirror(const ref_sample *src, size_t count, int m, ref_sample *out);

/* max over the angles 0, 5, ..., 175 of W E1 for one kernel; *argmax_deg gets the angle. */
long double ref_kernel_e2(const ref_filter *f, const ref_sample *s, size_t n, double *argmax_deg);

#endif
