/* Response helpers and small request utilities shared by the handlers. */
#define _GNU_SOURCE
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "codec.h"
#include "handlers.h"
#include "job_manager.h"

void api_response_free(api_response *resp)
{
    free(resp->body);
    resp->body = NULL;
    resp->body_len = 0;
}

void api_reply_owned(api_response *resp, int status, char *body, size_t body_len)
{
    free(resp->body);
    resp->status = status;
    resp->content_type = "application/json";
    resp->body = body;
    resp->body_len = body_len;
}

void api_reply_json(api_response *resp, int status, json_t *body)
{
    free(resp->body);
    resp->status = status;
    resp->content_type = "application/json";
    resp->body = body ? json_dumps(body, JSON_COMPACT | JSON_ENCODE_ANY) : NULL;
    json_decref(body);
    if (!resp->body) {
        const proto_wire_row *row = proto_wire_row_of(WIRE_INTERNAL);
        resp->status = row->status;
        if (asprintf(&resp->body,
                     "{\"error\":{\"code\":\"%s\",\"message\":\"cannot encode the answer\","
                     "\"field\":\"\"}}",
                     row->code) < 0)
            resp->body = NULL;
    }
    resp->body_len = resp->body ? strlen(resp->body) : 0;
}

void api_reply_wire(api_response *resp, proto_wire_error e, const char *field, const char *fmt, ...)
{
    const proto_wire_row *row = proto_wire_row_of(e);
    char msg[512], text[512], name[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    /* Messages may echo input (jansson's "near '...'"): every answer is UTF-8 all the same. */
    json_t *doc = json_pack("{s:{s:s,s:s,s:s}}", "error", "code", row->code, "message",
                            proto_utf8_prefix(text, sizeof text, msg, sizeof msg), "field",
                            proto_utf8_prefix(name, sizeof name, field ? field : "", sizeof name));
    api_reply_json(resp, row->status, doc); /* NULL (out of memory): a 500 answer */
    resp->retry_after = row->retry_after;
}

json_t *api_parse_body(const api_request *req, api_response *resp)
{
    if (!req->body_len) {
        api_reply_wire(resp, WIRE_INVALID_JSON, "", "the request body is empty");
        return NULL;
    }
    json_error_t je;
    json_t *j = json_loadb(req->body, req->body_len, JSON_REJECT_DUPLICATES, &je);
    if (!j) {
        api_reply_wire(resp, WIRE_INVALID_JSON, "", "invalid JSON at line %d column %d: %s",
                       je.line, je.column, je.text);
        return NULL;
    }
    if (!json_is_object(j)) {
        json_decref(j);
        api_reply_wire(resp, WIRE_INVALID_JSON, "", "the request body must be a JSON object");
        return NULL;
    }
    return j;
}

int api_reject_unknown(const json_t *obj, const char *const *allowed, const char *prefix,
                       api_response *resp)
{
    aa_error err = {0};
    if (!proto_check_keys(obj, allowed, &err, prefix))
        return 0;
    api_reply_aa_error(resp, &err);
    return -1;
}

void api_reply_aa_error(api_response *resp, const aa_error *err)
{
    api_reply_wire(resp, proto_wire_error_of_aa(err->code), err->field, "%s",
                   err->message[0] ? err->message : aa_strerror(err->code));
}

void api_reply_service_error(api_response *resp, int rc, const aa_error *err)
{
    const proto_service_row *row = proto_service_row_of(rc);
    if (!row) {
        api_reply_aa_error(resp, err);
        return;
    }
    api_reply_wire(resp, row->error, row->field, "%s",
                   err->message[0] ? err->message : row->message);
}

long long api_parse_job_id(const char *s)
{
    if (!s || !*s || *s == '0' || strlen(s) > 18)
        return -1;
    long long v = 0;
    for (const char *p = s; *p; p++) {
        if (*p < '0' || *p > '9')
            return -1;
        v = v * 10 + (*p - '0');
    }
    return v;
}

const char *api_query_get(const char *query, const char *key, char *buf, size_t cap)
{
    size_t klen = strlen(key);
    for (const char *p = query; p && *p;) {
        const char *amp = strchr(p, '&');
        size_t len = amp ? (size_t)(amp - p) : strlen(p);
        if (len > klen && !strncmp(p, key, klen) && p[klen] == '=') {
            size_t vlen = len - klen - 1;
            if (vlen >= cap)
                vlen = cap - 1;
            memcpy(buf, p + klen + 1, vlen);
            buf[vlen] = 0;
            return buf;
        }
        p = amp ? amp + 1 : NULL;
    }
    return NULL;
}
