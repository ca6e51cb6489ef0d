/* Counts of things held per key (a peer uid, a token hash) under a limit: connections per user
 * and per token, running evaluates and renders per user. Thread-safe (one mutex); a key whose
 * count falls to zero is forgotten, so the table holds only the keys in use. */
#ifndef AALAB_KEY_COUNTS_H
#define AALAB_KEY_COUNTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct key_counts key_counts;

key_counts *key_counts_create(void);
void key_counts_destroy(key_counts *kc);
/* Takes one unit for key if it holds fewer than limit; false (nothing taken) otherwise or when
 * out of memory. */
bool key_counts_acquire(key_counts *kc, uint64_t key, int limit);
/* Gives back one unit taken by key_counts_acquire. */
void key_counts_release(key_counts *kc, uint64_t key);
/* Units key holds now (0 if none). */
int key_counts_get(key_counts *kc, uint64_t key);
/* Keys holding at least one unit. */
size_t key_counts_keys(key_counts *kc);

/* A 64-bit key for a string (FNV-1a): token headers are counted by hash, never stored. */
uint64_t key_counts_hash(const char *s);

#endif
