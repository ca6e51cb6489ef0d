/* POST /v1/evaluate: {"pattern","filter"?,"acuity"?,"angles"?,"lp"?,"detail"?} -> E2 and its
 * argmax, family and cost (and per-kernel, per-angle detail on request). Identical request
 * bodies are answered from an LRU cache. Runs on the HTTP thread: a 4-sample pattern over the
 * 36 default angles costs microseconds; the size limits of the codec bound the worst case. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "eval_cache.h"
#include "handlers.h"

static const char *const evaluate_keys[] = {"pattern", "filter", "acuity", "angles",
                                            "lp",      "detail", NULL};

void handle_evaluate(api_context *ctx, const api_request *req, api_response *resp)
{
    eval_cache *cache = api_context_eval_cache(ctx);
    char *hit;
    size_t hit_len;
    if (eval_cache_get(cache, req->body, req->body_len, &hit, &hit_len)) {
        resp->status = 200;
        resp->content_type = "application/json";
        resp->body = hit;
        resp->body_len = hit_len;
        return;
    }
    json_t *body = api_parse_body(req, resp);
    if (!body)
        return;
    if (api_reject_unknown(body, evaluate_keys, "", resp)) {
        json_decref(body);
        return;
    }
    aa_error err = {0};
    aa_pattern pattern;
    memset(&pattern, 0, sizeof pattern);
    aa_filter filter;
    aa_acuity acuity;
    double *angles = NULL;
    size_t angle_count = 0;
    double lp = 0;
    bool detail = false;
    aa_evaluation ev;
    bool have_ev = false;
    json_t *pj = json_object_get(body, "pattern");
    json_t *dj = json_object_get(body, "detail");
    json_t *lj = json_object_get(body, "lp");
    int rc = AA_OK;
    /* A job's best pattern changes while it runs: such answers are not cached. */
    bool has_ref = pj && json_is_object(pj) && json_object_get(pj, "job");
    if (has_ref)
        rc = api_resolve_pattern_refs(ctx, body, &err);
    pj = json_object_get(body, "pattern");
    if (!rc && !pj)
        rc = aa_error_set(&err, AA_EINVAL, "pattern", "pattern is required");
    if (!rc && dj && !json_is_boolean(dj))
        rc = aa_error_set(&err, AA_EINVAL, "detail", "must be true or false");
    detail = dj && json_is_true(dj);
    if (!rc && lj) {
        if (!json_is_number(lj) || !(json_number_value(lj) >= 1) ||
            !isfinite(json_number_value(lj)))
            rc = aa_error_set(&err, AA_EINVAL, "lp", "must be a number >= 1");
        else
            lp = json_number_value(lj);
    }
    if (!rc)
        rc = proto_decode_pattern(pj, 0, &pattern, "pattern", &err);
    if (!rc)
        rc = proto_decode_filter(json_object_get(body, "filter"), &filter, "filter", &err);
    if (!rc)
        rc = proto_decode_acuity(json_object_get(body, "acuity"), &acuity, "acuity", &err);
    if (!rc)
        rc = proto_decode_angles(json_object_get(body, "angles"), &angles, &angle_count, "angles",
                                 &err);
    if (!rc) {
        aa_metric_params mp = {.filter = &filter,
                               .acuity = &acuity,
                               .angles_deg = angles,
                               .angle_count = angle_count,
                               .lp = lp};
        rc = aa_evaluate(&pattern, &mp, &ev, &err);
        if (rc == AA_OK)
            have_ev = true;
        else if (err.field[0] && strncmp(err.field, "angles", 6) && strcmp(err.field, "lp")) {
            char f[sizeof err.field];
            proto_join_field(f, sizeof f, "pattern", err.field);
            memcpy(err.field, f, sizeof f);
        }
    }
    if (rc) {
        api_reply_aa_error(resp, &err);
    } else {
        json_t *o = proto_encode_evaluation(&ev, &pattern, detail);
        api_reply_json(resp, 200, o);
        if (resp->status == 200 && !has_ref)
            eval_cache_put(cache, req->body, req->body_len, resp->body, resp->body_len);
    }
    if (have_ev)
        aa_evaluation_free(&ev);
    aa_pattern_free(&pattern);
    free(angles);
    json_decref(body);
}
