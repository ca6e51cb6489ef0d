/* POST /v1/evaluate: {"pattern","filter"?,"acuity"?,"angles"?,"lp"?,"detail"?} -> E2 and its
 * argmax, family and cost (and per-kernel, per-angle detail on request). Identical request
 * bodies are answered from an LRU cache. Cache hits and evaluates of at most --inline-work
 * kernel samples x angles run on the HTTP thread (a 4-sample pattern over the 36 default angles
 * costs microseconds, less than the hand-off); larger ones, and job references, on the compute
 * pool (http/compute_pool.c; docs/http.md gives the threshold's measurement). The request is
 * decoded by proto/request_evaluate.c; the size limits of the codec bound the worst case. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "codec_temporal.h"
#include "eval_cache.h"
#include "handlers.h"
#include "request_evaluate.h"

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

/* The angles an evaluate measures: those given, else the acuity table's default set. */
static size_t evaluate_angle_count(const aa_acuity *a, size_t angle_count)
{
    if (angle_count)
        return angle_count;
    static _Thread_local double buf[AA_MAX_ANGLES];
    return aa_acuity_default_angles(a, buf, AA_MAX_ANGLES);
}

/* The work of an evaluate: kernel samples x angles. */
static double evaluate_work(const aa_pattern *p, size_t angles)
{
    return (double)aa_pattern_total_kernel_samples(p) * (double)angles;
}

static int check_work(const aa_pattern *p, double work, size_t angle_count, aa_error *err)
{
    if (work <= (double)EVALUATE_MAX_WORK)
        return AA_OK;
    return aa_error_set(err, AA_ERANGE, angle_count ? "angles" : "pattern",
                        "%zu kernel samples x %.0f angles is more than a synchronous evaluate "
                        "does (%ld); use fewer angles or samples",
                        aa_pattern_total_kernel_samples(p),
                        work / (double)aa_pattern_total_kernel_samples(p), EVALUATE_MAX_WORK);
}

/* A temporal pattern's work: its phase kernels and after-cut kernels, each at every angle, and
 * the flicker (N phases over the group's samples per angle). Bounded like a pattern's, with room
 * for the cut curve (N = 256 one-sample frames, K = 1024, 36 angles: 1.2e7). */
#define EVALUATE_MAX_TEMPORAL_WORK (1L << 25)

static int evaluate_temporal(proto_evaluate_request *rq, json_t **answer, aa_error *err)
{
    aa_temporal t = {0};
    aa_temporal_evaluation ev = {0};
    bool have_ev = false;
    int rc = proto_temporal_build(rq->spec, "pattern.temporal", &t, err);
    if (!rc) {
        size_t na = rq->angle_count;
        if (!na) {
            static _Thread_local double buf[AA_MAX_ANGLES];
            na = aa_acuity_default_angles(&rq->acuity, buf, AA_MAX_ANGLES);
        }
        size_t K = rq->spec->cut_frames ? rq->spec->cut_frames : 4 * t.phase_count;
        double samples = 0;
        for (size_t g = 0; g < t.group_count; g++)
            samples += (double)t.groups[g].count;
        double work = samples * (double)(2 * t.phase_count + K) * (double)na;
        if (work > (double)EVALUATE_MAX_TEMPORAL_WORK)
            rc = aa_error_set(err, AA_ERANGE, rq->angle_count ? "angles" : "pattern.temporal",
                              "%.3g sample-angle evaluations is more than a synchronous evaluate "
                              "does (%ld); use fewer phases, frame samples, cut frames or angles",
                              work, EVALUATE_MAX_TEMPORAL_WORK);
    }
    if (!rc) {
        aa_metric_params mp = {.filter = &rq->filter,
                               .acuity = &rq->acuity,
                               .angles_deg = rq->angles,
                               .angle_count = rq->angle_count};
        rc = aa_temporal_evaluate(&t, &mp, rq->spec->cut_frames, &ev, err);
        have_ev = rc == AA_OK;
        if (rc && strncmp(err->field, "angles", 6))
            proto_prefix_error(err, "pattern");
    }
    if (!rc) {
        *answer = proto_encode_temporal_evaluation(&ev, &t, rq->spec);
        if (*answer)
            json_object_set_new(*answer, "acuity", proto_encode_acuity_ref(&rq->acuity));
    }
    if (have_ev)
        aa_temporal_evaluation_free(&ev);
    aa_temporal_free(&t);
    return rc;
}

/* A decoded evaluate: what handle_evaluate runs at once, or hands over (api_deferred) when it
 * is too large for the HTTP thread it was decoded on. */
typedef struct evaluate_call {
    api_deferred deferred;
    eval_cache *cache;
    char *key; /* the cache key (eval_cache_user_key), owned */
    size_t key_len;
    bool cacheable;
    json_t *body;
    proto_evaluate_request rq;
} evaluate_call;

static void evaluate_call_free(api_deferred *d)
{
    evaluate_call *c = (evaluate_call *)d;
    proto_evaluate_request_free(&c->rq);
    free(c->key);
    json_decref(c->body);
    free(c);
}

static void evaluate_call_run(api_deferred *d, api_response *resp)
{
    evaluate_call *c = (evaluate_call *)d;
    aa_error err = {0};
    aa_evaluation ev;
    const proto_evaluate_request *rq = &c->rq;
    aa_metric_params mp = {.filter = &rq->filter,
                           .acuity = &rq->acuity,
                           .angles_deg = rq->angles,
                           .angle_count = rq->angle_count,
                           .lp = rq->lp};
    int rc = aa_evaluate(&rq->pattern, &mp, &ev, &err);
    bool have_ev = rc == AA_OK;
    if (rc == AA_OK) {
        rc = check_finite(&rq->pattern, &ev, &err);
    } else if (err.field[0] && strncmp(err.field, "angles", 6) && strcmp(err.field, "lp") &&
               strncmp(err.field, "pattern", 7)) {
        proto_prefix_error(&err, "pattern");
    }
    if (rc) {
        api_reply_aa_error(resp, &err);
    } else {
        json_t *o = proto_encode_evaluation(&ev, &rq->pattern, rq->detail);
        if (o)
            json_object_set_new(o, "acuity", proto_encode_acuity_ref(&rq->acuity));
        api_reply_json(resp, 200, o);
        if (resp->status == 200 && c->cacheable && c->key)
            eval_cache_put(c->cache, c->key, c->key_len, resp->body, resp->body_len);
    }
    if (have_ev)
        aa_evaluation_free(&ev);
}

/* Answers or keeps a request whose decoded form is in c: a temporal pattern is evaluated whole
 * here (its work, up to EVALUATE_MAX_TEMPORAL_WORK, is far above --inline-work: it never comes
 * here on an HTTP thread). True when resp holds the answer (c is then freed). */
static bool evaluate_answer_temporal(evaluate_call *c, api_response *resp)
{
    if (!c->rq.temporal)
        return false;
    aa_error err = {0};
    json_t *answer = NULL;
    if (evaluate_temporal(&c->rq, &answer, &err)) {
        api_reply_aa_error(resp, &err);
    } else {
        api_reply_json(resp, 200, answer);
        if (resp->status == 200 && c->cacheable && c->key)
            eval_cache_put(c->cache, c->key, c->key_len, resp->body, resp->body_len);
    }
    evaluate_call_free(&c->deferred);
    return true;
}

/* Parses, resolves references and decodes: 0 with *out set, or an error already answered in
 * resp (or needs_pool without a deferred call: a job reference or a temporal pattern on an HTTP
 * thread). */
static int evaluate_decode(api_context *ctx, const api_request *req, api_response *resp, char *key,
                           size_t key_len, evaluate_call **out)
{
    /* key is ours from here: freed on every early return, else owned by the call. */
    aa_error refs = {0};
    bool had_refs = false;
    json_t *body = api_request_body(ctx, req, resp, &refs, &had_refs);
    if (!body) {
        free(key);
        return -1;
    }
    /* A temporal pattern goes to the pool undecoded. */
    if (req->inline_work_limit && proto_evaluate_is_temporal(body)) {
        resp->needs_pool = true;
        json_decref(body);
        free(key);
        return -1;
    }
    evaluate_call *c = calloc(1, sizeof *c);
    if (!c) {
        free(key);
        json_decref(body);
        api_reply_wire(resp, WIRE_INTERNAL, "", "out of memory");
        return -1;
    }
    /* A job's best pattern changes while it runs: such answers are not cached. */
    *c = (evaluate_call){.deferred = {.run = evaluate_call_run, .free = evaluate_call_free},
                         .cache = api_context_eval_cache(ctx),
                         .key = key,
                         .key_len = key_len,
                         .cacheable = !had_refs,
                         .body = body};
    aa_error err = {0};
    if (proto_decode_evaluate_request(body, &refs, &c->rq, &err)) {
        api_reply_aa_error(resp, &err);
        evaluate_call_free(&c->deferred);
        return -1;
    }
    if (evaluate_answer_temporal(c, resp))
        return -1;
    *out = c;
    return 0;
}

/* The detail is one row per kernel and angle, about 110 bytes of JSON each: bounded so that
 * one request cannot build a 100 MB answer (256 kernels x 4,096 angles did). */
#define EVALUATE_MAX_DETAIL_ROWS 16384

static int check_detail(const aa_pattern *p, size_t angles, bool detail, aa_error *err)
{
    if (!detail)
        return AA_OK;
    double rows = (double)p->kernel_count * (double)angles;
    if (rows <= EVALUATE_MAX_DETAIL_ROWS)
        return AA_OK;
    return aa_error_set(err, AA_ERANGE, "detail",
                        "detail of %zu kernels x %zu angles is %.0f rows, more than the %d an "
                        "answer carries; ask for fewer angles, or leave detail off",
                        p->kernel_count, angles, rows, EVALUATE_MAX_DETAIL_ROWS);
}

void handle_evaluate(api_context *ctx, const api_request *req, api_response *resp)
{
    char *hit;
    size_t hit_len, key_len = 0;
    char *key = eval_cache_user_key(req->caller.uid, req->body, req->body_len, &key_len);
    if (key && eval_cache_get(api_context_eval_cache(ctx), key, key_len, &hit, &hit_len)) {
        free(key);
        api_reply_owned(resp, 200, hit, hit_len);
        return;
    }
    evaluate_call *c;
    if (evaluate_decode(ctx, req, resp, key, key_len, &c))
        return;
    aa_error err = {0};
    const proto_evaluate_request *rq = &c->rq;
    size_t angles = evaluate_angle_count(&rq->acuity, rq->angle_count);
    double work = evaluate_work(&rq->pattern, angles);
    if (check_work(&rq->pattern, work, rq->angle_count, &err) ||
        check_detail(&rq->pattern, angles, rq->detail, &err)) {
        api_reply_aa_error(resp, &err);
        evaluate_call_free(&c->deferred);
        return;
    }
    if (req->inline_work_limit && work > (double)req->inline_work_limit) {
        resp->needs_pool = true; /* decoded here, computed on the pool */
        resp->deferred = &c->deferred;
        return;
    }
    evaluate_call_run(&c->deferred, resp);
    evaluate_call_free(&c->deferred);
}
