/* Who is on the other end of an accepted connection: the loopback check for the TCP listener,
 * the peer uid of a Unix-socket client (SO_PEERCRED) and of a loopback TCP client (the owner of
 * the connecting socket, asked of the kernel with NETLINK_SOCK_DIAG). The uids feed per-user
 * limits and fair share only; they never decide ownership on TCP. */
#ifndef AALAB_PEER_IDENTITY_H
#define AALAB_PEER_IDENTITY_H

#include <stdbool.h>
#include <sys/socket.h>
#include <sys/types.h>

/* 127.0.0.0/8, ::1 and ::ffff:127.0.0.0/104 are loopback; anything else (and AF_UNIX) is not. */
bool peer_addr_is_loopback(const struct sockaddr *sa, socklen_t len);
/* SO_PEERCRED of a connected AF_UNIX socket. 0 or -1 (errno set). */
int peer_unix_uid(int fd, uid_t *uid);
/* The owner uid of the socket at the other end of the connected TCP socket fd, which must be on
 * this host (loopback): an exact 4-tuple lookup with NETLINK_SOCK_DIAG (inet_diag_req_v2),
 * AF_INET or AF_INET6 (a v4-mapped peer is looked up as AF_INET). 0 or -1 (errno set). */
int peer_tcp_uid(int fd, uid_t *uid);

#endif
