/* The daemon state behind api_handle(): configuration, job manager, caches, tile store, tokens.
 * Created once at start-up (and by unit tests with a temporary state directory). */
#ifndef AALAB_API_CONTEXT_H
#define AALAB_API_CONTEXT_H

#include <stdbool.h>
#include <sys/types.h>

#include <jansson.h>

#include "aa_core.h"
#include "api.h"
#include "config.h"

struct tile_store;
struct job_manager;
struct eval_cache;
struct token_store;

/* Opens the state directory (created 0700 if missing), the job store (re-queueing unfinished
 * jobs), the tile store and the token store (tokens.db). NULL on error (err filled). */
api_context *api_context_create(const aalab_config *cfg, aa_error *err);
/* Stops the workers (running jobs are written back as queued) and frees everything. */
void api_context_destroy(api_context *ctx);
/* Stop accepting jobs and checkpoint running ones; api_context_destroy() still needed. */
void api_context_shutdown(api_context *ctx);

const aalab_config *api_context_config(const api_context *ctx);
/* The GET /v1/kinds body, encoded at api_context_create (kind_schemas_document). */
const char *api_context_kinds_body(const api_context *ctx);
struct tile_store *api_context_tiles(api_context *ctx);
struct job_manager *api_context_jobs(api_context *ctx);
struct eval_cache *api_context_eval_cache(api_context *ctx);
struct body_budget *api_context_body_budget(api_context *ctx);
struct token_store *api_context_tokens(api_context *ctx);
/* From now on a token is accepted only while its owner is in group gid (the socket's group;
 * root always). Call before the listeners start. AA_ENOMEM. */
int api_context_tie_tokens_to_group(api_context *ctx, gid_t gid);
bool api_context_token_owner_ok(api_context *ctx, long long uid);
/* The Unix socket file's owner and mode at start (after api_context_tie_tokens_to_group with its
 * group): from then on a socket peer is served only while it could still connect, i.e. it is
 * root, the owner, a member of the group (cached GROUP_MEMBERSHIP_TTL seconds) or the mode
 * lets others write. A user removed from the group loses an open keep-alive connection too. */
void api_context_tie_socket_access(api_context *ctx, uid_t owner, mode_t mode);
bool api_context_socket_peer_ok(api_context *ctx, long long uid);
double api_context_uptime(const api_context *ctx);

#endif
