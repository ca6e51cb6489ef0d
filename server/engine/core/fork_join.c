#define _POSIX_C_SOURCE 200809L /* pthreads */
#include "fork_join.h"

#include <assert.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>

typedef struct fork_item {
    void (*task)(void *item);
    void *item;
    pthread_t thread;
    bool started;
} fork_item;

static void *fork_main(void *arg)
{
    fork_item *f = arg;
    f->task(f->item);
    return NULL;
}

void aa_fork_join(void *items, size_t item_size, int count, void (*task)(void *item))
{
    if (count <= 0)
        return;
    assert(items && task && (count == 1 || item_size > 0));
    char *base = items;
    /* Without memory for the thread handles every item runs here, one after another. */
    fork_item *f = count > 1 ? calloc((size_t)count, sizeof *f) : NULL;
    for (int k = 1; f && k < count; k++) {
        f[k] = (fork_item){.task = task, .item = base + (size_t)k * item_size};
        f[k].started = pthread_create(&f[k].thread, NULL, fork_main, &f[k]) == 0;
    }
    task(base);
    for (int k = 1; k < count; k++) {
        if (f && f[k].started)
            pthread_join(f[k].thread, NULL);
        else
            task(base + (size_t)k * item_size);
    }
    free(f);
}
