/* Who may read a job. A job is "team" (default: everyone who may reach the API, i.e. the socket
 * group and their tokens) or "private" (its owner and root on the Unix socket only). Reads the
 * job JSON: "owner_uid" and "visibility" (until the store carries the column, the value kept in
 * the stored spec). */
#ifndef AALAB_JOB_ACCESS_H
#define AALAB_JOB_ACCESS_H

#include <stdbool.h>

#include <jansson.h>

#include "api.h"

#define JOB_VISIBILITY_KEY "visibility"

/* "team" or "private" (a missing or unknown value reads as "team"). */
const char *job_visibility(const json_t *job);
bool job_readable(const api_caller *caller, const json_t *job);
/* The owner, or the admin. */
bool job_owned_by(const api_caller *caller, const json_t *job);
/* NULL or "team"/"private": valid. */
bool job_visibility_valid(const json_t *value);

#endif
