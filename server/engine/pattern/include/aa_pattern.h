/* aalab_pattern: sample patterns in the P(s, r, n) families, the reference filters their
 * weights may come from, families, seeds, presets and the enumeration of configurations. The
 * only header code outside server/engine/pattern includes. */
#ifndef AA_PATTERN_PUBLIC_H
#define AA_PATTERN_PUBLIC_H

#include "../filter.h"
#include "../pattern.h"
#include "../family.h"
#include "../seeds.h"
#include "../presets.h"
#include "../enumerate.h"
#include "../point_set.h"
#include "../point_metrics.h"

#endif
