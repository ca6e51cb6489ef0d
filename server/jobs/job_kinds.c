/* The table of job kinds: what each is, how its spec is decoded, how it runs and where its
 * result keeps the best pattern. Each row is in its kind file (kind_<id>.c); kind_list.h gives
 * the order, the one GET /v1/kinds and error messages list. */
#include <string.h>

#include "kinds.h"

/* The rows live in their kind files; this is the order kind_list.h gives them. */
static const job_kind *const rows[] = {
#define KIND(id) &job_kind_##id,
#include "kind_list.h"
#undef KIND
};

#define KIND_COUNT (sizeof rows / sizeof rows[0])

const job_kind *const *job_kinds_table(size_t *count)
{
    *count = KIND_COUNT;
    return rows;
}

const job_kind *job_kind_find(const char *name)
{
    /* NULL: a stored row or a spec without a kind string is no kind, not a crash. */
    for (size_t i = 0; name && i < KIND_COUNT; i++)
        if (!strcmp(rows[i]->name, name))
            return rows[i];
    return NULL;
}
