/* A job's trace: the best E2 found against run time, one point per improvement. */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"

void view_trace(FILE *out, const json_t *trace, bool csv)
{
    const char *headers[] = {"seconds", "iterations", "evaluations", "best_e2"};
    table *t = table_new(4, headers);
    if (!t)
        return;
    size_t i;
    json_t *p;
    json_array_foreach(trace, i, p)
    {
        char sec[32], it[32], ev[32], e2[32];
        const char *cells[] = {
            fmt_number(sec, sizeof sec, json_object_get(p, "seconds"), fmt_decimals(csv, 4)),
            fmt_number(it, sizeof it, json_object_get(p, "iterations"), 0),
            fmt_number(ev, sizeof ev, json_object_get(p, "evaluations"), 0),
            fmt_number(e2, sizeof e2, json_object_get(p, "best_e2"), fmt_decimals(csv, 6))};
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
}
