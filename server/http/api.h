/* The request handler as a pure function of (method, path, headers, body) plus the daemon's
 * state; the libmicrohttpd layer (http/mhd_adapter.c) only fills api_request, calls
 * api_handle() and sends the api_response. Unit tests and fuzz drivers call api_handle()
 * directly, without a socket. */
#ifndef AALAB_API_H
#define AALAB_API_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>

#include <jansson.h>

#include "wire_error.h"

typedef struct api_context api_context; /* daemon state: config, job pool, store, caches */

/* Who is asking, resolved once per request by api_handle() (the router). On the Unix socket the
 * SO_PEERCRED uid, admin when it is 0; on TCP the uid the bearer token was issued to, never
 * admin (a token of root's reads and cancels only root's own private jobs). */
typedef struct api_caller {
    long long uid;      /* -1 unknown */
    bool admin;         /* root on the Unix socket: sees and cancels every job */
    bool via_tcp;       /* admitted by a bearer token */
    long long token_id; /* that token, 0 on the Unix socket */
} api_caller;

/* Where a route's body may hold pattern references {"job": ID}, a column of the route table:
 * the router copies it into api_request.refs and api_request_body (pattern_refs.h) resolves
 * them. A reference is a "pattern" value or an element of "patterns", at any depth. */
typedef enum {
    API_REFS_NONE,       /* the route takes no references */
    API_REFS_ANYWHERE,   /* every reference in the body */
    API_REFS_IF_PATTERN, /* the same, when the top-level "pattern" is one (a plain body is not
                          * walked) */
} api_refs;

typedef struct api_request {
    const char *method;        /* "GET", "POST", ... */
    const char *path;          /* URL path without query, e.g. "/v1/jobs/12" */
    const char *query;         /* raw query string without '?', or NULL */
    const char *content_type;  /* or NULL */
    const char *host;          /* Host header, or NULL */
    const char *authorization; /* Authorization header, or NULL */
    const char *body;          /* not NUL-terminated; may be NULL when body_len == 0 */
    size_t body_len;
    bool via_tcp;    /* arrived on the TCP listener (static files, token and Host checks) */
    bool peer_known; /* peer_uid is valid (SO_PEERCRED on the Unix socket) */
    uid_t peer_uid;
    api_caller caller; /* set by api_handle() before a handler runs; callers leave it zero */
    /* The owner uid of the connecting socket of a loopback TCP client (sock_diag). For limits
     * and fair share only: ownership on TCP does not come from it. */
    bool tcp_peer_known;
    uid_t tcp_peer_uid;
    /* 0: the handler may do all the work the codec allows (a compute-pool thread, a test).
     * Otherwise the request runs on an HTTP thread: a handler whose estimated work (kernel
     * samples x angles for evaluate) is larger, or that would read the job store, answers
     * nothing and sets api_response.needs_pool, and the caller hands the request to the pool. */
    size_t inline_work_limit;
    api_refs refs; /* set by api_handle() from the route table; callers leave it zero */
} api_request;

/* The rest of a handler's work, decoded on an HTTP thread and found too large to finish there
 * (api_request.inline_work_limit): the caller runs it on the compute pool, then frees it. */
typedef struct api_deferred api_deferred;
typedef struct api_response api_response;
struct api_deferred {
    void (*run)(api_deferred *d, api_response *resp);
    void (*free)(api_deferred *d);
};

struct api_response {
    int status;
    const char *content_type; /* static string */
    char *body;               /* malloc'd, owned by the response */
    size_t body_len;
    int retry_after;           /* seconds, > 0 adds Retry-After */
    const char *cache_control; /* static string or NULL */
    bool needs_pool;           /* no answer: too much work for inline_work_limit */
    api_deferred *deferred;    /* with needs_pool: the work left, or NULL to run it all again */
};

/* Requests the HTTP layer runs on the compute pool rather than on an HTTP thread: a column of
 * the route table, which api_classify reads. API_CLASS_PREDICT runs in the evaluate share but
 * is never answered from the evaluate cache. A job spec (the table's API_CLASS_SPEC, which
 * api_classify never returns) is parsed on the HTTP thread up to API_SPEC_INLINE_BYTES and in
 * the evaluate share above: parsing 2 MiB of JSON would hold an HTTP thread for milliseconds,
 * 64 KiB parse in well under one. */
typedef enum {
    API_CLASS_OTHER,
    API_CLASS_EVALUATE,
    API_CLASS_RENDER,
    API_CLASS_PREDICT,
    API_CLASS_SPEC
} api_request_class;
#define API_SPEC_INLINE_BYTES (64u << 10)
api_request_class api_classify(const char *method, const char *path, size_t body_len);

/* The body a route may have: --max-body (max_body) for the routes that take patterns, job
 * specs or scenes, API_SMALL_BODY for the rest (tokens, PATCH of a job, enumerate, and routes
 * without a body). The HTTP layer answers 413 beyond it before buffering more. */
#define API_SMALL_BODY 4096
size_t api_body_limit(const char *method, const char *path, size_t max_body);

void api_handle(api_context *ctx, const api_request *req, api_response *resp);
void api_response_free(api_response *resp);

/* Handler helpers. api_reply_json steals body. */
void api_reply_json(api_response *resp, int status, json_t *body);
/* A JSON body already encoded (a cached answer); takes ownership of the malloc'd body. */
void api_reply_owned(api_response *resp, int status, char *body, size_t body_len);
/* An error answer from the one table (proto/wire_error.h): its status, wire code and
 * Retry-After, with field (the JSON path of the offending input, "" if none) and a message. */
void api_reply_wire(api_response *resp, proto_wire_error e, const char *field, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#endif
