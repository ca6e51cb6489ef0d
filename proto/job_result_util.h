/* Pieces the job result codecs share: E2 values that may be null (NaN), patterns, method
 * names, and the "best"/"e2" pair every optimizer result carries. */
#ifndef AALAB_PROTO_JOB_RESULT_UTIL_H
#define AALAB_PROTO_JOB_RESULT_UTIL_H

#include <jansson.h>

#include "aa_core.h"
#include "aa_optimizer.h"
#include "aa_pattern.h"

/* A number, or null for NaN (proto_real writes non-finite values as null). */
int proto_result_real(const json_t *obj, const char *key, double *out, aa_error *err);
int proto_result_integer(const json_t *obj, const char *key, long long *out, aa_error *err);
/* An encoded pattern at obj[key] (must be present unless optional; null counts as absent when
 * optional). *present tells whether one was decoded. */
int proto_result_pattern(const json_t *obj, const char *key, bool optional, aa_pattern *out,
                         bool *present, aa_error *err);
int proto_result_method(const json_t *obj, const char *key, aa_optimize_method *out, aa_error *err);

#endif
