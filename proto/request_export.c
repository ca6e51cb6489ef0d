/* The pattern exports' request decoders (request_export.h). */
#include "request_export.h"

#include <stdlib.h>
#include <string.h>

#include "export_temporal.h"

static const char *const export_keys[] = {"pattern", "format", "filter", "phase", NULL};

int proto_decode_export_query(const char *format, const char *phase, proto_export_query *out,
                              aa_error *err)
{
    bool hlsl;
    *out = (proto_export_query){
        .format = format, .writer = PROTO_EXPORT_PATTERN, .points = PROTO_POINTS_UTK};
    if (format && !proto_export_format_parse(format, &out->writer, &out->points) &&
        !proto_jitter_format_parse(format, &hlsl))
        return aa_error_set(err, AA_EINVAL, "format", "format must be %s, %s", PROTO_EXPORT_FORMATS,
                            PROTO_JITTER_FORMATS);
    if (phase) {
        char *end = NULL;
        long long pv = strtoll(phase, &end, 10);
        out->phase = end != phase && !*end ? json_integer((json_int_t)pv) : json_string(phase);
    }
    return AA_OK;
}

void proto_export_query_free(proto_export_query *q)
{
    json_decref(q->phase);
    q->phase = NULL;
}

int proto_decode_export_request(const json_t *body, const aa_error *refs, proto_export_request *out,
                                aa_error *err)
{
    memset(out, 0, sizeof *out);
    out->writer = PROTO_EXPORT_PATTERN;
    out->points = PROTO_POINTS_UTK;
    int rc = proto_check_keys(body, export_keys, err, "");
    if (rc)
        return rc;
    const json_t *fj = json_object_get(body, "format");
    if (!fj)
        return aa_error_set(err, AA_EINVAL, "format", "is required: %s", PROTO_EXPORT_FORMATS);
    if (!json_is_string(fj))
        return aa_error_set(err, AA_EINVAL, "format", "must be %s", PROTO_EXPORT_FORMATS);
    if (!json_object_get(body, "pattern"))
        return aa_error_set(err, AA_EINVAL, "pattern", "pattern is required");
    if (refs && refs->code) {
        *err = *refs;
        return err->code;
    }
    out->format = json_string_value(fj);
    out->pattern = json_object_get(body, "pattern");
    out->phase = json_object_get(body, "phase");
    bool hlsl;
    out->temporal = (json_is_object(out->pattern) && json_object_get(out->pattern, "temporal")) ||
                    proto_jitter_format_parse(out->format, &hlsl) || out->phase;
    if (out->temporal)
        return AA_OK;
    if (!proto_export_format_parse(out->format, &out->writer, &out->points))
        return aa_error_set(err, AA_EINVAL, "format", "must be %s, %s", PROTO_EXPORT_FORMATS,
                            PROTO_JITTER_FORMATS);
    rc = proto_decode_filter(json_object_get(body, "filter"), &out->filter, "filter", err);
    if (!rc)
        rc = proto_decode_pattern_filtered(out->pattern, 0, &out->filter, &out->decoded, "pattern",
                                           err);
    return rc;
}
