/* A thread that accepts connections on a listening socket so the HTTP layer can look at the
 * peer (address, uid, counts) and at the request line before libmicrohttpd sees the socket.
 * An admitted connection waits (epoll, edge-triggered, MSG_PEEK: nothing is consumed) until its
 * request line has arrived; request_line_check() then decides whether it goes to
 * libmicrohttpd or gets a JSON 400/505. Nothing here blocks: a connection whose line does not
 * come within first_line_seconds, or that closes first, is dropped. */
#ifndef AALAB_ACCEPT_LOOP_H
#define AALAB_ACCEPT_LOOP_H

#include <stdbool.h>
#include <sys/socket.h>

typedef enum {
    ACCEPT_HANDOVER,    /* request line fine (or too long to judge): serve it */
    ACCEPT_BAD_REQUEST, /* answer 400 */
    ACCEPT_BAD_VERSION, /* answer 505 */
    ACCEPT_GONE         /* closed by the peer, timed out or shutting down: close it */
} accept_outcome;

/* On accept (fd non-blocking, close-on-exec): true if admitted (the loop watches it), false if
 * the callback has refused and closed it. */
typedef bool (*accept_admit_fn)(void *cls, int fd, const struct sockaddr *peer, socklen_t len);
/* The outcome for an admitted connection; the callback owns fd from here on. */
typedef void (*accept_outcome_fn)(void *cls, int fd, const struct sockaddr *peer, socklen_t len,
                                  accept_outcome outcome);

typedef struct accept_loop accept_loop;

/* NULL if the thread cannot start. listen_fd stays the caller's (made non-blocking). */
accept_loop *accept_loop_start(int listen_fd, double first_line_seconds, accept_admit_fn admit,
                               accept_outcome_fn outcome, void *cls);
/* Stops accepting, gives every waiting connection ACCEPT_GONE and joins the thread. */
void accept_loop_stop(accept_loop *al);

#endif
