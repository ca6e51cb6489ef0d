#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "clock.h"

#include <time.h>

double aa_monotonic_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

double aa_clock_seconds(const aa_clock *c)
{
    return c && c->fn ? c->fn(c->user) : aa_monotonic_seconds();
}
