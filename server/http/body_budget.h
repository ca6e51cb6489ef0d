/* The request bodies a user may have in flight at once, in bytes (--user-body-bytes): each
 * connection's body is counted from its Content-Length (or as it grows, for a chunked upload)
 * until its request completes. Past the budget the request is answered 429 with Retry-After
 * before its body is read, so 32 connections of 8 MiB bodies cannot make the daemon hold
 * 256 MiB for one user. Thread-safe (one mutex; a few dozen users at most). */
#ifndef AALAB_BODY_BUDGET_H
#define AALAB_BODY_BUDGET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct body_budget body_budget;

body_budget *body_budget_create(size_t per_user); /* NULL on out of memory */
void body_budget_destroy(body_budget *b);
/* Adds bytes to user's total if it stays within the budget; false (nothing added) otherwise. */
bool body_budget_acquire(body_budget *b, uint64_t user, size_t bytes);
void body_budget_release(body_budget *b, uint64_t user, size_t bytes);
size_t body_budget_limit(const body_budget *b);
size_t body_budget_held(body_budget *b, uint64_t user);

#endif
