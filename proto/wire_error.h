/* The one table of error answers: every error the daemon reports, as HTTP status, wire code
 * (the "code" of {"error":{"code","message","field"}}, proto/schemas/error.json) and
 * Retry-After. The daemon answers from it and a client may map codes back with it.
 *
 * Rows are causes, not codes: two causes may share a wire code and differ in status or
 * Retry-After (a job quota and a compute share are both "too_many_requests"). Retry-After is
 * given exactly when waiting can help (429 and 503): the request was valid and the resource it
 * waits for is being given back. */
#ifndef AALAB_PROTO_WIRE_ERROR_H
#define AALAB_PROTO_WIRE_ERROR_H

#include <stddef.h>

#include "aa_core.h"

/* X(name, HTTP status, wire code, Retry-After seconds or 0) */
#define PROTO_WIRE_ERRORS(X)                                                                       \
    X(WIRE_INVALID_JSON, 400, "invalid_json", 0)                                                   \
    X(WIRE_INVALID_FIELD, 400, "invalid_field", 0)                                                 \
    X(WIRE_OUT_OF_RANGE, 400, "out_of_range", 0)                                                   \
    X(WIRE_BAD_REQUEST, 400, "bad_request", 0) /* malformed request line */                        \
    X(WIRE_UNAUTHORIZED, 401, "unauthorized", 0)                                                   \
    X(WIRE_FORBIDDEN, 403, "forbidden", 0)                                                         \
    X(WIRE_QUOTA_EXCEEDED, 403, "quota_exceeded", 0) /* stored bytes: waiting frees none */        \
    X(WIRE_NOT_FOUND, 404, "not_found", 0)                                                         \
    X(WIRE_METHOD_NOT_ALLOWED, 405, "method_not_allowed", 0)                                       \
    X(WIRE_CONFLICT, 409, "conflict", 0)                                                           \
    X(WIRE_PAYLOAD_TOO_LARGE, 413, "payload_too_large", 0)                                         \
    X(WIRE_UNSUPPORTED_MEDIA_TYPE, 415, "unsupported_media_type", 0)                               \
    /* a synchronous computation ran out of its wall-time budget: the same request would too */    \
    X(WIRE_OVER_TIME_BUDGET, 422, "out_of_range", 0)                                               \
    /* a job ran past its max_seconds (in the job's "error", not an HTTP answer) */                \
    X(WIRE_TIME_LIMIT, 422, "time_limit", 0)                                                       \
    X(WIRE_QUEUE_FULL, 429, "queue_full", 5)                                                       \
    X(WIRE_JOB_QUOTA, 429, "too_many_requests", 10)        /* queued jobs per user */              \
    X(WIRE_TOO_MANY_REQUESTS, 429, "too_many_requests", 1) /* connections, compute share */        \
    X(WIRE_INTERNAL, 500, "internal", 0)                                                           \
    X(WIRE_NOT_IMPLEMENTED, 501, "not_implemented", 0)                                             \
    /* An allocation failed: the request was valid and memory comes back as running work           \
     * finishes, so it is a transient refusal (503, retry) rather than a fault (500). */           \
    X(WIRE_OUT_OF_MEMORY, 503, "unavailable", 5)                                                   \
    X(WIRE_STORE_UNAVAILABLE, 503, "unavailable", 30) /* the job or token store failed */          \
    X(WIRE_BUSY, 503, "unavailable", 1) /* compute queue or connections full, shutting down */     \
    /* executor "slurm" while Slurm is not configured (--slurm-shared-dir) or not answering */     \
    X(WIRE_SLURM_UNAVAILABLE, 503, "slurm_unavailable", 30)                                        \
    X(WIRE_HTTP_VERSION, 505, "http_version_not_supported", 0)

/* X(HTTP status, reason phrase): every status of the rows above (RFC 9110). */
#define PROTO_HTTP_STATUSES(X)                                                                     \
    X(400, "Bad Request")                                                                          \
    X(401, "Unauthorized")                                                                         \
    X(403, "Forbidden")                                                                            \
    X(404, "Not Found")                                                                            \
    X(405, "Method Not Allowed")                                                                   \
    X(409, "Conflict")                                                                             \
    X(413, "Content Too Large")                                                                    \
    X(415, "Unsupported Media Type")                                                               \
    X(422, "Unprocessable Content")                                                                \
    X(429, "Too Many Requests")                                                                    \
    X(500, "Internal Server Error")                                                                \
    X(501, "Not Implemented")                                                                      \
    X(503, "Service Unavailable")                                                                  \
    X(505, "HTTP Version Not Supported")

/* X(engine code of aa_error.h, row): every AA_E* code has one. */
#define PROTO_WIRE_ENGINE_ERRORS(X)                                                                \
    X(AA_EINVAL, WIRE_INVALID_FIELD)                                                               \
    X(AA_ERANGE, WIRE_OUT_OF_RANGE)                                                                \
    X(AA_ENOMEM, WIRE_OUT_OF_MEMORY)                                                               \
    X(AA_ECANCELED, WIRE_OVER_TIME_BUDGET) /* only a budget callback cancels a request */

#define PROTO_WIRE_AS_ENUM(name, status, code, retry_after) name,
typedef enum proto_wire_error {
    PROTO_WIRE_ERRORS(PROTO_WIRE_AS_ENUM) WIRE_ERROR_COUNT
} proto_wire_error;
#undef PROTO_WIRE_AS_ENUM

typedef struct proto_wire_row {
    const char *name; /* "WIRE_QUEUE_FULL" */
    int status;
    const char *code;
    int retry_after; /* seconds, 0 = no Retry-After */
} proto_wire_row;

/* The row of e (the WIRE_INTERNAL row for a value outside the enum). */
const proto_wire_row *proto_wire_row_of(proto_wire_error e);
/* The row for an engine code; WIRE_INTERNAL for a code the engine does not define. */
proto_wire_error proto_wire_error_of_aa(int aa_code);
/* The reason phrase of a status in PROTO_HTTP_STATUSES; "Error" for any other. */
const char *proto_http_reason(int status);
/* The first row with this status and wire code, for a client reading an answer; NULL if none. */
const proto_wire_row *proto_wire_row_find(int status, const char *code);

/* The engine codes the table maps, in table order (for tests and documentation). */
typedef struct proto_wire_engine_row {
    const char *aa_name; /* "AA_EINVAL" */
    int aa_code;
    proto_wire_error error;
} proto_wire_engine_row;
extern const proto_wire_engine_row proto_wire_engine_rows[];
extern const size_t proto_wire_engine_row_count;

#endif
