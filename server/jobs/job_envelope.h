/* The envelope of a job submission: keys every kind accepts beside its own, about how the
 * job is kept rather than what it computes ("visibility", "pinned", "priority"). They are
 * taken out of the spec before the kind parses it and stored in their own columns. */
#ifndef AALAB_JOB_ENVELOPE_H
#define AALAB_JOB_ENVELOPE_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_error.h"

typedef struct job_envelope {
    const char *visibility; /* "team" (default) or "private" (static strings) */
    bool pinned;            /* exempt from retention */
    int priority;           /* -10..10, default 0 */
} job_envelope;

/* Validates the envelope keys of spec (400-style errors naming the field) and returns a copy
 * of spec without them in *rest (new reference). */
int job_envelope_take(const json_t *spec, job_envelope *env, json_t **rest, aa_error *err);

#endif
