/* GET /v1/kinds: {"envelope_schema", "kinds": [{"name", "summary", "spec_schema",
 * "result_schema", "examples"}, ...]} for every kind this daemon runs. */
#include "handlers.h"
#include "job_manager.h"
#include "kind_schemas.h"

void handle_kinds(api_context *ctx, const api_request *req, api_response *resp)
{
    (void)req;
    json_t *kinds = json_array();
    size_t count;
    const job_kind *table = job_kinds_table(&count);
    for (size_t k = 0; k < count; k++)
        if (job_manager_kind(api_context_jobs(ctx), table[k].name))
            json_array_append_new(kinds, kind_schemas_describe(&table[k]));
    json_t *envelope = kind_schema_load("job_envelope.json");
    api_reply_json(resp, 200,
                   json_pack("{s:o,s:o}", "envelope_schema", envelope ? envelope : json_null(),
                             "kinds", kinds));
}
