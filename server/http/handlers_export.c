/* Pattern exports, formatted by the proto codec (proto/pointset.h) that the client shares:
 *   GET  /v1/patterns/{job}/export?format=F   a job's best pattern
 *   POST /v1/patterns/export {"pattern","format","filter"?}   any pattern: a preset, a posted
 *        pattern of any form, a job reference {"job": ID}
 * F: json (aalab's pattern JSON, the default), utk, xyw, csv (text/plain point sets with the
 * "# aalab-pattern" header that reads back exactly), bin (UTK binary, the header as a trailer),
 * rps (PSA raw float32, application/octet-stream), points-json (the point-set JSON), vulkan,
 * d3d12, metal (programmable sample positions, or representable false with a reason); a temporal
 * pattern's exports (json, jitter-c, jitter-hlsl, one phase in the point formats) are
 * handlers_export_temporal.c's. Formatting is bounded by the codec's limits (4096 tile
 * samples): no handler blocks. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "export_temporal.h"
#include "handlers.h"
#include "handlers_export_temporal.h"
#include "job_access.h"
#include "job_manager.h"
#include "pointset.h"
#include "request_export.h"

/* Answers p in format (already validated); job > 0 is named in the json answer. */
static void reply_export(api_response *resp, const aa_pattern *p, proto_export_writer writer,
                         proto_points_format points, long long job)
{
    if (writer == PROTO_EXPORT_PATTERN) {
        json_t *o = job > 0 ? json_pack("{s:I}", "job", (json_int_t)job) : json_object();
        if (o)
            json_object_set_new(o, "pattern", proto_encode_pattern(p));
        api_reply_json(resp, 200, o);
        return;
    }
    if (writer == PROTO_EXPORT_METAL) {
        api_reply_json(resp, 200, proto_export_metal(p));
        return;
    }
    if (writer != PROTO_EXPORT_POINTS) {
        api_reply_json(resp, 200, proto_export_gpu(p, writer == PROTO_EXPORT_D3D12));
        return;
    }
    size_t len = 0;
    aa_error err = {0};
    char *text = proto_export_points(p, points, &len, &err);
    if (!text) {
        api_reply_aa_error(resp, &err);
        return;
    }
    api_reply_owned(resp, 200, text, len);
    resp->content_type = points == PROTO_POINTS_JSON             ? "application/json"
                         : proto_points_format_is_binary(points) ? "application/octet-stream"
                                                                 : "text/plain; charset=utf-8";
}

void handle_export(api_context *ctx, const api_request *req, api_response *resp,
                   const char *id_text)
{
    char fmt[16], ph[24];
    const char *format = api_query_get(req->query, "format", fmt, sizeof fmt);
    const char *phase_text = api_query_get(req->query, "phase", ph, sizeof ph);
    aa_error err = {0};
    proto_export_query q;
    if (proto_decode_export_query(format, phase_text, &q, &err)) {
        proto_export_query_free(&q);
        api_reply_aa_error(resp, &err);
        return;
    }
    long long id = api_parse_job_id(id_text);
    const char *why = "no such job";
    /* Someone else's private job is "no such job", as in GET /v1/jobs/{id}. */
    json_t *pj = job_access_check(job_manager_store(api_context_jobs(ctx)), &req->caller, id, NULL)
                     ? job_manager_best_pattern(api_context_jobs(ctx), id, &why)
                     : NULL;
    if (!pj) {
        proto_export_query_free(&q);
        api_reply_wire(resp, strcmp(why, "no such job") ? WIRE_CONFLICT : WIRE_NOT_FOUND, "id",
                       "job %.40s: %s", id_text, why);
        return;
    }
    /* A temporal job's best and the jitter formats are export_temporal_answer's. */
    bool answered = export_temporal_answer(resp, pj, format, q.phase, id);
    proto_export_query_free(&q);
    if (answered) {
        json_decref(pj);
        return;
    }
    aa_pattern p;
    /* Exactly as stored; normalised only if its weights drifted off a sum of 1. */
    int rc = proto_decode_pattern(pj, 0, &p, "pattern", &err);
    if (rc)
        rc = proto_decode_pattern(pj, AA_PATTERN_NORMALIZE, &p, "pattern", &err);
    json_decref(pj);
    if (rc) {
        api_reply_wire(resp, WIRE_INTERNAL, err.field, "the job's pattern does not decode: %s",
                       err.message);
        return;
    }
    reply_export(resp, &p, q.writer, q.points, id);
    aa_pattern_free(&p);
}

void handle_export_post(api_context *ctx, const api_request *req, api_response *resp)
{
    aa_error refs = {0};
    json_t *body = api_request_body(ctx, req, resp, &refs, NULL);
    if (!body)
        return;
    aa_error err = {0};
    proto_export_request rq;
    int rc = proto_decode_export_request(body, &refs, &rq, &err);
    /* A temporal pattern, a jitter format or a phase: export_temporal_answer's. */
    if (!rc && rq.temporal) {
        export_temporal_answer(resp, rq.pattern, rq.format, rq.phase, 0);
        json_decref(body);
        return;
    }
    json_decref(body);
    if (rc) {
        api_reply_aa_error(resp, &err);
        return;
    }
    reply_export(resp, &rq.decoded, rq.writer, rq.points, 0);
    aa_pattern_free(&rq.decoded);
}
