/* POST /v1/evaluate: {"pattern","filter"?,"acuity"?,"angles"?,"lp"?,"detail"?} -> E2 and its
 * argmax, family and cost (and per-kernel, per-angle detail on request). Identical request
 * bodies are answered from an LRU cache. Runs on the compute pool (http/compute_pool.c; cache
 * hits on the HTTP thread): a 4-sample pattern over the 36 default angles costs microseconds;
 * the size limits of the codec bound the worst case. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "codec_temporal.h"
#include "eval_cache.h"
#include "handlers.h"

static const char *const evaluate_keys[] = {"pattern", "filter", "acuity", "angles",
                                            "lp",      "detail", NULL};

/* Weights like [1e308, -1e308, 1] sum to 1 but overflow the integral: a 400 naming the kernel
 * rather than a 200 with a null E2. */
static int check_finite(const aa_pattern *p, const aa_evaluation *ev, aa_error *err)
{
    if (isfinite(ev->e2))
        return AA_OK;
    size_t bad = 0;
    for (size_t k = 0; k < ev->kernel_count; k++) {
        for (size_t i = 0; i < ev->angle_count; i++) {
            if (!isfinite(ev->e1[k * ev->angle_count + i])) {
                bad = k;
                k = ev->kernel_count;
                break;
            }
        }
    }
    char field[64];
    if (p->form == AA_FORM_MIRRORED)
        snprintf(field, sizeof field, "pattern.mirrored");
    else if (p->form == AA_FORM_TILE)
        snprintf(field, sizeof field, "pattern.tile.weights[%zu]", bad);
    else
        snprintf(field, sizeof field, "pattern.kernels[%zu]", bad);
    return aa_error_set(err, AA_ERANGE, field,
                        "the error integral overflows for this kernel (weights too large)");
}

/* Evaluate is synchronous: bound its work (kernel samples x angles; 2^23 is about half a second
 * here) so that no request holds a compute thread for long. Larger studies belong in jobs. */
#define EVALUATE_MAX_WORK (1L << 23)

static int check_work(const aa_pattern *p, const aa_acuity *a, size_t angle_count, aa_error *err)
{
    size_t angles = angle_count;
    if (!angles) {
        static _Thread_local double buf[AA_MAX_ANGLES];
        angles = aa_acuity_default_angles(a, buf, AA_MAX_ANGLES);
    }
    double work = (double)aa_pattern_total_kernel_samples(p) * (double)angles;
    if (work <= (double)EVALUATE_MAX_WORK)
        return AA_OK;
    return aa_error_set(err, AA_ERANGE, angle_count ? "angles" : "pattern",
                        "%zu kernel samples x %zu angles is more than a synchronous evaluate "
                        "does (%ld); use fewer angles or samples",
                        aa_pattern_total_kernel_samples(p), angles, EVALUATE_MAX_WORK);
}

/* A temporal pattern's work: its phase kernels and after-cut kernels, each at every angle, and
 * the flicker (N phases over the group's samples per angle). Bounded like a pattern's, with room
 * for the cut curve (N = 256 one-sample frames, K = 1024, 36 angles: 1.2e7). */
#define EVALUATE_MAX_TEMPORAL_WORK (1L << 25)

static int evaluate_temporal(const json_t *body, const json_t *pj, json_t **answer, aa_error *err)
{
    aa_filter filter;
    aa_acuity acuity;
    double *angles = NULL;
    size_t angle_count = 0;
    proto_temporal spec;
    aa_temporal t = {0};
    aa_temporal_evaluation ev = {0};
    bool have_ev = false;
    int rc = AA_OK;
    if (json_object_get(body, "lp"))
        rc = aa_error_set(err, AA_EINVAL, "lp", "lp is not computed for temporal patterns");
    if (!rc)
        rc = proto_decode_filter(json_object_get(body, "filter"), &filter, "filter", err);
    if (!rc)
        rc = proto_decode_acuity(json_object_get(body, "acuity"), &acuity, "acuity", err);
    if (!rc)
        rc = proto_decode_angles(json_object_get(body, "angles"), &angles, &angle_count, "angles",
                                 err);
    memset(&spec, 0, sizeof spec);
    if (!rc)
        rc = proto_decode_temporal(pj, &spec, "pattern", err);
    if (!rc) {
        aa_temporal_spec ts = proto_temporal_spec(&spec);
        rc = aa_temporal_build(&t, &ts, err);
        if (rc) {
            char f[sizeof err->field];
            proto_join_field(f, sizeof f, "pattern.temporal", err->field);
            memcpy(err->field, f, sizeof f);
        }
    }
    if (!rc) {
        size_t na = angle_count;
        if (!na) {
            static _Thread_local double buf[AA_MAX_ANGLES];
            na = aa_acuity_default_angles(&acuity, buf, AA_MAX_ANGLES);
        }
        size_t K = spec.cut_frames ? spec.cut_frames : 4 * t.phase_count;
        double samples = 0;
        for (size_t g = 0; g < t.group_count; g++)
            samples += (double)t.groups[g].count;
        double work = samples * (double)(2 * t.phase_count + K) * (double)na;
        if (work > (double)EVALUATE_MAX_TEMPORAL_WORK)
            rc = aa_error_set(err, AA_ERANGE, angle_count ? "angles" : "pattern.temporal",
                              "%.3g sample-angle evaluations is more than a synchronous evaluate "
                              "does (%ld); use fewer phases, frame samples, cut frames or angles",
                              work, EVALUATE_MAX_TEMPORAL_WORK);
    }
    if (!rc) {
        aa_metric_params mp = {
            .filter = &filter, .acuity = &acuity, .angles_deg = angles, .angle_count = angle_count};
        rc = aa_temporal_evaluate(&t, &mp, spec.cut_frames, &ev, err);
        have_ev = rc == AA_OK;
        if (rc && strncmp(err->field, "angles", 6)) {
            char f[sizeof err->field];
            proto_join_field(f, sizeof f, "pattern", err->field);
            memcpy(err->field, f, sizeof f);
        }
    }
    if (!rc) {
        *answer = proto_encode_temporal_evaluation(&ev, &t, &spec);
        if (*answer)
            json_object_set_new(*answer, "acuity", proto_encode_acuity_ref(&acuity));
    }
    if (have_ev)
        aa_temporal_evaluation_free(&ev);
    aa_temporal_free(&t);
    proto_temporal_free(&spec);
    free(angles);
    return rc;
}

void handle_evaluate(api_context *ctx, const api_request *req, api_response *resp)
{
    eval_cache *cache = api_context_eval_cache(ctx);
    char *hit;
    size_t hit_len;
    if (eval_cache_get(cache, req->body, req->body_len, &hit, &hit_len)) {
        api_reply_owned(resp, 200, hit, hit_len);
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
        rc = api_resolve_pattern_refs(ctx, &req->caller, body, &err);
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
    if (!rc && json_is_object(pj) && json_object_get(pj, "temporal")) {
        json_t *answer = NULL;
        rc = evaluate_temporal(body, pj, &answer, &err);
        if (rc) {
            api_reply_aa_error(resp, &err);
        } else {
            api_reply_json(resp, 200, answer);
            if (resp->status == 200 && !has_ref)
                eval_cache_put(cache, req->body, req->body_len, resp->body, resp->body_len);
        }
        json_decref(body);
        return;
    }
    /* The filter first: a "points" pattern may take its weights from it. */
    if (!rc)
        rc = proto_decode_filter(json_object_get(body, "filter"), &filter, "filter", &err);
    if (!rc)
        rc = proto_decode_pattern_filtered(pj, 0, &filter, &pattern, "pattern", &err);
    if (!rc)
        rc = proto_decode_acuity(json_object_get(body, "acuity"), &acuity, "acuity", &err);
    if (!rc)
        rc = proto_decode_angles(json_object_get(body, "angles"), &angles, &angle_count, "angles",
                                 &err);
    if (!rc)
        rc = check_work(&pattern, &acuity, angle_count, &err);
    if (!rc) {
        aa_metric_params mp = {.filter = &filter,
                               .acuity = &acuity,
                               .angles_deg = angles,
                               .angle_count = angle_count,
                               .lp = lp};
        rc = aa_evaluate(&pattern, &mp, &ev, &err);
        if (rc == AA_OK) {
            have_ev = true;
            rc = check_finite(&pattern, &ev, &err);
        } else if (err.field[0] && strncmp(err.field, "angles", 6) && strcmp(err.field, "lp") &&
                   strncmp(err.field, "pattern", 7)) {
            char f[sizeof err.field];
            proto_join_field(f, sizeof f, "pattern", err.field);
            memcpy(err.field, f, sizeof f);
        }
    }
    if (rc) {
        api_reply_aa_error(resp, &err);
    } else {
        json_t *o = proto_encode_evaluation(&ev, &pattern, detail);
        if (o)
            json_object_set_new(o, "acuity", proto_encode_acuity_ref(&acuity));
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
