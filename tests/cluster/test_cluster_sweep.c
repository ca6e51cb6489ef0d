/* The shared files of deleted jobs (cluster_sweep.h): a purge removes its job's directory, the
 * sweep removes those of jobs the daemon no longer has and nothing else. */
#define _XOPEN_SOURCE 700
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "cluster_sweep.h"

static char root[64];

static void make_file(const char *rel)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", root, rel);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs("x\n", f);
    fclose(f);
}

static void make_dir(const char *rel)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", root, rel);
    assert_int_equal(mkdir(path, 0755), 0);
}

static bool exists(const char *rel)
{
    char path[256];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", root, rel);
    return lstat(path, &st) == 0;
}

/* A job with a stage, its files and a symlink pointing outside (removed, not followed). */
static void make_job(long long id)
{
    char rel[64], target[256], link[256];
    snprintf(rel, sizeof rel, "job-%lld", id);
    make_dir(rel);
    snprintf(rel, sizeof rel, "job-%lld/stage-0", id);
    make_dir(rel);
    snprintf(rel, sizeof rel, "job-%lld/stage-0/output-0.json", id);
    make_file(rel);
    snprintf(target, sizeof target, "%s/keep.txt", root);
    snprintf(link, sizeof link, "%s/job-%lld/stage-0/link", root, id);
    assert_int_equal(symlink(target, link), 0);
}

static bool known_odd(void *user, long long id)
{
    (void)user;
    return id % 2 == 1;
}

static int setup(void **state)
{
    (void)state;
    snprintf(root, sizeof root, "/tmp/aalab-sweep-XXXXXX");
    assert_non_null(mkdtemp(root));
    make_file("keep.txt");
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
    return system(cmd);
}

static void sweep_removes_only_unknown_jobs(void **state)
{
    (void)state;
    make_job(1);
    make_job(2);
    make_job(14);
    make_dir("job-x");   /* not a job directory name */
    make_file("job-4");  /* a plain file under a job name: removed like a job directory */
    make_dir("stage-0"); /* other entries stay */
    size_t removed = 99;
    aa_error err = {0};
    assert_int_equal(cluster_sweep_orphans(root, known_odd, NULL, &removed, &err), AA_OK);
    assert_true(exists("job-1/stage-0/output-0.json"));
    assert_false(exists("job-2"));
    assert_false(exists("job-14"));
    assert_true(exists("job-x"));
    assert_true(exists("stage-0"));
    assert_true(exists("keep.txt")); /* the symlink's target survives */
    assert_int_equal(removed, 3);    /* job-2, job-14 and the file job-4 */
    assert_int_equal(cluster_sweep_orphans(root, known_odd, NULL, &removed, &err), AA_OK);
    assert_int_equal(removed, 0);
}

static void purge_removes_one_job(void **state)
{
    (void)state;
    make_job(7);
    aa_error err = {0};
    assert_int_equal(cluster_remove_job_dir(root, 7, &err), AA_OK);
    assert_false(exists("job-7"));
    assert_true(exists("keep.txt"));
    /* Absent: nothing to do. */
    assert_int_equal(cluster_remove_job_dir(root, 7, &err), AA_OK);
}

static void missing_shared_dir_is_an_error(void **state)
{
    (void)state;
    size_t removed;
    aa_error err = {0};
    assert_int_not_equal(
        cluster_sweep_orphans("/nonexistent/aalab-shared", known_odd, NULL, &removed, &err), AA_OK);
    assert_non_null(strstr(err.message, "/nonexistent/aalab-shared"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sweep_removes_only_unknown_jobs),
        cmocka_unit_test(purge_removes_one_job),
        cmocka_unit_test(missing_shared_dir_is_an_error),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
