/* A bounded, thread-safe store of PNG tiles, addressed by content (the same bytes get the same
 * id). Ids are 32 lowercase hex characters: safe in URLs (/v1/tiles/{id}.png) and file names.
 * With a state directory the tiles are also written to state_dir/tiles/{id}.png (atomically,
 * via rename) and found there again after a restart; memory and disk hold the same set.
 * When the total exceeds max_bytes the least recently used tiles are dropped (and their files
 * removed).
 *
 * Access: a tile is "team" (anyone may fetch it) once anyone stores it as team; otherwise it is
 * readable by the uids that stored it privately (and root on the socket). The same bytes made
 * by two users are one tile: each of them made it, so neither learns anything from the other.
 * The private readers persist beside the PNG in {id}.readers. */
#ifndef AALAB_TILE_STORE_H
#define AALAB_TILE_STORE_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_core.h"
#include "service_error.h"

#define TILE_ID_LEN 32
/* TILE_ENOENT: no such tile (proto/service_error.h) */
enum { PROTO_SERVICE_TILE_ERRORS(PROTO_SERVICE_AS_ENUM) };

typedef struct tile_store tile_store;

/* state_dir NULL = memory only. max_bytes >= 1. NULL on error (err filled). */
tile_store *tile_store_create(const char *state_dir, size_t max_bytes, aa_error *err);
void tile_store_destroy(tile_store *ts);

/* Copies the bytes in; writes the id (TILE_ID_LEN chars + NUL). AA_ERANGE if larger than
 * max_bytes, AA_ENOMEM. A disk write failure keeps the tile in memory (returns AA_OK). */
int tile_store_put(tile_store *ts, const void *data, size_t len, char id[TILE_ID_LEN + 1],
                   aa_error *err);
/* Who stores a tile: NULL or private == false is team. */
typedef struct tile_access {
    long long owner;
    bool private_tile;
} tile_access;
/* tile_store_put with an access (the put above is team). */
int tile_store_put_as(tile_store *ts, const void *data, size_t len, const tile_access *access,
                      char id[TILE_ID_LEN + 1], aa_error *err);
/* tile_store_get for a caller: TILE_ENOENT also for a private tile uid may not read (its
 * existence is not revealed). admin reads everything. */
int tile_store_get_as(tile_store *ts, const char *id, long long uid, bool admin, void **data,
                      size_t *len);
/* Copies a tile out (*data malloc'd). AA_EINVAL for a malformed id, TILE_ENOENT if absent. */
int tile_store_get(tile_store *ts, const char *id, void **data, size_t *len);
bool tile_id_valid(const char *id);

typedef struct tile_store_usage {
    size_t tiles, bytes, max_bytes, evicted;
} tile_store_usage;
tile_store_usage tile_store_usage_get(tile_store *ts);

#endif
