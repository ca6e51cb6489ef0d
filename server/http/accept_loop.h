/* A thread that accepts connections on a listening socket and hands each to a callback, so the
 * HTTP layer can look at the peer (address, uid, counts) before libmicrohttpd sees the socket.
 * The callback owns the accepted fd (non-blocking, close-on-exec) and must not block. */
#ifndef AALAB_ACCEPT_LOOP_H
#define AALAB_ACCEPT_LOOP_H

#include <sys/socket.h>

typedef void (*accept_fn)(void *cls, int fd, const struct sockaddr *peer, socklen_t len);

typedef struct accept_loop accept_loop;

/* NULL if the thread cannot start. listen_fd stays the caller's. */
accept_loop *accept_loop_start(int listen_fd, accept_fn fn, void *cls);
/* Stops accepting and joins the thread (no callback runs after it returns). */
void accept_loop_stop(accept_loop *al);

#endif
