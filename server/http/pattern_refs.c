/* Pattern references (pattern_refs.h): found by one walk over the parsed body, resolved from the
 * job store with the caller's access rights. */
#include "pattern_refs.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api_context.h"
#include "handlers.h"
#include "job_access.h"
#include "job_manager.h"

/* ctx NULL: only finds references (1 for the first), replacing nothing. */
static int resolve_one(api_context *ctx, const api_caller *caller, json_t *parent_obj,
                       const char *key, json_t *arr, size_t index, json_t *v, const char *field,
                       aa_error *err)
{
    if (!json_is_object(v) || !json_object_get(v, "job"))
        return AA_OK;
    if (!ctx)
        return 1;
    char jfield[128];
    snprintf(jfield, sizeof jfield, "%s.job", field);
    if (json_object_size(v) != 1)
        return aa_error_set(err, AA_EINVAL, jfield, "a pattern reference is exactly {\"job\": ID}");
    json_t *idj = json_object_get(v, "job");
    long long id = -1;
    if (json_is_integer(idj))
        id = json_integer_value(idj);
    else if (json_is_string(idj)) {
        const char *s = json_string_value(idj);
        char *end;
        errno = 0;
        id = strtoll(s, &end, 10);
        if (errno || end == s || *end)
            id = -1;
    }
    if (id <= 0)
        return aa_error_set(err, AA_EINVAL, jfield, "not a job id");
    /* A private job of someone else reads as no job at all: its existence is not revealed. */
    const char *why = "no such job";
    job_manager *jm = api_context_jobs(ctx);
    json_t *p = job_access_check(job_manager_store(jm), caller, id, NULL)
                    ? job_manager_best_pattern(jm, id, &why)
                    : NULL;
    if (!p)
        return aa_error_set(err, AA_EINVAL, jfield, "job %lld: %s", id, why);
    if (parent_obj)
        json_object_set_new(parent_obj, key, p);
    else
        json_array_set_new(arr, index, p);
    return AA_OK;
}

static int resolve_walk(api_context *ctx, const api_caller *caller, json_t *node, const char *path,
                        int depth, aa_error *err)
{
    if (depth > 32)
        return AA_OK;
    char sub[256];
    if (json_is_object(node)) {
        const char *key;
        json_t *v;
        void *tmp;
        json_object_foreach_safe(node, tmp, key, v)
        {
            snprintf(sub, sizeof sub, "%s%s%s", path, *path ? "." : "", key);
            int rc = AA_OK;
            if (!strcmp(key, "pattern")) {
                rc = resolve_one(ctx, caller, node, key, NULL, 0, v, sub, err);
            } else if (!strcmp(key, "patterns") && json_is_array(v)) {
                for (size_t i = 0; i < json_array_size(v) && !rc; i++) {
                    char el[280];
                    snprintf(el, sizeof el, "%s[%zu]", sub, i);
                    rc = resolve_one(ctx, caller, NULL, NULL, v, i, json_array_get(v, i), el, err);
                }
            }
            if (rc)
                return rc;
            json_t *now = json_object_get(node, key);
            if ((rc = resolve_walk(ctx, caller, now, sub, depth + 1, err)))
                return rc;
        }
    } else if (json_is_array(node)) {
        for (size_t i = 0; i < json_array_size(node); i++) {
            snprintf(sub, sizeof sub, "%s[%zu]", path, i);
            int rc = resolve_walk(ctx, caller, json_array_get(node, i), sub, depth + 1, err);
            if (rc)
                return rc;
        }
    }
    return AA_OK;
}

int api_resolve_pattern_refs(api_context *ctx, const api_caller *caller, json_t *body,
                             aa_error *err)
{
    return resolve_walk(ctx, caller, body, "", 0, err);
}

/* Does body hold a reference where the route declares them? */
static bool has_refs(api_refs refs, json_t *body)
{
    if (refs == API_REFS_IF_PATTERN) {
        json_t *pj = json_object_get(body, "pattern");
        return json_is_object(pj) && json_object_get(pj, "job");
    }
    return refs == API_REFS_ANYWHERE && resolve_walk(NULL, NULL, body, "", 0, NULL);
}

json_t *api_request_body(api_context *ctx, const api_request *req, api_response *resp,
                         aa_error *refs_err, bool *had_refs)
{
    json_t *body = api_parse_body(req, resp);
    bool found = body && has_refs(req->refs, body);
    if (had_refs)
        *had_refs = found;
    if (!found)
        return body;
    if (req->inline_work_limit) {
        json_decref(body);
        resp->needs_pool = true;
        return NULL;
    }
    api_resolve_pattern_refs(ctx, &req->caller, body, refs_err);
    return body;
}
