/* Trust checks for the daemon's directories and private files (owned_path.h). */
#define _GNU_SOURCE
#include "owned_path.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int make_dirs(const char *path, mode_t mode)
{
    char tmp[PATH_MAX];
    if (snprintf(tmp, sizeof tmp, "%s", path) >= (int)sizeof tmp) {
        errno = ENAMETOOLONG;
        return -1;
    }
    for (char *p = tmp + 1; *p; p++) {
        if (*p == '/') {
            *p = 0;
            if (mkdir(tmp, 0755) && errno != EEXIST)
                return -1;
            *p = '/';
        }
    }
    if (mkdir(tmp, mode) && errno != EEXIST)
        return -1;
    return 0;
}

/* Every directory above path (not path itself): owned by root or us, and not writable by group
 * or others unless sticky, since whoever can write one of them can rename what is below it and
 * put their own directory in its place. stat follows symlinks: a symlinked component is judged
 * by where it leads, and the real path is walked too (owned_dir_prepare). */
static int check_ancestor(const char *dir, const char *what, const char *target, char *msg,
                          size_t cap)
{
    struct stat st;
    if (stat(dir, &st)) {
        snprintf(msg, cap, "%s: %s", dir, strerror(errno));
        return -1;
    }
    if (st.st_uid != 0 && st.st_uid != geteuid()) {
        snprintf(msg, cap,
                 "%s (above the %s %s) belongs to uid %u, neither root nor us (uid %u): its "
                 "owner could replace the %s; use another path",
                 dir, what, target, (unsigned)st.st_uid, (unsigned)geteuid(), what);
        return -1;
    }
    if ((st.st_mode & 022) && !(st.st_mode & S_ISVTX)) {
        snprintf(msg, cap,
                 "%s (above the %s %s) has mode %04o: other users could replace the %s; "
                 "chmod go-w it or use another path",
                 dir, what, target, (unsigned)(st.st_mode & 07777), what);
        return -1;
    }
    return 0;
}

/* Every directory above the absolute path (not path itself): owned by root or us, and not
 * writable by group or others unless sticky (/tmp), since whoever can write one of them can
 * rename what is below it and put their own directory in its place. stat follows symlinks: a
 * symlinked component is judged by where it leads (and the real path is walked too). */
static int check_ancestors(const char *path, const char *what, const char *target, char *msg,
                           size_t cap)
{
    if (check_ancestor("/", what, target, msg, cap))
        return -1;
    char pre[PATH_MAX];
    size_t n = strlen(path);
    if (n >= sizeof pre)
        return snprintf(msg, cap, "path too long: %s", path), -1;
    for (size_t i = 1; i < n; i++) {
        if (path[i] != '/')
            continue;
        memcpy(pre, path, i);
        pre[i] = 0;
        if (check_ancestor(pre, what, target, msg, cap))
            return -1;
    }
    return 0;
}

int owned_dir_prepare(const char *path, mode_t mode, const char *what, char *msg, size_t cap)
{
    char abs[PATH_MAX];
    if (path[0] == '/') {
        if (snprintf(abs, sizeof abs, "%s", path) >= (int)sizeof abs)
            return snprintf(msg, cap, "path too long: %s", path), -1;
    } else {
        char cwd[PATH_MAX];
        if (!getcwd(cwd, sizeof cwd) ||
            snprintf(abs, sizeof abs, "%s/%s", cwd, path) >= (int)sizeof abs)
            return snprintf(msg, cap, "cannot make %s absolute", path), -1;
    }
    size_t n = strlen(abs);
    while (n > 1 && abs[n - 1] == '/')
        abs[--n] = 0;
    if (make_dirs(abs, mode)) {
        snprintf(msg, cap, "cannot create the %s %s: %s", what, abs, strerror(errno));
        return -1;
    }
    char real[PATH_MAX];
    if (!realpath(abs, real)) {
        snprintf(msg, cap, "%s %s: %s", what, abs, strerror(errno));
        return -1;
    }
    if (check_ancestors(abs, what, abs, msg, cap) ||
        (strcmp(real, abs) && check_ancestors(real, what, abs, msg, cap)))
        return -1;
    struct stat st;
    if (lstat(real, &st)) {
        snprintf(msg, cap, "%s %s: %s", what, abs, strerror(errno));
        return -1;
    }
    if (!S_ISDIR(st.st_mode)) {
        snprintf(msg, cap, "the %s %s is not a directory", what, abs);
        return -1;
    }
    if (st.st_uid != geteuid()) {
        snprintf(msg, cap,
                 "the %s %s belongs to uid %u, not to us (uid %u): its owner could plant files "
                 "in it; chown it to uid %u or use another path",
                 what, abs, (unsigned)st.st_uid, (unsigned)geteuid(), (unsigned)geteuid());
        return -1;
    }
    if (st.st_mode & 022) {
        snprintf(msg, cap,
                 "the %s %s has mode %04o: writable by group or others, who could plant files "
                 "in it; chmod go-w it",
                 what, abs, (unsigned)(st.st_mode & 07777));
        return -1;
    }
    return 0;
}

/* A file the daemon keeps: regular, ours, one link. */
static int check_own_file(const char *path, const struct stat *st, char *msg, size_t cap)
{
    if (!S_ISREG(st->st_mode)) {
        snprintf(msg, cap, "%s is not a regular file; refusing to use it", path);
        return -1;
    }
    if (st->st_uid != geteuid()) {
        snprintf(msg, cap,
                 "%s belongs to uid %u, not to us (uid %u); refusing to use it (remove it, or "
                 "chown it if it is really ours)",
                 path, (unsigned)st->st_uid, (unsigned)geteuid());
        return -1;
    }
    if (st->st_nlink != 1) {
        snprintf(msg, cap, "%s has %lu hard links; refusing to use it", path,
                 (unsigned long)st->st_nlink);
        return -1;
    }
    return 0;
}

int owned_file_open(const char *path, mode_t *fixed_mode, char *msg, size_t cap)
{
    *fixed_mode = 0;
    /* O_NONBLOCK: a planted FIFO must not hang the start. */
    int fd = open(path, O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY | O_NONBLOCK, 0600);
    if (fd < 0) {
        if (errno == ELOOP)
            snprintf(msg, cap, "%s is a symlink; refusing to follow it", path);
        else
            snprintf(msg, cap, "cannot open %s: %s", path, strerror(errno));
        return -1;
    }
    struct stat st;
    if (fstat(fd, &st)) {
        snprintf(msg, cap, "%s: %s", path, strerror(errno));
        close(fd);
        return -1;
    }
    if (check_own_file(path, &st, msg, cap)) {
        close(fd);
        return -1;
    }
    if ((st.st_mode & 07777) != 0600) {
        if (fchmod(fd, 0600)) {
            snprintf(msg, cap, "cannot chmod 600 %s: %s", path, strerror(errno));
            close(fd);
            return -1;
        }
        *fixed_mode = st.st_mode & 07777;
    }
    int fl = fcntl(fd, F_GETFL);
    if (fl >= 0)
        fcntl(fd, F_SETFL, fl & ~O_NONBLOCK);
    return fd;
}

int owned_db_companions_check(const char *path, char *msg, size_t cap)
{
    static const char *const suffixes[] = {"-wal", "-shm", "-journal"};
    for (size_t i = 0; i < sizeof suffixes / sizeof *suffixes; i++) {
        char p[PATH_MAX];
        if (snprintf(p, sizeof p, "%s%s", path, suffixes[i]) >= (int)sizeof p)
            return snprintf(msg, cap, "path too long: %s", path), -1;
        struct stat st;
        if (lstat(p, &st)) {
            if (errno == ENOENT)
                continue;
            snprintf(msg, cap, "%s: %s", p, strerror(errno));
            return -1;
        }
        if (S_ISLNK(st.st_mode)) {
            snprintf(msg, cap, "%s is a symlink; refusing to follow it", p);
            return -1;
        }
        if (check_own_file(p, &st, msg, cap))
            return -1;
    }
    return 0;
}
