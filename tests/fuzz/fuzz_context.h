/* A daemon context for fuzzing api_handle() without sockets: a temporary state directory, no
 * listeners, a worker pool that never runs jobs (so fuzzed job submissions cost nothing). */
#ifndef AALAB_FUZZ_CONTEXT_H
#define AALAB_FUZZ_CONTEXT_H

#include "api.h"

api_context *fuzz_context_open(void);
/* Destroys the context and removes its directory (also registered with atexit). */
void fuzz_context_close(void);
/* The bearer token the context accepts on "TCP" requests, or NULL. */
const char *fuzz_context_token(api_context *ctx);

#endif
