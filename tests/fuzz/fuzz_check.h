/* An assert that stays on in release builds (NDEBUG): a failed invariant aborts, which libFuzzer
 * reports as a crash with the input saved. */
#ifndef AALAB_FUZZ_CHECK_H
#define AALAB_FUZZ_CHECK_H

#include <stdio.h>
#include <stdlib.h>

#define FUZZ_CHECK(cond)                                                                           \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: invariant failed: %s\n", __FILE__, __LINE__, #cond);           \
            abort();                                                                               \
        }                                                                                          \
    } while (0)

#endif
