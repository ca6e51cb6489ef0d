/* aalab_temporal: temporal antialiasing (a jitter sequence blended into a history buffer) as a
 * set of weighted kernels, one per phase, with its flicker and after-cut curve. The only header
 * code outside server/engine/temporal includes. */
#ifndef AA_TEMPORAL_PUBLIC_H
#define AA_TEMPORAL_PUBLIC_H

#include "../jitter.h"
#include "../temporal.h"
#include "../temporal_eval.h"
#include "../temporal_optimize.h"

#endif
