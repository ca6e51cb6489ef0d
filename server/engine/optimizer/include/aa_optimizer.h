/* aalab_optimizer: multi-start optimisation of positions and weights with the step rules, and
 * the statistics of random patterns. The only header code outside server/engine/optimizer
 * includes. */
#ifndef AA_OPTIMIZER_PUBLIC_H
#define AA_OPTIMIZER_PUBLIC_H

#include "../optimizer.h"
#include "../objective_scene.h"
#include "../random_patterns.h"
#include "../table3.h"

#endif
