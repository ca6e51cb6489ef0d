/* Per-user bearer tokens for the TCP listener, kept in <state-dir>/tokens.db (SQLite). A token
 * is issued to a Unix-socket peer and acts for that uid over TCP until it is revoked. Only the
 * SHA-256 of the secret is stored; the secret is shown once, at issue. A token reads
 * "aalab_<id>_<64 hex>": the id finds the row, the hash is compared in constant time.
 * Thread-safe (one connection behind a mutex). */
#ifndef AALAB_TOKEN_STORE_H
#define AALAB_TOKEN_STORE_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_core.h"
#include "request_token.h"
#include "service_error.h"

#define TOKEN_LABEL_MAX PROTO_TOKEN_LABEL_MAX
/* TOKEN_ENOENT, _EFORBIDDEN, _ESTORE, _EQUOTA (proto/service_error.h) */
enum { PROTO_SERVICE_TOKEN_ERRORS(PROTO_SERVICE_AS_ENUM) };

typedef struct token_store token_store;

/* Opens (creates 0600) state_dir/tokens.db. NULL on error (err filled). */
token_store *token_store_open(const char *state_dir, aa_error *err);
void token_store_close(token_store *ts);

/* A new token for uid; *out = {"id","token","uid","label","created"} (the only place the
 * secret appears). label may be NULL. TOKEN_EQUOTA when uid already holds max_per_user live
 * tokens (counted under the same lock as the insert, so parallel issues cannot pass it),
 * TOKEN_ESTORE, AA_ENOMEM. */
int token_store_issue(token_store *ts, long long uid, const char *label, int max_per_user,
                      json_t **out, aa_error *err);
/* Live tokens of uid. */
int token_store_count(token_store *ts, long long uid);
/* The uid and id of a presented token; TOKEN_ENOENT if malformed, unknown or revoked. */
int token_store_check(token_store *ts, const char *token, long long *uid, long long *id);
/* {"id","uid","label","created"} of uid's tokens (uid < 0: all), oldest first, no secrets. */
json_t *token_store_list(token_store *ts, long long uid);
/* Revokes at once. Only the owner, or anyone when admin. TOKEN_ENOENT, TOKEN_EFORBIDDEN. */
int token_store_revoke(token_store *ts, long long id, long long caller, bool admin);

#endif
