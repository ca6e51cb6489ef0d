/* The envelope of a job spec: the keys the job manager owns, whatever the kind. They are taken
 * out of the spec before the kind parses it, so a kind sees only its own fields:
 *   "priority":   integer -10..10, default 0: order among the owner's own waiting jobs (higher
 *                 first); it never moves a job ahead of another user's (fair share decides that);
 *   "visibility": "team" (default: every member of the socket group reads the job) or
 *                 "private" (its owner and root only);
 *   "pinned":     boolean, default false: exempt from the retention policy (--keep-days);
 *   "label":      string of at most JOB_LABEL_MAX bytes, optional: a name for people (the job
 *                 list shows it). */
#ifndef AALAB_JOB_ENVELOPE_H
#define AALAB_JOB_ENVELOPE_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_core.h"

#define JOB_PRIORITY_MIN (-10)
#define JOB_PRIORITY_MAX 10
#define JOB_LABEL_MAX 200

typedef struct job_envelope {
    int priority;
    bool private_job; /* visibility "private" */
    bool pinned;
    char label[JOB_LABEL_MAX + 1]; /* "" when absent */
    bool slurm;                    /* executor "slurm" */
} job_envelope;

/* Validates the envelope keys of spec (AA_EINVAL naming the field) and returns in *kind_spec a
 * new copy of spec without them and without "kind" (the caller decrefs it). "kind" itself is
 * checked by the job manager, which knows the table of kinds. */
int job_envelope_take(const json_t *spec, job_envelope *env, json_t **kind_spec, aa_error *err);
const char *job_envelope_visibility(const job_envelope *env); /* "team" or "private" */
const char *job_envelope_executor(const job_envelope *env);   /* "local" or "slurm" */

#endif
