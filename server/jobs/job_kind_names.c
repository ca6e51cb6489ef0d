/* Lists of kind names from the kind table (job_kind_names.h). */
#include "job_kind_names.h"

#include <stdio.h>

#include "job_kind.h"

static bool listed(const job_kind *k, bool test_kinds, bool split_only)
{
    return (test_kinds || !k->test_only) && (!split_only || k->split);
}

void job_kind_names_join(char *buf, size_t cap, bool test_kinds, bool split_only,
                         const char *last_join)
{
    size_t count, total = 0, seen = 0, n = 0;
    const job_kind *const *table = job_kinds_table(&count);
    for (size_t k = 0; k < count; k++)
        total += listed(table[k], test_kinds, split_only);
    buf[0] = 0;
    for (size_t k = 0; k < count && n < cap; k++) {
        if (!listed(table[k], test_kinds, split_only))
            continue;
        seen++;
        const char *sep = seen == 1 ? "" : seen == total ? last_join : ", ";
        int w = snprintf(buf + n, cap - n, "%s%s", sep, table[k]->name);
        if (w < 0)
            break;
        n += (size_t)w;
    }
}
