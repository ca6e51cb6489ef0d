/* POST /v1/jobs (202 + id), GET /v1/jobs, GET /v1/jobs/{id}, DELETE /v1/jobs/{id} (cancel, or
 * with ?purge=1 delete the record), PATCH /v1/jobs/{id} ({"pinned": b}), GET /v1/usage.
 * Changing a job is for its owner and root; a private job is 404 to everyone else
 * (job_access.h). */
#include <string.h>

#include "handlers.h"
#include "token_store.h"
#include "job_access.h"
#include "job_manager.h"

#define JOB_LIST_LIMIT 500

/* The caller as the job manager counts it: 0 (root's powers) only for an admin. The handlers
 * check ownership first, so a TCP caller holding a token of root's (uid 0, not admin) reaches
 * the manager only for root's own jobs. */
static long long manager_caller(const api_request *req)
{
    return req->caller.admin ? 0 : req->caller.uid;
}

/* 1 if the caller may change job id (its owner, or the admin), 0 if it may only read it, -1
 * after a 404 (it may not even read it). */
static int caller_owns(api_context *ctx, const api_request *req, api_response *resp, long long id)
{
    bool owns = false;
    if (!job_access_check(job_manager_store(api_context_jobs(ctx)), &req->caller, id, &owns)) {
        api_reply_wire(resp, WIRE_NOT_FOUND, "id", "no job %lld", id > 0 ? id : 0);
        return -1;
    }
    return owns;
}

void handle_jobs_post(api_context *ctx, const api_request *req, api_response *resp)
{
    /* Refused before parsing: a big spec costs its parse and, stored, its bytes. */
    size_t max_spec = api_context_config(ctx)->max_spec_bytes;
    if (max_spec && req->body_len > max_spec) {
        api_reply_wire(resp, WIRE_PAYLOAD_TOO_LARGE, "",
                       "a job spec may have at most %zu bytes (--max-spec-bytes); this one has "
                       "%zu",
                       max_spec, req->body_len);
        return;
    }
    aa_error err = {0};
    json_t *body = api_request_body(ctx, req, resp, &err, NULL);
    if (!body)
        return;
    long long id = 0;
    int rc = err.code;
    if (!rc)
        rc = job_manager_submit(api_context_jobs(ctx), body, req->caller.uid, &id, &err);
    json_decref(body);
    if (rc) {
        api_reply_service_error(resp, rc, &err);
    } else {
        json_t *job = job_manager_get(api_context_jobs(ctx), id);
        if (!job)
            job = json_pack("{s:I,s:s}", "id", (json_int_t)id, "state", "queued");
        api_reply_json(resp, 202, job);
    }
}

/* GET /v1/jobs?limit=N&state=S&kind=K: newest first, at most N (default and max 500). */
void handle_jobs_list(api_context *ctx, const api_request *req, api_response *resp)
{
    char buf[32];
    int limit = JOB_LIST_LIMIT, state = -1;
    const char *v = api_query_get(req->query, "limit", buf, sizeof buf);
    if (v) {
        long long n = api_parse_job_id(v); /* a positive decimal */
        if (n <= 0 || n > JOB_LIST_LIMIT) {
            api_reply_wire(resp, WIRE_INVALID_FIELD, "limit", "limit must be 1..%d",
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
            api_reply_wire(resp, WIRE_INVALID_FIELD, "state",
                           "state must be queued, running, done, failed, cancelled or "
                           "interrupted");
            return;
        }
    }
    v = api_query_get(req->query, "kind", buf, sizeof buf);
    if (v && !job_manager_kind(api_context_jobs(ctx), v)) {
        char names[256];
        job_manager_kind_names(api_context_jobs(ctx), names, sizeof names);
        api_reply_wire(resp, WIRE_INVALID_FIELD, "kind",
                       "unknown job kind \"%.31s\"; known kinds: %s", v, names);
        return;
    }
    /* Root on the socket sees every job; others see team jobs and their own private ones. */
    long long uid = req->caller.uid;
    job_store_filter f = {.limit = limit,
                          .state = state,
                          .kind = v,
                          .viewer = req->caller.admin ? JOB_VIEWER_ALL
                                    : uid >= 0        ? uid
                                                      : -2};
    json_t *jobs = job_manager_list(api_context_jobs(ctx), &f);
    api_reply_json(resp, 200, json_pack("{s:o}", "jobs", jobs));
    resp->cache_control = "no-store";
}

void handle_job_get(api_context *ctx, const api_request *req, api_response *resp,
                    const char *id_text)
{
    long long id = api_parse_job_id(id_text);
    json_t *job =
        caller_owns(ctx, req, resp, id) >= 0 ? job_manager_get(api_context_jobs(ctx), id) : NULL;
    if (!job) {
        if (!resp->status)
            api_reply_wire(resp, WIRE_NOT_FOUND, "id", "no job %lld", id);
        return;
    }
    api_reply_json(resp, 200, job);
    resp->cache_control = "no-store";
}

static void handle_job_purge(api_context *ctx, const api_request *req, api_response *resp,
                             long long id, const char *purge)
{
    if (strcmp(purge, "1")) {
        api_reply_wire(resp, WIRE_INVALID_FIELD, "purge", "purge must be 0 or 1");
        return;
    }
    int owned = caller_owns(ctx, req, resp, id);
    if (owned < 0)
        return;
    /* Refusals come with their message and are answered from their rows. */
    aa_error err = {0};
    int rc =
        owned ? job_manager_purge(api_context_jobs(ctx), id, manager_caller(req), &err)
              : aa_error_set(&err, JM_EFORBIDDEN, "", "only the job's owner or root may purge it");
    if (rc)
        api_reply_service_error(resp, rc, &err);
    else
        api_reply_json(resp, 200, json_pack("{s:I,s:b}", "id", (json_int_t)id, "purged", 1));
}

/* PATCH /v1/jobs/{id} {"pinned": bool}: a pinned job is exempt from retention. */
void handle_job_patch(api_context *ctx, const api_request *req, api_response *resp,
                      const char *id_text)
{
    long long id = api_parse_job_id(id_text);
    job_store *st = job_manager_store(api_context_jobs(ctx));
    int owned = caller_owns(ctx, req, resp, id);
    if (owned < 0)
        return;
    if (!owned) {
        api_reply_wire(resp, WIRE_FORBIDDEN, "", "only the job's owner or root may change it");
        return;
    }
    json_t *body = api_parse_body(req, resp);
    if (!body)
        return;
    static const char *const allowed[] = {"pinned", NULL};
    int rc;
    aa_error err = {0};
    json_t *pinned = json_object_get(body, "pinned");
    if (!api_reject_unknown(body, allowed, "", resp)) {
        if (!json_is_boolean(pinned)) {
            api_reply_wire(resp, WIRE_INVALID_FIELD, "pinned", "pinned must be true or false");
        } else if ((rc = job_store_set_pinned(st, id, json_is_true(pinned), &err)) != AA_OK) {
            api_reply_service_error(resp, rc, &err);
        } else {
            json_t *changed = job_manager_get(api_context_jobs(ctx), id);
            if (changed)
                api_reply_json(resp, 200, changed);
            else
                api_reply_wire(resp, WIRE_NOT_FOUND, "id", "no job %lld", id);
        }
    }
    json_decref(body);
}

void handle_job_delete(api_context *ctx, const api_request *req, api_response *resp,
                       const char *id_text)
{
    long long id = api_parse_job_id(id_text);
    if (id <= 0) {
        api_reply_wire(resp, WIRE_NOT_FOUND, "id", "no job %.40s", id_text);
        return;
    }
    char buf[8];
    const char *purge = api_query_get(req->query, "purge", buf, sizeof buf);
    if (purge && strcmp(purge, "0")) {
        handle_job_purge(ctx, req, resp, id, purge);
        return;
    }
    int owned = caller_owns(ctx, req, resp, id);
    if (owned < 0)
        return;
    const char *state = NULL;
    aa_error err = {0};
    int rc =
        owned ? job_manager_cancel(api_context_jobs(ctx), id, manager_caller(req), &state, &err)
              : aa_error_set(&err, JM_EFORBIDDEN, "", "only the job's owner or root may cancel it");
    if (rc)
        api_reply_service_error(resp, rc, &err);
    else
        api_reply_json(resp, 202,
                       json_pack("{s:I,s:s,s:b}", "id", (json_int_t)id, "state", state,
                                 "cancel_requested", 1));
}

/* GET /v1/usage: the caller's stored job bytes against the quota; root also sees every user. */
void handle_usage(api_context *ctx, const api_request *req, api_response *resp)
{
    job_store *st = job_manager_store(api_context_jobs(ctx));
    long long uid = req->caller.uid;
    job_store_usage u = {0};
    if (uid >= 0 && job_store_usage_of(st, uid, &u) != AA_OK) {
        api_reply_wire(resp, WIRE_STORE_UNAVAILABLE, "", "the job store cannot be read");
        return;
    }
    u.limit = api_context_config(ctx)->user_store_bytes;
    json_t *o =
        json_pack("{s:o,s:I,s:I,s:I,s:f}", "uid", uid >= 0 ? json_integer(uid) : json_null(),
                  "store_bytes", (json_int_t)u.bytes, "store_limit", (json_int_t)u.limit, "jobs",
                  (json_int_t)u.jobs, "keep_days", api_context_config(ctx)->keep_days);
    /* Tokens count in the caller's quota: held against --user-tokens. */
    json_object_set_new(
        o, "tokens", json_integer(uid >= 0 ? token_store_count(api_context_tokens(ctx), uid) : 0));
    json_object_set_new(o, "tokens_limit", json_integer(api_context_config(ctx)->user_tokens));
    if (req->caller.admin)
        json_object_set_new(o, "users", job_store_usage_all(st));
    api_reply_json(resp, 200, o);
    resp->cache_control = "no-store";
}
