/* Angle-specific acuity W(theta) for the E2 metric (Laine & Aila 2005 after Naiman 1998).
 *
 * A table is a list of (angle in degrees, weight) knots, interpolated linearly. Two kinds:
 *  - folded (all knots in [0, 45]): W has the 8 symmetries of the square; an angle is folded
 *    into [0, 45] before interpolation. The default angle set is the knots unfolded to
 *    [0, 180): {k, 90-k, 90+k, 180-k}.
 *  - periodic (knots anywhere in [0, 180)): W has period 180 and is interpolated with
 *    wrap-around; the default angle set is the knots themselves.
 * theta is the direction of the edge normal (p = x cos theta + y sin theta); for a folded table
 * normal and edge direction give the same W. */
#ifndef AA_ACUITY_H
#define AA_ACUITY_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_core.h"

#define AA_ACUITY_MAX_KNOTS 361
#define AA_MAX_ANGLES 4096

typedef struct aa_acuity {
    char name[24]; /* "naiman", "naiman-envelope", "uniform" or "custom" */
    int version;   /* of a named table (naiman 2, naiman-envelope 1, uniform 1); 0: custom */
    bool folded;
    size_t count;
    double angle_deg[AA_ACUITY_MAX_KNOTS]; /* ascending */
    double weight[AA_ACUITY_MAX_KNOTS];
} aa_acuity;

/* The reconstructed Naiman table shipped with aalab (data/acuity-naiman.json), version 2: the
 * default table. */
void aa_acuity_naiman(aa_acuity *a);
/* Version 1 of that table, "naiman-envelope": its knots 5..40 sit just under the upper bound the
 * fixed patterns allow (data/acuity-naiman.json, alternatives). */
void aa_acuity_naiman_envelope(aa_acuity *a);
/* The named tables aa_acuity_by_name knows, NULL-terminated, the default first. */
extern const char *const aa_acuity_names[];
/* W = 1 at every angle; its default angle set is 0, 5, ..., 175. */
void aa_acuity_uniform(aa_acuity *a);
/* knots: count pairs (deg, W). W must be finite and >= 0, angles finite, distinct, in [0,180).
 * Errors name the field as "knots[i][0]" / "knots[i][1]". */
int aa_acuity_from_knots(aa_acuity *a, const double (*knots)[2], size_t count, aa_error *err);
int aa_acuity_by_name(aa_acuity *a, const char *name, aa_error *err);

double aa_acuity_weight(const aa_acuity *a, double theta_deg);
/* Writes the default angle set (ascending, in [0,180)) to out; returns how many (<= cap). */
size_t aa_acuity_default_angles(const aa_acuity *a, double *out, size_t cap);

#endif
