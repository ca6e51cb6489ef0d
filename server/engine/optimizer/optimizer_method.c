/* Names of the step rules and the choice made when a caller leaves it to the engine. */
#include <string.h>

#include "optimizer.h"

static const char *const method_names[] = {"laine-aila", "minimax", "smooth"};

const char *aa_optimize_method_name(aa_optimize_method m)
{
    return (unsigned)m < sizeof method_names / sizeof method_names[0] ? method_names[m] : "?";
}

int aa_optimize_method_parse(const char *name, aa_optimize_method *out)
{
    for (size_t i = 0; i < sizeof method_names / sizeof method_names[0]; i++)
        if (!strcmp(name, method_names[i])) {
            *out = (aa_optimize_method)i;
            return AA_OK;
        }
    return AA_EINVAL;
}

aa_optimize_method aa_auto_method(bool tiled_without_border, aa_optimize_mode mode)
{
    if (mode == AA_OPTIMIZE_WEIGHTS)
        return AA_METHOD_MINIMAX;
    if (tiled_without_border)
        return AA_METHOD_SMOOTH;
    return AA_METHOD_LAINE_AILA;
}
