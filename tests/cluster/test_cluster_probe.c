/* The Slurm probe thread (cluster_probe.h): unconfigured it starts no thread and says why;
 * configured, its housekeeping runs at the first round and again at once when asked (a purge),
 * not only every CLUSTER_HOUSEKEEPING_INTERVAL seconds. scontrol need not exist: the probe then
 * reports Slurm as not answering. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include <stdatomic.h>

#include "cluster_probe.h"

static void count_round(void *user)
{
    atomic_fetch_add((atomic_int *)user, 1);
}

/* Waits up to seconds for *counter to reach at least want. */
static bool wait_count(atomic_int *counter, int want, double seconds)
{
    for (double t = 0; t < seconds; t += 0.01) {
        if (atomic_load(counter) >= want)
            return true;
        nanosleep(&(struct timespec){0, 10000000L}, NULL);
    }
    return atomic_load(counter) >= want;
}

static void unconfigured_has_no_thread(void **state)
{
    (void)state;
    atomic_int rounds = 0;
    aa_error err = {0};
    cluster_probe *p = cluster_probe_start(false, count_round, &rounds, &err);
    assert_non_null(p);
    cluster_status st;
    cluster_probe_status(p, &st);
    assert_false(st.configured);
    assert_int_equal(st.answering, 0);
    assert_non_null(strstr(st.message, "--slurm-shared-dir"));
    cluster_probe_housekeep_soon(p);
    nanosleep(&(struct timespec){0, 50000000L}, NULL);
    assert_int_equal(atomic_load(&rounds), 0);
    cluster_probe_stop(p);
}

static void housekeeping_runs_when_asked(void **state)
{
    (void)state;
    atomic_int rounds = 0;
    aa_error err = {0};
    cluster_probe *p = cluster_probe_start(true, count_round, &rounds, &err);
    assert_non_null(p);
    assert_true(wait_count(&rounds, 1, 10));
    /* Far sooner than the 60 s interval. */
    cluster_probe_housekeep_soon(p);
    assert_true(wait_count(&rounds, 2, 10));
    cluster_probe_housekeep_soon(p);
    assert_true(wait_count(&rounds, 3, 10));
    cluster_probe_stop(p);
    assert_int_equal(atomic_load(&rounds), 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(unconfigured_has_no_thread),
        cmocka_unit_test(housekeeping_runs_when_asked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
