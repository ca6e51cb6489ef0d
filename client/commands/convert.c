/* aalab convert PATTERN [--format json|utk|xyw|csv|bin|rps|points-json|vulkan|d3d12|metal]
 *               [-o FILE]
 * A preset, a pattern file or a point-set file in another format, written locally by the
 * codec the daemon uses (proto/pointset.h), so the bytes are those of POST /v1/patterns/export;
 * job:ID asks the daemon (POST /v1/patterns/export). */
#include "commands.h"

#include <stdlib.h>
#include <string.h>

#include "../exit_codes.h"
#include "../pattern_source.h"
#include "codec.h"
#include "pointset.h"

int convert_text(const json_t *pattern, const char *format, char **text, size_t *len, char *err,
                 size_t errcap)
{
    proto_export_writer writer;
    proto_points_format points = PROTO_POINTS_UTK;
    *text = NULL;
    if (!proto_export_format_parse(format, &writer, &points)) {
        snprintf(err, errcap, "--format wants %s", PROTO_EXPORT_FORMATS);
        return -1;
    }
    aa_pattern p;
    aa_error e = {0};
    if (proto_decode_pattern(pattern, 0, &p, "pattern", &e)) {
        snprintf(err, errcap, "field %s: %s", e.field, e.message);
        return -1;
    }
    json_t *doc = NULL;
    if (writer == PROTO_EXPORT_PATTERN)
        doc = json_pack("{s:o}", "pattern", proto_encode_pattern(&p));
    else if (writer == PROTO_EXPORT_METAL)
        doc = proto_export_metal(&p);
    else if (writer != PROTO_EXPORT_POINTS)
        doc = proto_export_gpu(&p, writer == PROTO_EXPORT_D3D12);
    else
        *text = proto_export_points(&p, points, len, &e);
    aa_pattern_free(&p);
    if (doc) { /* as the daemon encodes its answers */
        *text = json_dumps(doc, JSON_COMPACT | JSON_ENCODE_ANY);
        *len = *text ? strlen(*text) : 0;
        json_decref(doc);
    }
    if (!*text) {
        snprintf(err, errcap, "out of memory");
        return -1;
    }
    return 0;
}

int cmd_convert(cli_session *s)
{
    const cli_args *a = s->args;
    char err[600];
    json_t *pattern;
    if (pattern_argument_load(a->target, a, &pattern, NULL, err, sizeof err)) {
        fprintf(s->err, "aalab: %s\n", err);
        return EXIT_USAGE;
    }
    if (json_object_get(pattern, "job")) { /* only the daemon knows a job's pattern */
        json_t *body = json_pack("{s:o,s:s}", "pattern", pattern, "format", a->format);
        http_response resp;
        int code = cli_call_raw_body(s, "POST", "/v1/patterns/export", body, &resp);
        json_decref(body);
        if (code != EXIT_OK)
            return code;
        code = write_command_output(s, resp.body, resp.len);
        http_response_free(&resp);
        return code;
    }
    char *text;
    size_t len = 0;
    int rc = convert_text(pattern, a->format, &text, &len, err, sizeof err);
    json_decref(pattern);
    if (rc) {
        fprintf(s->err, "aalab: %s: %s\n", a->target, err);
        return EXIT_USAGE;
    }
    int code = write_command_output(s, text, len);
    free(text);
    return code;
}
