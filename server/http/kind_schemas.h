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
/* The parsed schema at path (relative to proto/schemas), or NULL if there is none. New
 * reference. */
json_t *kind_schema_load(const char *path);
/* {"name","summary","spec_schema","result_schema","examples"} of a kind (schemas null when the
 * kind has none: only test-only kinds may lack them). */
json_t *kind_schemas_describe(const job_kind *kind);

#endif
