/* Atomic file replacement (atomic_file.h). */
#define _POSIX_C_SOURCE 200809L
#include "atomic_file.h"

#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int write_all(int fd, const char *s, size_t n)
{
    while (n) {
        ssize_t w = write(fd, s, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        s += w;
        n -= (size_t)w;
    }
    return 0;
}

static int sync_dir_of(const char *path)
{
    char *copy = strdup(path);
    if (!copy)
        return -1;
    int fd = open(dirname(copy), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    free(copy);
    if (fd < 0)
        return -1;
    int rc = fsync(fd);
    close(fd);
    return rc;
}

int atomic_write_json(const char *path, const json_t *j, const char *field, aa_error *err)
{
    char *text = json_dumps(j, JSON_COMPACT | JSON_REAL_PRECISION(17));
    if (!text)
        return aa_error_set(err, AA_ENOMEM, field, "out of memory");
    size_t n = strlen(path) + 16;
    char *tmp = malloc(n);
    if (!tmp) {
        free(text);
        return aa_error_set(err, AA_ENOMEM, field, "out of memory");
    }
    /* The pid keeps a retried task (a new process) off a killed one's leftover. */
    snprintf(tmp, n, "%s.%ld.tmp", path, (long)getpid());
    int rc = AA_OK;
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        rc = aa_error_set(err, ATOMIC_EIO, field, "cannot create %s: %s", tmp, strerror(errno));
    } else {
        if (write_all(fd, text, strlen(text)) || write_all(fd, "\n", 1) || fsync(fd))
            rc = aa_error_set(err, ATOMIC_EIO, field, "cannot write %s: %s", tmp, strerror(errno));
        if (close(fd) && !rc)
            rc = aa_error_set(err, ATOMIC_EIO, field, "cannot write %s: %s", tmp, strerror(errno));
        if (!rc && rename(tmp, path))
            rc = aa_error_set(err, ATOMIC_EIO, field, "cannot rename %s to %s: %s", tmp, path,
                              strerror(errno));
        if (!rc && sync_dir_of(path))
            rc = aa_error_set(err, ATOMIC_EIO, field, "cannot sync the directory of %s: %s", path,
                              strerror(errno));
        if (rc)
            unlink(tmp);
    }
    free(tmp);
    free(text);
    return rc;
}
