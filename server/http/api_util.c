/* Response helpers and small request utilities shared by the handlers. */
#define _GNU_SOURCE
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "handlers.h"

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
        resp->status = 500;
        resp->body = strdup("{\"error\":{\"code\":\"internal\",\"message\":\"cannot encode the "
                            "answer\",\"field\":\"\"}}");
    }
    resp->body_len = resp->body ? strlen(resp->body) : 0;
}

void api_reply_error(api_response *resp, int status, const char *code, const char *field,
                     const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    json_t *e = json_pack("{s:{s:s,s:s,s:s}}", "error", "code", code, "message", msg, "field",
                          field ? field : "");
    if (!e) /* message not valid UTF-8 (echoed input): drop it */
        e = json_pack("{s:{s:s,s:s,s:s}}", "error", "code", code, "message", "invalid input",
                      "field", "");
    api_reply_json(resp, status, e);
    resp->status = status;
}

json_t *api_parse_body(const api_request *req, api_response *resp)
{
    if (!req->body_len) {
        api_reply_error(resp, 400, "invalid_json", "", "the request body is empty");
        return NULL;
    }
    json_error_t je;
    json_t *j = json_loadb(req->body, req->body_len, JSON_REJECT_DUPLICATES, &je);
    if (!j) {
        api_reply_error(resp, 400, "invalid_json", "", "invalid JSON at line %d column %d: %s",
                        je.line, je.column, je.text);
        return NULL;
    }
    if (!json_is_object(j)) {
        json_decref(j);
        api_reply_error(resp, 400, "invalid_json", "", "the request body must be a JSON object");
        return NULL;
    }
    return j;
}

int api_reject_unknown(const json_t *obj, const char *const *allowed, const char *prefix,
                       api_response *resp)
{
    const char *key;
    json_t *v;
    json_object_foreach((json_t *)obj, key, v)
    {
        bool ok = false;
        for (size_t i = 0; allowed[i] && !ok; i++)
            ok = !strcmp(key, allowed[i]);
        if (!ok) {
            char field[128];
            snprintf(field, sizeof field, "%s%s%.80s", prefix ? prefix : "",
                     prefix && *prefix ? "." : "", key);
            api_reply_error(resp, 400, "invalid_field", field, "unknown field");
            return -1;
        }
    }
    return 0;
}

void api_reply_aa_error(api_response *resp, const aa_error *err)
{
    switch (err->code) {
    case AA_ENOMEM:
        api_reply_error(resp, 503, "unavailable", err->field, "%s", err->message);
        break;
    case AA_ERANGE:
        api_reply_error(resp, 400, "out_of_range", err->field, "%s", err->message);
        break;
    default:
        api_reply_error(resp, 400, "invalid_field", err->field, "%s",
                        err->message[0] ? err->message : "invalid input");
        break;
    }
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
