/* AALAB_TEST_SMALL=1 (set by scripts/test.sh's sanitizer stage): slow engine tests run fewer
 * seeds, rounds or steps there, the same code and checks; the normal stage runs them whole. */
#ifndef AALAB_TEST_SMALL_H
#define AALAB_TEST_SMALL_H

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

static inline bool test_small(void)
{
    const char *small = getenv("AALAB_TEST_SMALL");
    return small && strcmp(small, "1") == 0;
}

#endif
