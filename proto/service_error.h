/* The one table of the service's own error codes (beside the engine's AA_E*, aa_error.h): job
 * manager, job store, tokens, cluster and tiles. Each subsystem has its own range, so a code
 * names its subsystem and no two mean different things. A subsystem's header takes its codes
 * from here (no second definition), and the HTTP layer answers a code from its row.
 *
 * X(name, value, wire row (wire_error.h), field, default message)
 * The field names the request field the refusal is about ("" = the daemon's state); the
 * default message is used when the code comes without one. */
#ifndef AALAB_PROTO_SERVICE_ERROR_H
#define AALAB_PROTO_SERVICE_ERROR_H

#include <stddef.h>

#include "wire_error.h"

/* Ranges: job manager -1001..-1999, job store -2001..-2999, cluster -3001..-3999,
 * tokens -4001..-4999, tiles -5001..-5999. */
#define PROTO_SERVICE_JM_ERRORS(X)                                                                 \
    X(JM_ENOENT, -1001, WIRE_NOT_FOUND, "id", "the job was refused")                               \
    X(JM_EQUEUE_FULL, -1002, WIRE_QUEUE_FULL, "", "the job was refused")                           \
    X(JM_EQUOTA, -1003, WIRE_JOB_QUOTA, "", "the job was refused")                                 \
    X(JM_EFORBIDDEN, -1004, WIRE_FORBIDDEN, "", "the job was refused")                             \
    X(JM_EFINISHED, -1005, WIRE_CONFLICT, "", "the job was refused")                               \
    X(JM_ESTORE, -1006, WIRE_STORE_UNAVAILABLE, "", "the job was refused")                         \
    /* purge of a running job */                                                                   \
    X(JM_EACTIVE, -1007, WIRE_CONFLICT, "", "the job was refused")                                 \
    /* executor slurm: Slurm not configured or not answering; names the envelope field */          \
    X(JM_ESLURM, -1009, WIRE_SLURM_UNAVAILABLE, "executor", "Slurm is unavailable")

#define PROTO_SERVICE_JOB_STORE_ERRORS(X)                                                          \
    /* the owner's stored bytes would exceed the quota */                                          \
    X(JOB_STORE_EQUOTA, -2001, WIRE_QUOTA_EXCEEDED, "", "the job store quota is exceeded")         \
    X(JOB_STORE_ENOENT, -2002, WIRE_NOT_FOUND, "id", "no such job")                                \
    X(JOB_STORE_EACTIVE, -2003, WIRE_CONFLICT, "", "the job is queued or running")                 \
    /* a write failed for lack of space or an I/O error: the store may recover */                  \
    X(JOB_STORE_EUNAVAILABLE, -2004, WIRE_STORE_UNAVAILABLE, "", "the job store is unavailable")   \
    /* any other failed write (a constraint, a corrupt page): the answer is the same 503 */        \
    X(JOB_STORE_EWRITE, -2005, WIRE_STORE_UNAVAILABLE, "", "the job store write failed")

#define PROTO_SERVICE_CLUSTER_ERRORS(X)                                                            \
    /* stopped for a daemon shutdown; the arrays keep running */                                   \
    X(CLUSTER_EDETACHED, -3001, WIRE_BUSY, "", "the daemon is shutting down")                      \
    /* a shard failed twice (the job's error: "internal") */                                       \
    X(CLUSTER_ESHARD, -3002, WIRE_INTERNAL, "", "a shard failed twice")                            \
    X(CLUSTER_ESLURM, -3003, WIRE_SLURM_UNAVAILABLE, "executor", "sbatch failed")

#define PROTO_SERVICE_TOKEN_ERRORS(X)                                                              \
    X(TOKEN_ENOENT, -4001, WIRE_NOT_FOUND, "id", "no such token")                                  \
    X(TOKEN_EFORBIDDEN, -4002, WIRE_FORBIDDEN, "id",                                               \
      "only the token's owner or root may revoke it")                                              \
    X(TOKEN_ESTORE, -4003, WIRE_STORE_UNAVAILABLE, "", "the token store failed")                   \
    X(TOKEN_EQUOTA, -4004, WIRE_QUOTA_EXCEEDED, "", "too many live tokens")

#define PROTO_SERVICE_TILE_ERRORS(X) X(TILE_ENOENT, -5001, WIRE_NOT_FOUND, "", "no such tile")

#define PROTO_SERVICE_ERRORS(X)                                                                    \
    PROTO_SERVICE_JM_ERRORS(X)                                                                     \
    PROTO_SERVICE_JOB_STORE_ERRORS(X)                                                              \
    PROTO_SERVICE_CLUSTER_ERRORS(X)                                                                \
    PROTO_SERVICE_TOKEN_ERRORS(X)                                                                  \
    PROTO_SERVICE_TILE_ERRORS(X)

/* For a subsystem header: enum { PROTO_SERVICE_JM_ERRORS(PROTO_SERVICE_AS_ENUM) }; */
#define PROTO_SERVICE_AS_ENUM(name, value, row, field, message) name = (value),

typedef struct proto_service_row {
    const char *name; /* "JM_ESLURM" */
    int value;
    proto_wire_error error;
    const char *field;
    const char *message;
} proto_service_row;

/* The row of a service code; NULL for any other value (an AA_E* code, 0). */
const proto_service_row *proto_service_row_of(int code);

extern const proto_service_row proto_service_rows[];
extern const size_t proto_service_row_count;

#endif
