#define _GNU_SOURCE
#include "accept_loop.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <stdlib.h>
#include <sys/eventfd.h>
#include <unistd.h>

struct accept_loop {
    pthread_t thread;
    int listen_fd, stop_fd;
    accept_fn fn;
    void *cls;
};

static void *accept_main(void *arg)
{
    accept_loop *al = arg;
    struct pollfd p[2] = {{.fd = al->listen_fd, .events = POLLIN},
                          {.fd = al->stop_fd, .events = POLLIN}};
    int backoff = -1;
    for (;;) {
        if (poll(p, 2, backoff) < 0 && errno != EINTR)
            break;
        if (p[1].revents)
            break;
        backoff = -1;
        for (;;) {
            struct sockaddr_storage ss;
            socklen_t len = sizeof ss;
            int fd =
                accept4(al->listen_fd, (struct sockaddr *)&ss, &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
            if (fd < 0) {
                /* Out of fds: wait a little rather than spin on a pending connection. */
                if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM)
                    backoff = 50;
                break;
            }
            al->fn(al->cls, fd, (struct sockaddr *)&ss, len);
        }
    }
    return NULL;
}

accept_loop *accept_loop_start(int listen_fd, accept_fn fn, void *cls)
{
    accept_loop *al = calloc(1, sizeof *al);
    if (!al)
        return NULL;
    al->listen_fd = listen_fd;
    al->fn = fn;
    al->cls = cls;
    /* A socket from systemd may be blocking: accept() must return EAGAIN once drained, or the
     * thread would sit in accept() and never see the stop event. */
    int fl = fcntl(listen_fd, F_GETFL);
    if (fl < 0 || fcntl(listen_fd, F_SETFL, fl | O_NONBLOCK)) {
        free(al);
        return NULL;
    }
    al->stop_fd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    if (al->stop_fd < 0) {
        free(al);
        return NULL;
    }
    if (pthread_create(&al->thread, NULL, accept_main, al)) {
        close(al->stop_fd);
        free(al);
        return NULL;
    }
    return al;
}

void accept_loop_stop(accept_loop *al)
{
    if (!al)
        return;
    uint64_t one = 1;
    ssize_t n = write(al->stop_fd, &one, sizeof one);
    (void)n; /* an eventfd write of 1 cannot fail short of overflow */
    pthread_join(al->thread, NULL);
    close(al->stop_fd);
    free(al);
}
