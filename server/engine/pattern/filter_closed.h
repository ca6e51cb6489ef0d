/* Internal to the pattern library: the closed-form tables of a piecewise-polynomial filter
 * (filter.h, closed_*), built by the constructors in filter.c. */
#ifndef AA_FILTER_CLOSED_H
#define AA_FILTER_CLOSED_H

#include "filter.h"

/* h_coef[j][m]: coefficient of a^m (a the global abscissa) of the normalised impulse response
 * h on piece j; the pieces have equal width and cover [-radius, radius]; degree <= 3. Fills
 * closed_pieces, closed_inv_width, closed_mid, closed_gamma and closed_var. */
void aa_filter_build_closed(aa_filter *f, const long double (*h_coef)[4], int pieces);

/* The normalised response of the Mitchell-Netravali filter of f (B, C, radius) as h_coef rows
 * for the four pieces [-r, -r/2], [-r/2, 0], [0, r/2], [r/2, r]. */
void aa_filter_mitchell_coefficients(const aa_filter *f, long double (*h_coef)[4]);

#endif
