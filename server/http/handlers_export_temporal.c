/* The temporal half of the pattern exports (handlers_export_temporal.h). */
#include "handlers_export_temporal.h"

#include <string.h>

#include "codec.h"
#include "codec_temporal.h"
#include "export_temporal.h"
#include "handlers.h"
#include "pointset.h"

static void reply_phase(api_response *resp, const proto_temporal *t, const json_t *phase,
                        proto_points_format points)
{
    if (!phase) {
        api_reply_wire(resp, WIRE_INVALID_FIELD, "phase",
                       "the point formats export one phase's kernels of a temporal pattern: give "
                       "phase 0 to %zu",
                       t->count - 1);
        return;
    }
    aa_pattern p;
    aa_error err = {0};
    int rc = proto_temporal_phase_pattern(t, (size_t)json_integer_value(phase), &p, &err);
    size_t len = 0;
    char *text = rc ? NULL : proto_export_points(&p, points, &len, &err);
    if (!rc)
        aa_pattern_free(&p);
    if (!text) {
        api_reply_aa_error(resp, &err);
        return;
    }
    api_reply_owned(resp, 200, text, len);
    resp->content_type =
        points == PROTO_POINTS_JSON ? "application/json" : "text/plain; charset=utf-8";
}

static void reply_temporal(api_response *resp, const proto_temporal *t, const char *format,
                           const json_t *phase, long long job)
{
    bool hlsl = false;
    proto_export_writer writer = PROTO_EXPORT_PATTERN;
    proto_points_format points = PROTO_POINTS_UTK;
    bool jitter = proto_jitter_format_parse(format, &hlsl);
    if (!jitter && format && !proto_export_format_parse(format, &writer, &points)) {
        api_reply_wire(resp, WIRE_INVALID_FIELD, "format", "format must be %s, %s",
                       PROTO_EXPORT_FORMATS, PROTO_JITTER_FORMATS);
        return;
    }
    if (!jitter && (writer == PROTO_EXPORT_VULKAN || writer == PROTO_EXPORT_D3D12)) {
        api_reply_wire(resp, WIRE_INVALID_FIELD, "format",
                       "a temporal pattern's jitter offsets the projection, it is not a set of "
                       "programmable sample positions: export it as %s (or its frame pattern on "
                       "its own as %s)",
                       PROTO_JITTER_FORMATS, format);
        return;
    }
    if (!jitter && writer == PROTO_EXPORT_POINTS) {
        reply_phase(resp, t, phase, points);
        return;
    }
    if (phase) {
        api_reply_wire(resp, WIRE_INVALID_FIELD, "phase",
                       "phase selects the kernels a point format exports (utk, xyw, csv, "
                       "points-json)");
        return;
    }
    if (!jitter) {
        json_t *o = job > 0 ? json_pack("{s:I}", "job", (json_int_t)job) : json_object();
        if (o)
            json_object_set_new(o, "pattern", proto_encode_temporal(t));
        api_reply_json(resp, 200, o);
        return;
    }
    aa_error err = {0};
    size_t len = 0;
    char *text = proto_export_jitter_text(t, hlsl, &len, &err);
    if (!text) {
        api_reply_aa_error(resp, &err);
        return;
    }
    api_reply_owned(resp, 200, text, len);
    resp->content_type = "text/plain; charset=utf-8";
}

bool export_temporal_answer(api_response *resp, const json_t *pattern, const char *format,
                            const json_t *phase, long long job)
{
    bool hlsl;
    bool temporal = json_is_object(pattern) && json_object_get(pattern, "temporal");
    bool jitter = proto_jitter_format_parse(format, &hlsl);
    if (!temporal && !jitter && !phase)
        return false;
    if (!temporal) {
        if (jitter)
            api_reply_wire(resp, WIRE_INVALID_FIELD, "format",
                           "%s take a temporal pattern {\"temporal\": {...}}",
                           PROTO_JITTER_FORMATS);
        else
            api_reply_wire(resp, WIRE_INVALID_FIELD, "phase",
                           "phase selects a phase of a temporal pattern");
        return true;
    }
    if (phase && (!json_is_integer(phase) || json_integer_value(phase) < 0)) {
        api_reply_wire(resp, WIRE_INVALID_FIELD, "phase", "must be an integer >= 0");
        return true;
    }
    proto_temporal t;
    aa_error err = {0};
    if (proto_decode_temporal(pattern, &t, "pattern", &err)) {
        api_reply_aa_error(resp, &err);
        return true;
    }
    reply_temporal(resp, &t, format, phase, job);
    proto_temporal_free(&t);
    return true;
}
