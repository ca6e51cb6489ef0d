/* A kind without a view of its own: every scalar of its result, one "key  value" line each. */
#include "job_views.h"

#include "../commands/view_util.h"

void view_generic(FILE *out, const json_t *result, bool csv)
{
    print_flat_as(out, result, csv);
}
