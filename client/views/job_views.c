/* Kind name -> view. A kind added to the daemon shows through the generic view until it has
 * a row here. */
#include "job_views.h"

#include <string.h>

static const job_view VIEWS[] = {
    {"optimize", view_optimize},
    {"family-sweep", view_family_sweep},
    {"random-stats", view_random_stats},
    {"table3", view_table3},
    {"compare", view_compare},
    {"animation", view_animation},
    {"reference-convergence", view_reference_convergence},
    {"temporal-optimize", view_temporal_optimize},
    {"temporal-render", view_temporal_render},
};

static const job_view GENERIC = {"", view_generic};

const job_view *job_view_find(const char *kind)
{
    for (size_t i = 0; kind && i < sizeof VIEWS / sizeof VIEWS[0]; i++)
        if (strcmp(VIEWS[i].kind, kind) == 0)
            return &VIEWS[i];
    return &GENERIC;
}
