/* Ownership check of /tmp/aalab-UID (fallback_dir.h). */
#define _GNU_SOURCE
#include "fallback_dir.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int fallback_dir_check(const char *path, char *msg, size_t cap)
{
    char dir[64];
    int n = snprintf(dir, sizeof dir, "/tmp/aalab-%u", (unsigned)geteuid());
    if (strncmp(path, dir, (size_t)n) || path[n] != '/')
        return 0;
    if (mkdir(dir, 0700) && errno != EEXIST) {
        snprintf(msg, cap, "cannot create %s: %s", dir, strerror(errno));
        return -1;
    }
    struct stat st;
    if (lstat(dir, &st)) {
        snprintf(msg, cap, "%s: %s", dir, strerror(errno));
        return -1;
    }
    if (!S_ISDIR(st.st_mode)) {
        snprintf(msg, cap, "%s is not a directory (a symlink?); refusing to use it for %s", dir,
                 path);
        return -1;
    }
    if (st.st_uid != geteuid()) {
        snprintf(msg, cap,
                 "%s belongs to uid %u, not to us (uid %u): another user could take over the "
                 "socket; remove it or set XDG_RUNTIME_DIR or --socket",
                 dir, (unsigned)st.st_uid, (unsigned)geteuid());
        return -1;
    }
    if ((st.st_mode & 07777) != 0700) {
        snprintf(msg, cap,
                 "%s has mode %04o, not 0700: other users could replace the socket; chmod 700 "
                 "it or remove it",
                 dir, (unsigned)(st.st_mode & 07777));
        return -1;
    }
    return 0;
}
