/* Fair share (server/jobs/fair_share.c): which waiting job gets a free worker, when a running
 * job yields; and the job envelope (priority, visibility, pinned). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

#include "fair_share.h"
#include "job_envelope.h"

#define A 1001
#define B 1002
#define C 1003

static fs_job queued(long long owner, long long id)
{
    return (fs_job){.owner = owner, .id = id};
}

static fs_job running(long long owner, long long id, double served)
{
    return (fs_job){.owner = owner, .id = id, .running = true, .served = served};
}

static void test_nothing_waits(void **state)
{
    (void)state;
    fs_job jobs[] = {running(A, 1, 0), running(B, 2, 0)};
    assert_int_equal(fs_pick(jobs, 2, 1), -1);
    assert_int_equal(fs_pick(NULL, 0, 1), -1);
}

static void test_user_with_fewest_workers_first(void **state)
{
    (void)state;
    /* A holds a worker and has older queued jobs; B holds none: B's job goes first, whatever
     * the submission order. */
    fs_job jobs[] = {running(A, 1, 5), queued(A, 2), queued(A, 3), queued(B, 9)};
    assert_int_equal(fs_pick(jobs, 4, 1), 3);
}

static void test_cap_and_work_conservation(void **state)
{
    (void)state;
    /* cap 1: A at its cap, B below it -> B even though B holds as many as... */
    fs_job capped[] = {running(A, 1, 0), queued(A, 2), running(B, 3, 0), queued(B, 4),
                       running(B, 5, 0)};
    /* A holds 1, B holds 2: both at/above cap 1; A has fewer -> A's job. */
    assert_int_equal(fs_pick(capped, 5, 1), 1);
    /* Only A waits and A is at the cap: the idle worker still goes to A (nobody else waits). */
    fs_job alone[] = {running(A, 1, 0), queued(A, 2)};
    assert_int_equal(fs_pick(alone, 2, 1), 1);
    /* Below-cap users come before capped ones even with more workers held: cap 3, A holds 3
     * (capped), B holds 2 (below). */
    fs_job mixed[] = {running(A, 1, 0), running(A, 2, 0), running(A, 3, 0), queued(A, 4),
                      running(B, 5, 0), running(B, 6, 0), queued(B, 7)};
    assert_int_equal(fs_pick(mixed, 7, 3), 6);
}

static void test_round_robin_between_equals(void **state)
{
    (void)state;
    /* A and B hold nothing; A was served more recently -> B. */
    fs_job jobs[] = {(fs_job){.owner = A, .id = 1, .paused = true, .served = 20},
                     (fs_job){.owner = B, .id = 2, .paused = true, .served = 10}};
    assert_int_equal(fs_pick(jobs, 2, 1), 1);
    jobs[1].served = 30;
    assert_int_equal(fs_pick(jobs, 2, 1), 0);
}

static void test_within_user_priority_paused_oldest(void **state)
{
    (void)state;
    fs_job jobs[] = {queued(A, 1), queued(A, 2), queued(A, 3)};
    assert_int_equal(fs_pick(jobs, 3, 1), 0); /* oldest */
    jobs[2].priority = 5;
    assert_int_equal(fs_pick(jobs, 3, 1), 2); /* higher priority */
    jobs[1].paused = true;
    jobs[1].priority = 5;
    assert_int_equal(fs_pick(jobs, 3, 1), 1); /* same priority: started work first */
    /* Priority never jumps another user's turn. */
    fs_job two[] = {running(A, 1, 0), (fs_job){.owner = A, .id = 2, .priority = 10}, queued(B, 3)};
    assert_int_equal(fs_pick(two, 3, 1), 2);
}

static void test_yield(void **state)
{
    (void)state;
    /* A holds both workers, B waits with none: each of A's jobs yields at its slice end. */
    fs_job jobs[] = {running(A, 1, 0), running(A, 2, 0), queued(B, 3)};
    assert_true(fs_should_yield(jobs, 3, 0));
    assert_true(fs_should_yield(jobs, 3, 1));
    /* Equal shares do not swap: A 1, B 1, B waits with more. */
    fs_job equal[] = {running(A, 1, 0), running(B, 2, 0), queued(B, 3)};
    assert_false(fs_should_yield(equal, 3, 0));
    /* Only A's own jobs wait: no yield. */
    fs_job own[] = {running(A, 1, 0), queued(A, 2)};
    assert_false(fs_should_yield(own, 2, 0));
    /* A paused job of another user counts as waiting. */
    fs_job paused[] = {running(A, 1, 0), (fs_job){.owner = C, .id = 2, .paused = true}};
    assert_true(fs_should_yield(paused, 2, 0));
}

static void test_envelope(void **state)
{
    (void)state;
    json_error_t je;
    json_t *spec =
        json_loads("{\"kind\":\"sleep\",\"seconds\":1,\"priority\":3,\"visibility\":\"private\","
                   "\"pinned\":true,\"label\":\"nap\"}",
                   0, &je);
    job_envelope env;
    json_t *kind_spec = NULL;
    aa_error err = {0};
    assert_int_equal(job_envelope_take(spec, &env, &kind_spec, &err), AA_OK);
    assert_int_equal(env.priority, 3);
    assert_true(env.private_job && env.pinned);
    assert_string_equal(job_envelope_visibility(&env), "private");
    assert_string_equal(env.label, "nap");
    assert_int_equal(json_object_size(kind_spec), 1); /* seconds: the kind sees no envelope */
    assert_int_equal(json_object_size(spec), 6);      /* the caller's spec is untouched */
    json_decref(kind_spec);
    static const char *const bad[][2] = {{"{\"priority\":11}", "priority"},
                                         {"{\"priority\":1.5}", "priority"},
                                         {"{\"visibility\":\"public\"}", "visibility"},
                                         {"{\"visibility\":1}", "visibility"},
                                         {"{\"pinned\":\"yes\"}", "pinned"},
                                         {"{\"label\":false}", "label"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        json_t *b = json_loads(bad[i][0], 0, &je);
        memset(&err, 0, sizeof err);
        assert_true(job_envelope_take(b, &env, &kind_spec, &err) < 0);
        assert_string_equal(err.field, bad[i][1]);
        assert_null(kind_spec);
        json_decref(b);
    }
    json_decref(spec);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nothing_waits),
        cmocka_unit_test(test_user_with_fewest_workers_first),
        cmocka_unit_test(test_cap_and_work_conservation),
        cmocka_unit_test(test_round_robin_between_equals),
        cmocka_unit_test(test_within_user_priority_paused_oldest),
        cmocka_unit_test(test_yield),
        cmocka_unit_test(test_envelope),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
