/* Data a job's stored JSON does not keep because it follows from the rest: the
 * kernels_expanded of encoded patterns (proto_encode_pattern), re-derived on read; and the
 * summary columns (best E2, family) the job list reads instead of parsing best. */
#ifndef AALAB_JOB_DERIVED_H
#define AALAB_JOB_DERIVED_H

#include <stdbool.h>

#include <jansson.h>

/* A copy of v without the derived keys of the encoded patterns inside it, or NULL when v has
 * none (store v as it is then). v is not modified (live state other threads copy). */
json_t *job_derived_stripped(const json_t *v);
/* Adds kernels_expanded back to every encoded pattern inside v that lacks it, by decoding the
 * pattern and re-encoding it. Patterns that do not decode are left as they are. */
void job_derived_restore(json_t *v);

/* Of a job's best ({"pattern", "e2"}, job_kind.h): best.e2 if it is a number (else NaN) and
 * best.pattern.family (else NULL). */
double job_derived_best_e2(const json_t *best);
const char *job_derived_family(const json_t *best);

#endif
