/* cluster_command.h: posix_spawnp with two pipes, read with poll until both close or the
 * deadline passes. posix_spawn, not fork: the daemon is multi-threaded and fork would copy
 * every thread's locks in whatever state they are. */
#define _GNU_SOURCE
#include "cluster_command.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

typedef struct sink {
    char *buf;
    size_t len, cap;
} sink;

static int sink_add(sink *s, const char *data, size_t n)
{
    /* Past the limit: keep reading to drain the pipe, store no more. */
    if (s->len >= CLUSTER_COMMAND_OUTPUT_MAX)
        return AA_OK;
    if (n > CLUSTER_COMMAND_OUTPUT_MAX - s->len)
        n = CLUSTER_COMMAND_OUTPUT_MAX - s->len;
    if (s->len + n + 1 > s->cap) {
        size_t cap = s->cap ? s->cap : 4096;
        while (cap < s->len + n + 1)
            cap *= 2;
        char *b = realloc(s->buf, cap);
        if (!b)
            return AA_ENOMEM;
        s->buf = b;
        s->cap = cap;
    }
    memcpy(s->buf + s->len, data, n);
    s->len += n;
    s->buf[s->len] = 0;
    return AA_OK;
}

/* An empty output is "" rather than NULL. */
static int sink_finish(sink *s)
{
    if (s->buf)
        return AA_OK;
    if (!(s->buf = calloc(1, 1)))
        return AA_ENOMEM;
    s->cap = 1;
    return AA_OK;
}

int cluster_command_run(char *const argv[], double timeout_seconds, cluster_output *out,
                        aa_error *err)
{
    *out = (cluster_output){0};
    int po[2] = {-1, -1}, pe[2] = {-1, -1};
    if (pipe2(po, O_CLOEXEC) || pipe2(pe, O_CLOEXEC)) {
        int e = errno;
        for (int i = 0; i < 2; i++) {
            if (po[i] >= 0)
                close(po[i]);
            if (pe[i] >= 0)
                close(pe[i]);
        }
        return aa_error_set(err, AA_EINVAL, "", "cannot run %s: pipe: %s", argv[0], strerror(e));
    }
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&fa, po[1], 1);
    posix_spawn_file_actions_adddup2(&fa, pe[1], 2);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    /* The daemon blocks some signals in its threads; the command starts with none blocked and
     * default dispositions, in a process group of its own so a timeout kills its children too. */
    sigset_t none, all;
    sigemptyset(&none);
    sigfillset(&all);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setsigdefault(&attr, &all);
    posix_spawnattr_setpgroup(&attr, 0);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF |
                                        POSIX_SPAWN_SETPGROUP);
    pid_t pid;
    int rc = posix_spawnp(&pid, argv[0], &fa, &attr, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    posix_spawnattr_destroy(&attr);
    close(po[1]);
    close(pe[1]);
    if (rc) {
        close(po[0]);
        close(pe[0]);
        return aa_error_set(err, AA_EINVAL, "", "cannot run %s: %s", argv[0], strerror(rc));
    }
    sink so = {0}, se = {0};
    double deadline = aa_monotonic_seconds() + timeout_seconds;
    struct pollfd fds[2] = {{po[0], POLLIN, 0}, {pe[0], POLLIN, 0}};
    int open_fds = 2, mem = AA_OK;
    while (open_fds > 0) {
        double left = deadline - aa_monotonic_seconds();
        if (left <= 0) {
            out->timed_out = true;
            kill(-pid, SIGKILL);
            break;
        }
        int n = poll(fds, 2, (int)(left * 1000) + 1);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            break;
        for (int i = 0; i < 2; i++) {
            if (fds[i].fd < 0 || !fds[i].revents)
                continue;
            char buf[4096];
            ssize_t r = read(fds[i].fd, buf, sizeof buf);
            if (r < 0 && (errno == EINTR || errno == EAGAIN))
                continue;
            if (r <= 0) {
                close(fds[i].fd);
                fds[i].fd = -1;
                open_fds--;
            } else if (mem == AA_OK) {
                mem = sink_add(i ? &se : &so, buf, (size_t)r);
            }
        }
    }
    for (int i = 0; i < 2; i++)
        if (fds[i].fd >= 0)
            close(fds[i].fd);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    out->exit_code = WIFEXITED(status)     ? WEXITSTATUS(status)
                     : WIFSIGNALED(status) ? 128 + WTERMSIG(status)
                                           : 255;
    if (mem == AA_OK)
        mem = sink_finish(&so);
    if (mem == AA_OK)
        mem = sink_finish(&se);
    out->out = so.buf;
    out->err = se.buf;
    if (mem != AA_OK) {
        cluster_output_free(out);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    return AA_OK;
}

void cluster_output_free(cluster_output *out)
{
    free(out->out);
    free(out->err);
    out->out = out->err = NULL;
}

void cluster_first_line(const char *s, char *buf, size_t cap)
{
    if (!cap)
        return;
    buf[0] = 0;
    if (!s)
        return;
    while (*s == ' ' || *s == '\n' || *s == '\t' || *s == '\r')
        s++;
    size_t n = strcspn(s, "\r\n");
    if (n >= cap)
        n = cap - 1;
    memcpy(buf, s, n);
    while (n > 0 && (buf[n - 1] == ' ' || buf[n - 1] == '\t'))
        n--;
    buf[n] = 0;
}
