/* libFuzzer driver for the request handler: api_handle() on a daemon context created without
 * sockets (fuzz_context.c). Input format, so that the corpus stays readable and mutations reach
 * every field:
 *   line 1: METHOD SP PATH[?QUERY]
 *   line 2: Content-Type (empty line: none)
 *   line 3: flag letters: t = via TCP, u = peer uid 1000, r = peer uid 0, h = Host 127.0.0.1,
 *           e = Host evil.example, a = Authorization with the context's token, b = a wrong one
 *   rest:   the body (bytes, may contain NUL)
 * Every answer must be a valid status with a body; errors must be {"error":{...}} JSON. */
#include "fuzz_check.h"
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <jansson.h>

#include "api.h"
#include "fuzz_context.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static api_context *ctx;
static unsigned long inputs;

/* Jobs, tiles and cache entries accumulate in the context; a fresh one every so many inputs
 * keeps the per-input cost bounded in long runs (and exercises start-up on a fresh state). */
#define FUZZ_CONTEXT_INPUTS 20000

/* Splits off one line (without '\n') into a fresh NUL-terminated string. */
static char *take_line(const uint8_t **p, size_t *n)
{
    const uint8_t *nl = memchr(*p, '\n', *n);
    size_t len = nl ? (size_t)(nl - *p) : *n;
    char *s = malloc(len + 1);
    memcpy(s, *p, len);
    s[len] = '\0';
    size_t used = nl ? len + 1 : len;
    *p += used;
    *n -= used;
    return s;
}

static void check_response(const api_response *r)
{
    FUZZ_CHECK(r->status >= 100 && r->status <= 599);
    FUZZ_CHECK(r->content_type != NULL);
    FUZZ_CHECK(r->body != NULL || r->body_len == 0);
    if (r->status >= 400 && strncmp(r->content_type, "application/json", 16) == 0) {
        json_error_t e;
        json_t *j = json_loadb(r->body, r->body_len, 0, &e);
        FUZZ_CHECK(j != NULL);
        json_t *err = json_object_get(j, "error");
        FUZZ_CHECK(json_is_object(err));
        FUZZ_CHECK(json_is_string(json_object_get(err, "code")));
        FUZZ_CHECK(json_is_string(json_object_get(err, "message")));
        json_decref(j);
    }
    /* 503/507: resources. */
    FUZZ_CHECK(r->status < 500 || r->status == 503 || r->status == 507);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (ctx && ++inputs % FUZZ_CONTEXT_INPUTS == 0) {
        fuzz_context_close();
        ctx = NULL;
    }
    if (!ctx)
        ctx = fuzz_context_open();
    const uint8_t *p = data;
    size_t n = size;
    char *line = take_line(&p, &n);
    char *ctype = take_line(&p, &n);
    char *flags = take_line(&p, &n);

    char *sp = strchr(line, ' ');
    const char *method = line;
    const char *path = "/";
    const char *query = NULL;
    if (sp) {
        *sp = '\0';
        path = sp + 1;
        char *q = strchr(sp + 1, '?');
        if (q) {
            *q = '\0';
            query = q + 1;
        }
    }
    static char auth_ok[256];
    const char *token = fuzz_context_token(ctx);
    snprintf(auth_ok, sizeof auth_ok, "Bearer %s", token ? token : "");

    /* The body is copied so that ASan catches reads past body_len. */
    char *body = n ? malloc(n) : NULL;
    if (n)
        memcpy(body, p, n);
    api_request req = {
        .method = method,
        .path = path,
        .query = query,
        .content_type = ctype[0] ? ctype : NULL,
        .host = strchr(flags, 'e')   ? "evil.example"
                : strchr(flags, 'h') ? "127.0.0.1"
                                     : NULL,
        .authorization = strchr(flags, 'a')   ? auth_ok
                         : strchr(flags, 'b') ? "Bearer x"
                                              : NULL,
        .body = body,
        .body_len = n,
        .via_tcp = strchr(flags, 't') != NULL,
        .peer_known = strchr(flags, 'u') || strchr(flags, 'r'),
        .peer_uid = strchr(flags, 'r') ? 0 : 1000,
    };
    api_response resp;
    memset(&resp, 0, sizeof resp);
    api_handle(ctx, &req, &resp);
    check_response(&resp);
    api_response_free(&resp);
    free(body);
    free(line);
    free(ctype);
    free(flags);
    return 0;
}
