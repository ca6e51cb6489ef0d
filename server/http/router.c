/* api_handle: access checks (TCP Host and token, who the caller is), body limit, content type,
 * then dispatch on (method, path). A pure function of the request and the daemon state. */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "handlers.h"
#include "handlers_render.h"
#include "token_store.h"

/* Host header names a loopback host: localhost, 127.x.y.z, [::1], with an optional port. */
static bool host_is_loopback(const char *host)
{
    if (!host)
        return false;
    char h[256];
    if (snprintf(h, sizeof h, "%s", host) >= (int)sizeof h)
        return false;
    if (h[0] == '[') {
        char *end = strchr(h, ']');
        if (!end || (end[1] && end[1] != ':'))
            return false;
        *end = 0;
        return !strcmp(h + 1, "::1");
    }
    char *colon = strchr(h, ':');
    if (colon) {
        for (char *p = colon + 1; *p; p++)
            if (*p < '0' || *p > '9')
                return false;
        *colon = 0;
    }
    if (!strcasecmp(h, "localhost") || !strcasecmp(h, "localhost."))
        return true;
    unsigned a, b, c, d;
    char tail;
    return sscanf(h, "%u.%u.%u.%u%c", &a, &b, &c, &d, &tail) == 4 && a == 127 && b < 256 &&
           c < 256 && d < 256;
}

/* Every TCP request but a dashboard file needs a token: the API (/v1...) never goes without. */
static bool is_static_request(const api_request *req, const char *path)
{
    bool safe = !strcmp(req->method, "GET") || !strcmp(req->method, "HEAD");
    return safe && strncmp(path, "/v1/", 4) && strcmp(path, "/v1");
}

/* The caller: SO_PEERCRED on the Unix socket (uid 0 = admin), the token's uid over TCP (never
 * admin). False for a TCP request without a valid token, or whose owner has left the socket
 * group. */
static bool resolve_caller(api_context *ctx, const api_request *req, api_caller *c)
{
    memset(c, 0, sizeof *c);
    c->uid = -1;
    if (!req->via_tcp) {
        if (req->peer_known) {
            c->uid = (long long)req->peer_uid;
            c->admin = req->peer_uid == 0;
        }
        return true;
    }
    c->via_tcp = true;
    const char *auth = req->authorization;
    if (!auth || strncasecmp(auth, "Bearer ", 7))
        return false;
    return token_store_check(api_context_tokens(ctx), auth + 7, &c->uid, &c->token_id) == AA_OK &&
           api_context_token_owner_ok(ctx, c->uid);
}

static bool is_json_type(const char *ct)
{
    if (!ct)
        return true; /* tolerated: curl --data-binary without -H */
    size_t n = strcspn(ct, ";");
    while (n && (ct[n - 1] == ' ' || ct[n - 1] == '\t'))
        n--;
    return n == strlen("application/json") && !strncasecmp(ct, "application/json", n);
}

static bool method_is(const api_request *req, const char *m)
{
    if (!strcmp(m, "GET") && !strcmp(req->method, "HEAD"))
        return true;
    return !strcmp(req->method, m);
}

typedef enum { ARG_NONE, ARG_TAIL, ARG_JOB_EXPORT, ARG_TILE } arg_kind;

/* How much body a route reads: BODY_LARGE up to --max-body (patterns, job specs, scenes),
 * BODY_SMALL up to API_SMALL_BODY (tokens, PATCH, enumerate, and every route that reads no
 * body). The HTTP layer answers 413 past the limit before buffering the rest (api_body_limit). */
typedef enum { BODY_SMALL, BODY_LARGE } body_kind;

/* One row per endpoint: its shape, its body limit, its compute class (api_classify: which
 * requests the HTTP layer runs on the compute pool), where its body may hold pattern references
 * (api_request_body resolves them) and its handler. */
typedef struct route {
    const char *method;
    const char *path; /* exact, or a prefix ending in '/' for ARG_* routes */
    arg_kind arg;
    body_kind body;
    api_request_class compute;
    api_refs refs;
    void (*plain)(api_context *, const api_request *, api_response *);
    void (*with_arg)(api_context *, const api_request *, api_response *, const char *);
} route;

/* An export decodes and writes a posted pattern of up to --max-body, an analysis sums over pairs
 * of up to 4,096 points: evaluate's class. */
#define OTHER API_CLASS_OTHER
#define EVALUATE API_CLASS_EVALUATE
#define PREDICT API_CLASS_PREDICT
#define RENDER API_CLASS_RENDER
#define SPEC API_CLASS_SPEC
#define NO_REFS API_REFS_NONE
#define REFS API_REFS_ANYWHERE
#define PATTERN_REF API_REFS_IF_PATTERN

static const route routes[] = {
    {"GET", "/v1/health", ARG_NONE, BODY_SMALL, OTHER, NO_REFS, handle_health, NULL},
    {"GET", "/v1/kinds", ARG_NONE, BODY_SMALL, OTHER, NO_REFS, handle_kinds, NULL},
    {"GET", "/v1/presets", ARG_NONE, BODY_SMALL, OTHER, NO_REFS, handle_presets_list, NULL},
    {"GET", "/v1/presets/", ARG_TAIL, BODY_SMALL, OTHER, NO_REFS, NULL, handle_preset_get},
    {"GET", "/v1/filters", ARG_NONE, BODY_SMALL, OTHER, NO_REFS, handle_filters, NULL},
    {"GET", "/v1/acuity", ARG_NONE, BODY_SMALL, OTHER, NO_REFS, handle_acuity, NULL},
    {"POST", "/v1/evaluate", ARG_NONE, BODY_LARGE, EVALUATE, PATTERN_REF, handle_evaluate, NULL},
    {"POST", "/v1/analyze", ARG_NONE, BODY_LARGE, EVALUATE, PATTERN_REF, handle_analyze, NULL},
    {"POST", "/v1/jobs", ARG_NONE, BODY_LARGE, SPEC, REFS, handle_jobs_post, NULL},
    {"GET", "/v1/jobs", ARG_NONE, BODY_SMALL, OTHER, NO_REFS, handle_jobs_list, NULL},
    {"GET", "/v1/jobs/", ARG_TAIL, BODY_SMALL, OTHER, NO_REFS, NULL, handle_job_get},
    {"DELETE", "/v1/jobs/", ARG_TAIL, BODY_SMALL, OTHER, NO_REFS, NULL, handle_job_delete},
    {"PATCH", "/v1/jobs/", ARG_TAIL, BODY_SMALL, OTHER, NO_REFS, NULL, handle_job_patch},
    {"GET", "/v1/usage", ARG_NONE, BODY_SMALL, OTHER, NO_REFS, handle_usage, NULL},
    {"POST", "/v1/families/enumerate", ARG_NONE, BODY_SMALL, OTHER, NO_REFS, handle_enumerate,
     NULL},
    {"GET", "/v1/patterns/", ARG_JOB_EXPORT, BODY_SMALL, OTHER, NO_REFS, NULL, handle_export},
    {"POST", "/v1/patterns/export", ARG_NONE, BODY_LARGE, EVALUATE, REFS, handle_export_post, NULL},
    {"POST", "/v1/render", ARG_NONE, BODY_LARGE, RENDER, REFS, handle_render, NULL},
    {"POST", "/v1/predict", ARG_NONE, BODY_LARGE, PREDICT, REFS, handle_predict, NULL},
    {"GET", "/v1/tiles/", ARG_TILE, BODY_SMALL, OTHER, NO_REFS, NULL, handle_tile},
    {"POST", "/v1/tokens", ARG_NONE, BODY_SMALL, OTHER, NO_REFS, handle_tokens_post, NULL},
    {"GET", "/v1/tokens", ARG_NONE, BODY_SMALL, OTHER, NO_REFS, handle_tokens_list, NULL},
    {"DELETE", "/v1/tokens/", ARG_TAIL, BODY_SMALL, OTHER, NO_REFS, NULL, handle_token_delete},
};

/* Does path match the route's shape? Fills arg (a segment without '/'). */
static bool route_matches(const route *r, const char *path, char *arg, size_t cap)
{
    if (r->arg == ARG_NONE)
        return !strcmp(path, r->path);
    size_t n = strlen(r->path);
    if (strncmp(path, r->path, n))
        return false;
    const char *rest = path + n;
    size_t len = strcspn(rest, "/");
    if (len == 0 || len >= cap)
        return false;
    if (r->arg == ARG_JOB_EXPORT) {
        if (strcmp(rest + len, "/export"))
            return false;
    } else if (rest[len]) {
        return false;
    }
    if (r->arg == ARG_TILE && (len <= 4 || strcmp(rest + len - 4, ".png")))
        return false;
    memcpy(arg, rest, len);
    arg[len] = 0;
    return true;
}

/* The route for (method, path) exactly (HEAD is not GET here), or NULL. */
static const route *find_route(const char *method, const char *path)
{
    char arg[256];
    for (size_t i = 0; method && path && i < sizeof routes / sizeof routes[0]; i++)
        if (!strcmp(routes[i].method, method) && route_matches(&routes[i], path, arg, sizeof arg))
            return &routes[i];
    return NULL;
}

size_t api_body_limit(const char *method, const char *path, size_t max_body)
{
    const route *r = find_route(method, path);
    if (r && r->body == BODY_LARGE)
        return max_body;
    return API_SMALL_BODY < max_body ? API_SMALL_BODY : max_body;
}

api_request_class api_classify(const char *method, const char *path, size_t body_len)
{
    const route *r = find_route(method, path);
    if (r && r->compute == API_CLASS_SPEC)
        return body_len > API_SPEC_INLINE_BYTES ? API_CLASS_PREDICT : API_CLASS_OTHER;
    return r ? r->compute : API_CLASS_OTHER;
}

void api_handle(api_context *ctx, const api_request *in, api_response *resp)
{
    memset(resp, 0, sizeof *resp);
    const aalab_config *cfg = api_context_config(ctx);
    const char *path = in->path ? in->path : "";
    api_request caller_req = *in;
    const api_request *req = &caller_req;
    if (in->via_tcp) {
        /* DNS rebinding: a browser page on another origin resolving to 127.0.0.1 still sends
         * its own Host. */
        if (!host_is_loopback(req->host)) {
            api_reply_wire(resp, WIRE_FORBIDDEN, "", "Host must be a loopback name");
            return;
        }
    }
    /* The socket follows the group too: a peer removed from the socket's group (or whose
     * account is gone) loses a keep-alive connection it opened before (cached 2 s). */
    if (!in->via_tcp && in->peer_known && !api_context_socket_peer_ok(ctx, in->peer_uid)) {
        api_reply_wire(resp, WIRE_FORBIDDEN, "",
                       "uid %lld may no longer connect to this socket (not in its group)",
                       (long long)in->peer_uid);
        return;
    }
    if (!resolve_caller(ctx, in, &caller_req.caller) && !is_static_request(in, path)) {
        api_reply_wire(resp, WIRE_UNAUTHORIZED, "",
                       "this request needs 'Authorization: Bearer <token>' with a valid token of "
                       "a socket group member (issue one on the Unix socket: aalab token)");
        return;
    }
    size_t limit = api_body_limit(req->method, path, cfg->max_body);
    if (req->body_len > limit) {
        api_reply_wire(resp, WIRE_PAYLOAD_TOO_LARGE, "",
                       "the body exceeds %zu bytes, this endpoint's limit%s", limit,
                       limit == cfg->max_body ? " (--max-body)" : "");
        return;
    }
    bool path_known = false;
    char arg[256];
    for (size_t i = 0; i < sizeof routes / sizeof routes[0]; i++) {
        const route *r = &routes[i];
        if (!route_matches(r, path, arg, sizeof arg))
            continue;
        path_known = true;
        if (!method_is(req, r->method))
            continue;
        if ((!strcmp(r->method, "POST") || !strcmp(r->method, "PATCH")) &&
            !is_json_type(req->content_type)) {
            api_reply_wire(resp, WIRE_UNSUPPORTED_MEDIA_TYPE, "",
                           "send the body as Content-Type: application/json");
            return;
        }
        caller_req.refs = r->refs;
        if (r->arg == ARG_NONE)
            r->plain(ctx, req, resp);
        else
            r->with_arg(ctx, req, resp, arg);
        return;
    }
    if (path_known) {
        api_reply_wire(resp, WIRE_METHOD_NOT_ALLOWED, "", "%s is not allowed on this path",
                       req->method);
        return;
    }
    if (req->via_tcp && is_static_request(req, path)) {
        handle_static(ctx, req, resp);
        return;
    }
    api_reply_wire(resp, WIRE_NOT_FOUND, "", "no such endpoint");
}
