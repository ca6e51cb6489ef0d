/* Local pattern check. Uses the shared codec (proto/codec.h) so that the client and the daemon
 * accept exactly the same files. */
#include "pattern_source.h"

#include <stdio.h>
#include <string.h>

int pattern_check(const json_t *pattern, char *err, size_t errcap)
{
    static const char *const FORMS[] = {"preset", "kernels", "mirrored", "tile"};
    size_t forms = 0;
    for (size_t i = 0; i < sizeof FORMS / sizeof FORMS[0]; i++)
        forms += json_object_get(pattern, FORMS[i]) != NULL;
    if (forms != 1) {
        snprintf(err, errcap, "a pattern has exactly one of preset, kernels, mirrored, tile");
        return -1;
    }
    return 0;
}
