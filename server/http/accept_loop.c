#define _GNU_SOURCE
#include "accept_loop.h"
#include "aa_core.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <time.h>
#include <unistd.h>

#include "request_line.h"

/* Longer request lines are libmicrohttpd's to judge (it answers 414 itself). */
#define PEEK_BYTES 2048

typedef struct waiting {
    bool used;
    double since;
    struct sockaddr_storage peer;
    socklen_t len;
} waiting;

struct accept_loop {
    pthread_t thread;
    int listen_fd, stop_fd, ep;
    double first_line_seconds;
    accept_admit_fn admit;
    accept_outcome_fn outcome;
    void *cls;
    /* Only the loop's thread touches these. */
    waiting *by_fd;
    size_t cap;
    int count;
};

static void finish(accept_loop *al, int fd, accept_outcome o)
{
    waiting w = al->by_fd[fd];
    epoll_ctl(al->ep, EPOLL_CTL_DEL, fd, NULL);
    al->by_fd[fd].used = false;
    al->count--;
    al->outcome(al->cls, fd, (struct sockaddr *)&w.peer, w.len, o);
}

static void watch(accept_loop *al, int fd, const struct sockaddr_storage *ss, socklen_t len)
{
    if ((size_t)fd >= al->cap) {
        size_t cap = al->cap ? al->cap : 256;
        while (cap <= (size_t)fd)
            cap *= 2;
        waiting *grown = realloc(al->by_fd, cap * sizeof *grown);
        if (!grown) {
            al->outcome(al->cls, fd, (const struct sockaddr *)ss, len, ACCEPT_GONE);
            return;
        }
        memset(grown + al->cap, 0, (cap - al->cap) * sizeof *grown);
        al->by_fd = grown;
        al->cap = cap;
    }
    al->by_fd[fd] =
        (waiting){.used = true, .since = aa_monotonic_seconds(), .peer = *ss, .len = len};
    al->count++;
    struct epoll_event ev = {.events = EPOLLIN | EPOLLRDHUP | EPOLLET, .data.fd = fd};
    if (epoll_ctl(al->ep, EPOLL_CTL_ADD, fd, &ev))
        finish(al, fd, ACCEPT_GONE);
}

/* Bytes (or a hang-up) arrived on a waiting connection. */
static void look(accept_loop *al, int fd, uint32_t events)
{
    char buf[PEEK_BYTES];
    ssize_t n = recv(fd, buf, sizeof buf, MSG_PEEK | MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EINTR))
        return;
    if (n <= 0) {
        finish(al, fd, ACCEPT_GONE);
        return;
    }
    switch (request_line_check(buf, (size_t)n)) {
    case REQUEST_LINE_OK:
        finish(al, fd, ACCEPT_HANDOVER);
        return;
    case REQUEST_LINE_BAD:
        finish(al, fd, ACCEPT_BAD_REQUEST);
        return;
    case REQUEST_LINE_BAD_VERSION:
        finish(al, fd, ACCEPT_BAD_VERSION);
        return;
    case REQUEST_LINE_INCOMPLETE:
        if (n == (ssize_t)sizeof buf)
            finish(al, fd, ACCEPT_HANDOVER);
        else if (events & (EPOLLRDHUP | EPOLLHUP | EPOLLERR))
            finish(al, fd, ACCEPT_GONE);
        return;
    }
}

/* Accepts what is pending; false when out of fds (the caller pauses the listening socket). */
static bool accept_all(accept_loop *al)
{
    for (;;) {
        struct sockaddr_storage ss;
        socklen_t len = sizeof ss;
        int fd = accept4(al->listen_fd, (struct sockaddr *)&ss, &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0)
            return !(errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM);
        if (al->admit(al->cls, fd, (struct sockaddr *)&ss, len)) {
            watch(al, fd, &ss, len);
            /* Bytes that came with the connection raise no edge later: look now. */
            if ((size_t)fd < al->cap && al->by_fd[fd].used)
                look(al, fd, 0);
        }
    }
}

static void expire(accept_loop *al, double now)
{
    for (size_t fd = 0; fd < al->cap && al->count; fd++)
        if (al->by_fd[fd].used && now - al->by_fd[fd].since > al->first_line_seconds)
            finish(al, (int)fd, ACCEPT_GONE);
}

static void *accept_main(void *arg)
{
    accept_loop *al = arg;
    double paused_until = 0; /* out of fds: the listening socket rests, not spins */
    for (;;) {
        struct epoll_event ev[64];
        int timeout = al->count ? 250 : -1;
        if (paused_until > 0)
            timeout = 50;
        int n = epoll_wait(al->ep, ev, 64, timeout);
        if (n < 0 && errno != EINTR)
            break;
        bool stop = false, listen_ready = false;
        for (int i = 0; i < n; i++) {
            if (ev[i].data.fd == al->stop_fd)
                stop = true;
            else if (ev[i].data.fd == al->listen_fd)
                listen_ready = true;
            else if ((size_t)ev[i].data.fd < al->cap && al->by_fd[ev[i].data.fd].used)
                look(al, ev[i].data.fd, ev[i].events);
        }
        if (stop)
            break;
        double now = aa_monotonic_seconds();
        if (paused_until > 0 && now >= paused_until) {
            struct epoll_event lev = {.events = EPOLLIN, .data.fd = al->listen_fd};
            epoll_ctl(al->ep, EPOLL_CTL_MOD, al->listen_fd, &lev);
            paused_until = 0;
            listen_ready = true;
        }
        if (listen_ready && paused_until == 0 && !accept_all(al)) {
            struct epoll_event off = {.events = 0, .data.fd = al->listen_fd};
            epoll_ctl(al->ep, EPOLL_CTL_MOD, al->listen_fd, &off);
            paused_until = now + 0.05;
        }
        if (al->count)
            expire(al, now);
    }
    for (size_t fd = 0; fd < al->cap && al->count; fd++)
        if (al->by_fd[fd].used)
            finish(al, (int)fd, ACCEPT_GONE);
    return NULL;
}

accept_loop *accept_loop_start(int listen_fd, double first_line_seconds, accept_admit_fn admit,
                               accept_outcome_fn outcome, void *cls)
{
    accept_loop *al = calloc(1, sizeof *al);
    if (!al)
        return NULL;
    al->listen_fd = listen_fd;
    al->first_line_seconds = first_line_seconds;
    al->admit = admit;
    al->outcome = outcome;
    al->cls = cls;
    al->stop_fd = al->ep = -1;
    /* A socket from systemd may be blocking: accept() must return EAGAIN once drained, or the
     * thread would sit in accept() and never see the stop event. */
    int fl = fcntl(listen_fd, F_GETFL);
    struct epoll_event lev = {.events = EPOLLIN, .data.fd = listen_fd};
    if (fl < 0 || fcntl(listen_fd, F_SETFL, fl | O_NONBLOCK) ||
        (al->stop_fd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) < 0 ||
        (al->ep = epoll_create1(EPOLL_CLOEXEC)) < 0 ||
        epoll_ctl(al->ep, EPOLL_CTL_ADD, listen_fd, &lev))
        goto fail;
    struct epoll_event sev = {.events = EPOLLIN, .data.fd = al->stop_fd};
    if (epoll_ctl(al->ep, EPOLL_CTL_ADD, al->stop_fd, &sev) ||
        pthread_create(&al->thread, NULL, accept_main, al))
        goto fail;
    return al;
fail:
    if (al->stop_fd >= 0)
        close(al->stop_fd);
    if (al->ep >= 0)
        close(al->ep);
    free(al);
    return NULL;
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
    close(al->ep);
    free(al->by_fd);
    free(al);
}
