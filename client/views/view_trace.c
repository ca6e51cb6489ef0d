/* A job's trace: the best E2 found against run time, one point per improvement. */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"
#include "view_rows.h"

void view_trace(FILE *out, const json_t *trace, bool csv)
{
    static const view_column cols[] = {
        {"seconds", "seconds", VIEW_MEASURE, 4},
        {"iterations", "iterations", VIEW_FIXED, 0},
        {"evaluations", "evaluations", VIEW_FIXED, 0},
        {"best_e2", "best_e2", VIEW_MEASURE, 6},
    };
    view_rows_write(out, trace, cols, sizeof cols / sizeof cols[0], csv);
}
