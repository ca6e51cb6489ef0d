/* The one clock: monotonic seconds, and the clock a computation's time budget reads. */
#ifndef AA_CLOCK_H
#define AA_CLOCK_H

/* CLOCK_MONOTONIC in seconds: for intervals, deadlines and timeouts, never the time of day. */
double aa_monotonic_seconds(void);

/* The time source of budgets and reported seconds: seconds since any fixed point, never going
 * backwards. fn NULL: aa_monotonic_seconds. A caller that pauses a run (the daemon gives a
 * waiting user's job the core for a while) passes a clock that stands still during the pause,
 * so the pause costs the run none of its budget and a budget-free run gives the same result. */
typedef struct aa_clock {
    double (*fn)(void *user);
    void *user;
} aa_clock;
double aa_clock_seconds(const aa_clock *c);

#endif
