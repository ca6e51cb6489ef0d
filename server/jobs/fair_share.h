/* Fair share between the users of one daemon: which waiting job gets a free worker, and when a
 * running job gives its worker back. Pure functions over a snapshot of the active jobs (the job
 * manager builds it under its lock), so the policy is unit-tested without threads.
 *
 * Picking (fs_pick), in this order:
 *  1. users below --user-workers before users at or above it (a user exceeds the cap only when
 *     nobody else is waiting: idle cores are not left idle);
 *  2. the user holding the fewest workers;
 *  3. the user served longest ago (round robin: a user's "served" time is the latest time one of
 *     its jobs got or gave back a worker);
 *  4. within the user: higher priority, then a paused job before a queued one (finish started
 *     work first), then the oldest (lowest id).
 * Yielding (fs_should_yield): a running job whose slice is over gives its worker back when a job
 * of another user waits and that user holds fewer workers than the running job's owner. Equal
 * holders keep their workers, so two users with equal shares do not swap back and forth. */
#ifndef AALAB_FAIR_SHARE_H
#define AALAB_FAIR_SHARE_H

#include <stdbool.h>
#include <stddef.h>

typedef struct fs_job {
    long long owner; /* uid; -1 (unknown) is one more user */
    int priority;
    bool running; /* holds a worker */
    bool paused;  /* has run and waits to resume (else: queued, never ran) */
    double served;
    long long id;
} fs_job;

/* Index of the waiting (not running) job that gets the next free worker, or -1 if none waits.
 * O(jobs x users). */
long fs_pick(const fs_job *jobs, size_t n, int user_workers);
/* Does running job jobs[r] give its worker to a waiting user now? */
bool fs_should_yield(const fs_job *jobs, size_t n, size_t r);

#endif
