/* The table of job kinds: what each is, how its spec is decoded, how it runs and where its
 * result keeps the best pattern. Each row is in its kind file (kind_<id>.c); kind_list.h gives
 * the order, the one GET /v1/kinds and error messages list. */
#include <pthread.h>
#include <string.h>

#include "kinds.h"

/* The rows live in their kind files; the callers index one array (job_kinds_table), so the
 * rows kind_list.h names are copied into it once. */
static const job_kind *const rows[] = {
#define KIND(id) &job_kind_##id,
#include "kind_list.h"
#undef KIND
};

#define KIND_COUNT (sizeof rows / sizeof rows[0])

static job_kind table[KIND_COUNT];
static pthread_once_t table_once = PTHREAD_ONCE_INIT;

static void table_fill(void)
{
    for (size_t i = 0; i < KIND_COUNT; i++)
        table[i] = *rows[i];
}

const job_kind *job_kinds_table(size_t *count)
{
    pthread_once(&table_once, table_fill);
    *count = KIND_COUNT;
    return table;
}

const job_kind *job_kind_find(const char *name)
{
    pthread_once(&table_once, table_fill);
    /* NULL: a stored row or a spec without a kind string is no kind, not a crash. */
    for (size_t i = 0; name && i < KIND_COUNT; i++)
        if (!strcmp(table[i].name, name))
            return &table[i];
    return NULL;
}
