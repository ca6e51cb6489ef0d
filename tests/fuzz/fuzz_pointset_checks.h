/* What both point-set fuzz drivers check of a result: a small pattern's E2 (for round trips) and
 * a refusal's shape (a field under "pattern.points", a UTF-8 message). */
#ifndef AALAB_FUZZ_POINTSET_CHECKS_H
#define AALAB_FUZZ_POINTSET_CHECKS_H

#include "aa_pattern.h"

/* E2 over four angles of a pattern of at most 256 kernel samples; NaN above that or on error. */
double fuzz_small_e2(const aa_pattern *p);
/* rc is a refusal whose field and message are terminated, the message non-empty and valid
 * UTF-8 (it goes into a JSON answer), the field under "pattern.points". */
void fuzz_check_pointset_error(int rc, const aa_error *err);

#endif
