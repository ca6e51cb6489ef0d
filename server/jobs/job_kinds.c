/* The table of job kinds.
 *
 * How kinds are added without merge conflicts: every kind is one file server/jobs/kind_*.c that
 * defines `const job_kind job_kind_<name>` (dashes become underscores). server/CMakeLists.txt
 * globs kind_*.c into an OBJECT library, so every kind file that exists is linked. Here each
 * known kind is declared weak and listed on its own line: a kind whose file has not landed yet
 * resolves to NULL and is skipped, so this table can name kinds before their code exists.
 * To add a kind: add its file, then one KIND_DECL line and one table line below. */
#include <stddef.h>
#include <string.h>

#include "job_kind.h"

#define KIND_DECL(sym) extern const job_kind sym __attribute__((weak))

KIND_DECL(job_kind_sleep);                 /* service: test kind (kind_sleep.c) */
KIND_DECL(job_kind_optimize);              /* optimizer (issue 3) */
KIND_DECL(job_kind_family_sweep);          /* optimizer */
KIND_DECL(job_kind_random_stats);          /* optimizer */
KIND_DECL(job_kind_animation);             /* renderer (issue 5) */
KIND_DECL(job_kind_compare);               /* renderer */
KIND_DECL(job_kind_reference_convergence); /* renderer */

static const job_kind *const candidates[] = {
    &job_kind_sleep,
    &job_kind_optimize,
    &job_kind_family_sweep,
    &job_kind_random_stats,
    &job_kind_animation,
    &job_kind_compare,
    &job_kind_reference_convergence,
};

#define CANDIDATE_COUNT (sizeof candidates / sizeof candidates[0])

const job_kind *const *job_kinds_all(void)
{
    /* Built on every call from constant data: no mutable global state, no init race. The
     * returned array is thread-local storage so callers get a stable NULL-terminated list. */
    static _Thread_local const job_kind *list[CANDIDATE_COUNT + 1];
    size_t n = 0;
    for (size_t i = 0; i < CANDIDATE_COUNT; i++)
        if (candidates[i])
            list[n++] = candidates[i];
    list[n] = NULL;
    return list;
}

const job_kind *job_kind_find(const char *name)
{
    for (size_t i = 0; i < CANDIDATE_COUNT; i++)
        if (candidates[i] && !strcmp(candidates[i]->name, name))
            return candidates[i];
    return NULL;
}
