/* The one fork-join: a batch of independent tasks, one thread each, the caller's thread
 * included. */
#ifndef AA_FORK_JOIN_H
#define AA_FORK_JOIN_H

#include <stddef.h>

/* Runs task(items + k * item_size) for k in [0, count): item 0 on the calling thread, every
 * other on a thread of its own. An item whose thread cannot be started runs on the calling
 * thread after item 0, so every item runs whatever the system allows. Returns when all have. */
void aa_fork_join(void *items, size_t item_size, int count, void (*task)(void *item));

#endif
