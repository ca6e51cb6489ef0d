/* The schemas of the job envelope and of every kind's spec and result, as GET /v1/kinds serves
 * them: proto/schemas/job_envelope.json and proto/schemas/kinds/<kind>.{spec,result}.json,
 * embedded at build time. */
#ifndef AALAB_KIND_SCHEMAS_H
#define AALAB_KIND_SCHEMAS_H

#include <jansson.h>

#include "aa_core.h"
#include "job_kind.h"

/* Every kind that is not test-only has both schemas, the envelope schema exists and all of
 * them parse; else AA_EINVAL with a message naming the missing or broken file. */
int kind_schemas_check(aa_error *err);
struct job_manager;
/* The GET /v1/kinds body, encoded: {"envelope_schema", "kinds": [{"name", "summary",
 * "spec_schema", "result_schema", "examples"}, ...]} for every kind jobs runs (schemas null
 * when a kind has none: only test-only kinds may lack them). malloc'd; NULL when out of memory.
 * The schemas are embedded, so the daemon builds this once at start. */
char *kind_schemas_document(struct job_manager *jobs);

#endif
