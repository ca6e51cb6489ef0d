/* Flicker F1 of one group at one direction, with its gradient in the projections (private to
 * the temporal library; docs/temporal.md section 3). */
#ifndef AA_TEMPORAL_FLICKER_H
#define AA_TEMPORAL_FLICKER_H

#include <stddef.h>

#include "temporal.h"

typedef struct aa_flicker_scratch {
    double *p;     /* projections, input order */
    size_t *order; /* sorted order, carried from one direction to the next */
    double *dev;   /* age weight minus the mean age weight */
    double *d2;    /* per sorted gap: sum over phases of D^2 */
} aa_flicker_scratch;

/* m: the most samples of a group; the order holds the identity afterwards. */
int aa_flicker_scratch_init(aa_flicker_scratch *sc, const aa_temporal *t, size_t m);
void aa_flicker_scratch_free(aa_flicker_scratch *sc);
/* Resets the carried order to the identity (before a group's first direction). */
void aa_flicker_scratch_reset(aa_flicker_scratch *sc, size_t m);
/* F1 of group g at (ct, st); dp (group count entries, or NULL) gets dF1/dp_s, the derivative
 * in sample s's projection (0 where F1 = 0; one-sided at ties). */
double aa_flicker_sorted(const aa_temporal *t, size_t g, double ct, double st,
                         aa_flicker_scratch *sc, double *dp);

#endif
