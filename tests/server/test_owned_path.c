/* owned_path.c: which directories and database files the daemon trusts. The cases that need a
 * file of another uid run only as root (tests/e2e/e2e_users_fs.py covers them with real users). */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "owned_path.h"

static char base[256];

static int setup(void **state)
{
    (void)state;
    snprintf(base, sizeof base, "/tmp/aalab-owned-XXXXXX");
    return mkdtemp(base) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", base);
    return system(cmd) == 0 ? 0 : -1;
}

static void path_in(char *out, size_t cap, const char *name)
{
    snprintf(out, cap, "%s/%s", base, name);
}

static mode_t mode_of(const char *p)
{
    struct stat st;
    assert_int_equal(lstat(p, &st), 0);
    return st.st_mode & 07777;
}

static void test_dirs(void **state)
{
    (void)state;
    char msg[512], p[300], below[320];
    /* Missing: created with the mode asked for, below 0755 parents. */
    path_in(p, sizeof p, "a/b/state");
    assert_int_equal(owned_dir_prepare(p, 0700, "state directory", msg, sizeof msg), 0);
    assert_int_equal(mode_of(p), 0700);
    /* Group-readable is fine (the unit's 0750), group- or other-writable is not. */
    chmod(p, 0750);
    assert_int_equal(owned_dir_prepare(p, 0700, "state directory", msg, sizeof msg), 0);
    chmod(p, 0770);
    assert_int_equal(owned_dir_prepare(p, 0700, "state directory", msg, sizeof msg), -1);
    assert_non_null(strstr(msg, p));
    assert_non_null(strstr(msg, "0770"));
    chmod(p, 0700);
    /* A parent others can write (not sticky) is refused by name; sticky is fine. */
    path_in(p, sizeof p, "a");
    snprintf(below, sizeof below, "%s/b/state", p);
    chmod(p, 0777);
    assert_int_equal(owned_dir_prepare(below, 0700, "state directory", msg, sizeof msg), -1);
    assert_non_null(strstr(msg, "above the state directory"));
    chmod(p, 01777);
    assert_int_equal(owned_dir_prepare(below, 0700, "state directory", msg, sizeof msg), 0);
    chmod(p, 0755);
    /* A symlink to a good directory is judged by its target, which passes here. */
    char link[300];
    path_in(link, sizeof link, "link");
    assert_int_equal(symlink(below, link), 0);
    assert_int_equal(owned_dir_prepare(link, 0700, "state directory", msg, sizeof msg), 0);
    /* A file where the directory should be. */
    path_in(p, sizeof p, "file");
    fclose(fopen(p, "w"));
    assert_int_equal(owned_dir_prepare(p, 0700, "socket directory", msg, sizeof msg), -1);
    /* Not ours (root only: chown to nobody). */
    if (geteuid() == 0) {
        path_in(p, sizeof p, "theirs");
        mkdir(p, 0700);
        assert_int_equal(chown(p, 65534, 65534), 0);
        assert_int_equal(owned_dir_prepare(p, 0700, "socket directory", msg, sizeof msg), -1);
        assert_non_null(strstr(msg, "belongs to uid 65534"));
    }
}

static void test_files(void **state)
{
    (void)state;
    char msg[512], p[300], victim[300];
    mode_t fixed;
    /* New: 0600 whatever the umask. */
    mode_t old = umask(0);
    path_in(p, sizeof p, "jobs.db");
    int fd = owned_file_open(p, &fixed, msg, sizeof msg);
    umask(old);
    assert_true(fd >= 0);
    close(fd);
    assert_int_equal(mode_of(p), 0600);
    assert_int_equal(fixed, 0);
    /* Ours but 0644: narrowed, and the old mode reported. */
    chmod(p, 0644);
    fd = owned_file_open(p, &fixed, msg, sizeof msg);
    assert_true(fd >= 0);
    close(fd);
    assert_int_equal(fixed, 0644);
    assert_int_equal(mode_of(p), 0600);
    /* A symlink is refused and its target left alone. */
    path_in(victim, sizeof victim, "victim");
    fclose(fopen(victim, "w"));
    chmod(victim, 0640);
    path_in(p, sizeof p, "tokens.db");
    assert_int_equal(symlink(victim, p), 0);
    assert_int_equal(owned_file_open(p, &fixed, msg, sizeof msg), -1);
    assert_non_null(strstr(msg, "symlink"));
    assert_int_equal(mode_of(victim), 0640);
    unlink(p);
    /* A hard link to another file is refused. */
    assert_int_equal(link(victim, p), 0);
    assert_int_equal(owned_file_open(p, &fixed, msg, sizeof msg), -1);
    assert_non_null(strstr(msg, "hard links"));
    assert_int_equal(mode_of(victim), 0640);
    unlink(p);
    /* A planted -wal companion (symlink) is refused before SQLite would open it. */
    char wal[320];
    path_in(p, sizeof p, "jobs.db");
    snprintf(wal, sizeof wal, "%s-wal", p);
    assert_int_equal(owned_db_companions_check(p, msg, sizeof msg), 0);
    assert_int_equal(symlink(victim, wal), 0);
    assert_int_equal(owned_db_companions_check(p, msg, sizeof msg), -1);
    assert_non_null(strstr(msg, "-wal"));
    unlink(wal);
    if (geteuid() == 0) {
        path_in(p, sizeof p, "theirs.db");
        fclose(fopen(p, "w"));
        assert_int_equal(chown(p, 65534, 65534), 0);
        assert_int_equal(owned_file_open(p, &fixed, msg, sizeof msg), -1);
        assert_non_null(strstr(msg, "belongs to uid 65534"));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_dirs, setup, teardown),
        cmocka_unit_test_setup_teardown(test_files, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
