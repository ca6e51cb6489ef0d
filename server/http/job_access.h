/* Who may read and change a job. A job is "team" (default: everyone who may reach the API, i.e.
 * the socket group and their tokens) or "private" (its owner and root on the Unix socket only).
 * Decided from the store's indexed owner and visibility columns: no job JSON is loaded. */
#ifndef AALAB_JOB_ACCESS_H
#define AALAB_JOB_ACCESS_H

#include <stdbool.h>

#include <jansson.h>

#include "api.h"
#include "job_store.h"

#define JOB_VISIBILITY_KEY "visibility"

/* True if job id exists and the caller may read it (someone else's private job reads as absent);
 * *owns (optional) then says whether the caller may change it: its owner, or the admin. */
bool job_access_check(job_store *st, const api_caller *caller, long long id, bool *owns);
/* NULL or "team"/"private": valid. */
bool job_visibility_valid(const json_t *value);

#endif
