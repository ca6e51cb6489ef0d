#include "fair_share.h"

#include <stdlib.h>

typedef struct owner_stat {
    long long owner;
    int running;
    double served;
} owner_stat;

/* Distinct owners of jobs[] with their running counts and latest served time; returns the
 * count, or 0 (and *out NULL) when out of memory. */
static size_t owner_stats(const fs_job *jobs, size_t n, owner_stat **out)
{
    owner_stat *s = malloc((n ? n : 1) * sizeof *s);
    *out = s;
    if (!s)
        return 0;
    size_t u = 0;
    for (size_t i = 0; i < n; i++) {
        size_t k = 0;
        while (k < u && s[k].owner != jobs[i].owner)
            k++;
        if (k == u)
            s[u++] = (owner_stat){jobs[i].owner, 0, jobs[i].served};
        s[k].running += jobs[i].running;
        if (jobs[i].served > s[k].served)
            s[k].served = jobs[i].served;
    }
    return u;
}

static const owner_stat *stat_of(const owner_stat *s, size_t u, long long owner)
{
    for (size_t k = 0; k < u; k++)
        if (s[k].owner == owner)
            return &s[k];
    return NULL;
}

/* Is a (with its owner's stats oa) a better pick than b (ob)? */
static bool better(const fs_job *a, const owner_stat *oa, const fs_job *b, const owner_stat *ob,
                   int cap)
{
    if (oa != ob) {
        bool a_capped = oa->running >= cap, b_capped = ob->running >= cap;
        if (a_capped != b_capped)
            return !a_capped;
        if (oa->running != ob->running)
            return oa->running < ob->running;
        if (oa->served != ob->served)
            return oa->served < ob->served;
        return oa->owner < ob->owner; /* deterministic between never-served users */
    }
    if (a->priority != b->priority)
        return a->priority > b->priority;
    if (a->paused != b->paused)
        return a->paused;
    return a->id < b->id;
}

long fs_pick(const fs_job *jobs, size_t n, int user_workers)
{
    owner_stat *s;
    size_t u = owner_stats(jobs, n, &s);
    long best = -1;
    for (size_t i = 0; i < n; i++) {
        if (jobs[i].running)
            continue;
        if (!s) { /* out of memory: the oldest waiting job, still a valid choice */
            if (best < 0 || jobs[i].id < jobs[best].id)
                best = (long)i;
            continue;
        }
        if (best < 0 || better(&jobs[i], stat_of(s, u, jobs[i].owner), &jobs[best],
                               stat_of(s, u, jobs[best].owner), user_workers))
            best = (long)i;
    }
    free(s);
    return best;
}

bool fs_should_yield(const fs_job *jobs, size_t n, size_t r)
{
    owner_stat *s;
    size_t u = owner_stats(jobs, n, &s);
    if (!s)
        return false; /* out of memory: keep running; the next check tries again */
    int mine = stat_of(s, u, jobs[r].owner)->running;
    bool yield = false;
    for (size_t i = 0; i < n && !yield; i++)
        yield = !jobs[i].running && jobs[i].owner != jobs[r].owner &&
                stat_of(s, u, jobs[i].owner)->running < mine;
    free(s);
    return yield;
}
