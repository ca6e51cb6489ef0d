/* Spec and result of the test-only "sleep" job kind.
 * Spec: {"seconds": S (0..3600, required), "fail": bool (default false), "pattern": P?}.
 * Result: {"slept_seconds", "steps", "pattern"?} (the spec's pattern, re-encoded). */
#ifndef AALAB_PROTO_JOB_SLEEP_H
#define AALAB_PROTO_JOB_SLEEP_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_core.h"
#include "aa_pattern.h"

typedef struct proto_sleep_spec {
    double seconds;
    bool fail;
    bool have_pattern;
    aa_pattern pattern;
} proto_sleep_spec;

int proto_decode_sleep_spec(const json_t *spec, proto_sleep_spec *out, aa_error *err);
void proto_sleep_spec_free(proto_sleep_spec *s);

typedef struct proto_sleep_result {
    double slept_seconds;
    long long steps;
    bool have_pattern;
    aa_pattern pattern;
} proto_sleep_result;

/* NULL when out of memory. */
json_t *proto_encode_sleep_result(const proto_sleep_result *r);
int proto_decode_sleep_result(const json_t *j, proto_sleep_result *out, aa_error *err);
void proto_sleep_result_free(proto_sleep_result *r);

#endif
