/* Parsers of Slurm output (server/cluster/slurm_parse.c) on canned text. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "slurm_parse.h"

static void test_sbatch(void **state)
{
    (void)state;
    long long id = 0;
    assert_int_equal(slurm_parse_sbatch("123\n", &id), AA_OK);
    assert_int_equal(id, 123);
    assert_int_equal(slurm_parse_sbatch("4567;cluster1\n", &id), AA_OK);
    assert_int_equal(id, 4567);
    assert_int_equal(slurm_parse_sbatch("sbatch: error: x\n", &id), AA_EINVAL);
    assert_int_equal(slurm_parse_sbatch("", &id), AA_EINVAL);
    assert_int_equal(slurm_parse_sbatch("12x", &id), AA_EINVAL);
}

static void test_squeue_elements_and_ranges(void **state)
{
    (void)state;
    const char *out = "123_0 RUNNING\n"
                      "123_[4-7] PENDING\n"
                      "  124_[1,3,9-10%2] PENDING\n"
                      "125 RUNNING\n"
                      "garbage line\n"
                      "126_[x] PENDING\n"
                      "123_2 COMPLETING";
    slurm_queued *q = NULL;
    size_t n = 0;
    assert_int_equal(slurm_parse_squeue(out, &q, &n), AA_OK);
    assert_int_equal(n, 1 + 4 + 4 + 1 + 1);
    assert_int_equal(q[0].job_id, 123);
    assert_int_equal(q[0].index, 0);
    assert_string_equal(q[0].state, "RUNNING");
    for (int k = 0; k < 4; k++) {
        assert_int_equal(q[1 + k].job_id, 123);
        assert_int_equal(q[1 + k].index, 4 + k);
        assert_string_equal(q[1 + k].state, "PENDING");
    }
    long want[] = {1, 3, 9, 10};
    for (int k = 0; k < 4; k++) {
        assert_int_equal(q[5 + k].job_id, 124);
        assert_int_equal(q[5 + k].index, want[k]);
    }
    assert_int_equal(q[9].job_id, 125);
    assert_int_equal(q[9].index, -1);
    assert_int_equal(q[10].index, 2);
    assert_string_equal(q[10].state, "COMPLETING");
    free(q);
    assert_int_equal(slurm_parse_squeue("", &q, &n), AA_OK);
    assert_int_equal(n, 0);
    free(q);
    assert_true(slurm_squeue_invalid_id("slurm_load_jobs error: Invalid job id specified\n"));
    assert_false(slurm_squeue_invalid_id("squeue: error: Unable to contact slurm controller"));
}

static void test_scontrol_show_job(void **state)
{
    (void)state;
    const char *out = "JobId=130 ArrayJobId=123 ArrayTaskId=4 JobName=aalab-7-s0\n"
                      "   UserId=root(0) GroupId=root(0) MCS_label=N/A\n"
                      "   Priority=1 Nice=0 Account=(null) QOS=(null)\n"
                      "   JobState=FAILED Reason=NonZeroExitCode Dependency=(null)\n"
                      "   Requeue=1 Restarts=0 BatchFlag=1 Reboot=0 ExitCode=1:0\n"
                      "   StdOut=/shared/job-7/stage-0/log-4.out\n"
                      "\n"
                      "JobId=131 JobState=COMPLETED\n";
    char buf[64];
    assert_true(slurm_parse_scontrol_field(out, "JobState", buf, sizeof buf));
    assert_string_equal(buf, "FAILED");
    assert_true(slurm_parse_scontrol_field(out, "ExitCode", buf, sizeof buf));
    assert_string_equal(buf, "1:0");
    assert_true(slurm_parse_scontrol_field(out, "Reason", buf, sizeof buf));
    assert_string_equal(buf, "NonZeroExitCode");
    assert_true(slurm_parse_scontrol_field(out, "JobId", buf, sizeof buf));
    assert_string_equal(buf, "130");
    /* ArrayJobId must not match JobId, nor MCS_label match label. */
    assert_true(slurm_parse_scontrol_field(out, "ArrayJobId", buf, sizeof buf));
    assert_string_equal(buf, "123");
    assert_false(slurm_parse_scontrol_field(out, "label", buf, sizeof buf));
    assert_false(slurm_parse_scontrol_field(out, "Nope", buf, sizeof buf));
    char small[4];
    assert_true(slurm_parse_scontrol_field(out, "StdOut", small, sizeof small));
    assert_string_equal(small, "/sh");
}

static void test_sacct(void **state)
{
    (void)state;
    const char *out = "123_3|COMPLETED|0:0\n"
                      "123_3.batch|COMPLETED|0:0\n"
                      "123_4|FAILED|1:0\n"
                      "123_4.batch|FAILED|1:0\n"
                      "123_5|CANCELLED by 0|0:15\n";
    char st[32], ex[16];
    assert_true(slurm_parse_sacct(out, "123_4", st, sizeof st, ex, sizeof ex));
    assert_string_equal(st, "FAILED");
    assert_string_equal(ex, "1:0");
    assert_true(slurm_parse_sacct(out, "123_5", st, sizeof st, ex, sizeof ex));
    assert_string_equal(st, "CANCELLED");
    assert_string_equal(ex, "0:15");
    assert_false(slurm_parse_sacct(out, "123_6", st, sizeof st, ex, sizeof ex));
    assert_false(slurm_parse_sacct(out, "123", st, sizeof st, ex, sizeof ex));
    assert_true(slurm_accounting_disabled("sacct: error: Slurm accounting storage is disabled\n"));
    assert_false(slurm_accounting_disabled("sacct: error: Problem talking to the database"));
}

static void test_ping(void **state)
{
    (void)state;
    assert_true(slurm_parse_ping_up("Slurmctld(primary) at node1 is UP\n"));
    assert_true(
        slurm_parse_ping_up("Slurmctld(primary) at a is DOWN\nSlurmctld(backup) at b is UP\n"));
    assert_false(slurm_parse_ping_up("Slurmctld(primary) at node1 is DOWN\n"));
    assert_false(slurm_parse_ping_up(""));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sbatch),
        cmocka_unit_test(test_squeue_elements_and_ranges),
        cmocka_unit_test(test_scontrol_show_job),
        cmocka_unit_test(test_sacct),
        cmocka_unit_test(test_ping),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
