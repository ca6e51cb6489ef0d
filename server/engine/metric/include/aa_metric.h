/* aalab_metric: the acuity model and the E1/E2 metric of a pattern against its reference filter,
 * with gradients. The only header code outside server/engine/metric includes. */
#ifndef AA_METRIC_PUBLIC_H
#define AA_METRIC_PUBLIC_H

#include "../acuity.h"
#include "../metric.h"

#endif
