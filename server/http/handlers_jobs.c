/* POST /v1/jobs (202 + id), GET /v1/jobs, GET /v1/jobs/{id}, DELETE /v1/jobs/{id} (cancel:
 * owner or root only). A private job is 404 to everyone but its owner and root (job_access.h). */
#include <string.h>

#include "handlers.h"
#include "job_access.h"
#include "job_manager.h"

#define JOB_LIST_LIMIT 500

void handle_jobs_post(api_context *ctx, const api_request *req, api_response *resp)
{
    json_t *body = api_parse_body(req, resp);
    if (!body)
        return;
    if (!job_visibility_valid(json_object_get(body, JOB_VISIBILITY_KEY))) {
        json_decref(body);
        api_reply_error(resp, 400, "invalid_field", JOB_VISIBILITY_KEY,
                        "visibility must be \"team\" or \"private\"");
        return;
    }
    aa_error err = {0};
    long long id = 0;
    int rc = api_resolve_pattern_refs(ctx, &req->caller, body, &err);
    if (!rc)
        rc = job_manager_submit(api_context_jobs(ctx), body, req->caller.uid, &id, &err);
    json_decref(body);
    if (rc == JM_EQUEUE_FULL) {
        api_reply_error(resp, 429, "queue_full", "", "%s", err.message);
        resp->retry_after = 5;
    } else if (rc == JM_EQUOTA) {
        api_reply_error(resp, 429, "too_many_requests", "", "%s", err.message);
        resp->retry_after = 10;
    } else if (rc == JM_ESTORE) {
        api_reply_error(resp, 503, "unavailable", "", "%s", err.message);
        resp->retry_after = 30;
    } else if (rc) {
        api_reply_aa_error(resp, &err);
    } else {
        json_t *job = job_manager_get(api_context_jobs(ctx), id);
        if (!job)
            job = json_pack("{s:I,s:s}", "id", (json_int_t)id, "state", "queued");
        else
            json_object_set_new(job, JOB_VISIBILITY_KEY, json_string(job_visibility(job)));
        api_reply_json(resp, 202, job);
    }
}

/* GET /v1/jobs?limit=N&state=S: newest first, at most N (default and max 500). */
void handle_jobs_list(api_context *ctx, const api_request *req, api_response *resp)
{
    char buf[32];
    int limit = JOB_LIST_LIMIT, state = -1;
    const char *v = api_query_get(req->query, "limit", buf, sizeof buf);
    if (v) {
        long long n = api_parse_job_id(v); /* a positive decimal */
        if (n <= 0 || n > JOB_LIST_LIMIT) {
            api_reply_error(resp, 400, "invalid_field", "limit", "limit must be 1..%d",
                            JOB_LIST_LIMIT);
            return;
        }
        limit = (int)n;
    }
    v = api_query_get(req->query, "state", buf, sizeof buf);
    if (v) {
        for (int i = 0; i < JOB_STATE_COUNT && state < 0; i++)
            if (!strcmp(v, job_state_name((job_state)i)))
                state = i;
        if (state < 0) {
            api_reply_error(resp, 400, "invalid_field", "state",
                            "state must be queued, running, done, failed, cancelled or "
                            "interrupted");
            return;
        }
    }
    json_t *jobs = job_manager_list(api_context_jobs(ctx), limit, state);
    /* Until the store filters by viewer in SQL: drop what the caller may not read. A list entry
     * without "visibility" (the spec is not in it) is looked up in full (55 ms for 500 rows). */
    for (size_t i = json_array_size(jobs); i-- > 0;) {
        json_t *o = json_array_get(jobs, i);
        json_t *full = json_object_get(o, JOB_VISIBILITY_KEY)
                           ? json_incref(o)
                           : job_manager_get(api_context_jobs(ctx),
                                             json_integer_value(json_object_get(o, "id")));
        if (!full || !job_readable(&req->caller, full))
            json_array_remove(jobs, i);
        else
            json_object_set_new(o, JOB_VISIBILITY_KEY, json_string(job_visibility(full)));
        json_decref(full);
    }
    api_reply_json(resp, 200, json_pack("{s:o}", "jobs", jobs));
    resp->cache_control = "no-store";
}

void handle_job_get(api_context *ctx, const api_request *req, api_response *resp,
                    const char *id_text)
{
    long long id = api_parse_job_id(id_text);
    json_t *job = id > 0 ? job_manager_get(api_context_jobs(ctx), id) : NULL;
    if (!job || !job_readable(&req->caller, job)) {
        json_decref(job);
        api_reply_error(resp, 404, "not_found", "id", "no job %.40s", id_text);
        return;
    }
    json_object_set_new(job, JOB_VISIBILITY_KEY, json_string(job_visibility(job)));
    api_reply_json(resp, 200, job);
    resp->cache_control = "no-store";
}

void handle_job_delete(api_context *ctx, const api_request *req, api_response *resp,
                       const char *id_text)
{
    long long id = api_parse_job_id(id_text);
    if (id <= 0) {
        api_reply_error(resp, 404, "not_found", "id", "no job %.40s", id_text);
        return;
    }
    /* Checked here, not only in the manager: a TCP caller with a token of root's is uid 0
     * there but has no root powers. */
    json_t *job = job_manager_get(api_context_jobs(ctx), id);
    bool readable = job && job_readable(&req->caller, job);
    bool owned = job && job_owned_by(&req->caller, job);
    json_decref(job);
    if (!readable) {
        api_reply_error(resp, 404, "not_found", "id", "no job %lld", id);
        return;
    }
    const char *state = NULL;
    int rc = owned ? job_manager_cancel(api_context_jobs(ctx), id,
                                        req->caller.admin ? 0 : req->caller.uid, &state)
                   : JM_EFORBIDDEN;
    switch (rc) {
    case JM_OK:
        api_reply_json(resp, 202,
                       json_pack("{s:I,s:s,s:b}", "id", (json_int_t)id, "state", state,
                                 "cancel_requested", 1));
        break;
    case JM_ENOENT:
        api_reply_error(resp, 404, "not_found", "id", "no job %lld", id);
        break;
    case JM_EFORBIDDEN:
        api_reply_error(resp, 403, "forbidden", "", "only the job's owner or root may cancel it");
        break;
    default:
        api_reply_error(resp, 409, "conflict", "", "job %lld has already finished", id);
        break;
    }
}
