/* aalab_core: error codes and aa_error, the random number generator, Gauss-Legendre quadrature,
 * the one clock and the one fork-join. The only header code outside server/engine/core
 * includes. */
#ifndef AA_CORE_H
#define AA_CORE_H

#include "../aa_error.h"
#include "../clock.h"
#include "../fork_join.h"
#include "../gauss_legendre.h"
#include "../rng.h"
#include "../spearman.h"

#endif
