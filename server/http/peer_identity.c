#define _GNU_SOURCE
#include "peer_identity.h"

#include <errno.h>
#include <linux/inet_diag.h>
#include <linux/netlink.h>
#include <linux/sock_diag.h>
#include <netinet/in.h>
#include <string.h>
#include <sys/time.h>
#include <unistd.h>

bool peer_addr_is_loopback(const struct sockaddr *sa, socklen_t len)
{
    if (!sa)
        return false;
    if (sa->sa_family == AF_INET && len >= (socklen_t)sizeof(struct sockaddr_in)) {
        const struct sockaddr_in *in = (const struct sockaddr_in *)sa;
        return (ntohl(in->sin_addr.s_addr) >> 24) == 127;
    }
    if (sa->sa_family == AF_INET6 && len >= (socklen_t)sizeof(struct sockaddr_in6)) {
        const struct in6_addr *a = &((const struct sockaddr_in6 *)sa)->sin6_addr;
        if (IN6_IS_ADDR_LOOPBACK(a))
            return true;
        return IN6_IS_ADDR_V4MAPPED(a) && a->s6_addr[12] == 127;
    }
    return false;
}

int peer_unix_uid(int fd, uid_t *uid)
{
    struct ucred cred;
    socklen_t len = sizeof cred;
    if (getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len))
        return -1;
    *uid = cred.uid;
    return 0;
}

/* One endpoint as inet_diag wants it: family, port (network order) and address words. */
typedef struct endpoint {
    int family;
    __be16 port;
    __be32 addr[4];
} endpoint;

static int to_endpoint(const struct sockaddr_storage *ss, endpoint *e)
{
    memset(e, 0, sizeof *e);
    if (ss->ss_family == AF_INET) {
        const struct sockaddr_in *in = (const struct sockaddr_in *)ss;
        e->family = AF_INET;
        e->port = in->sin_port;
        e->addr[0] = in->sin_addr.s_addr;
        return 0;
    }
    if (ss->ss_family == AF_INET6) {
        const struct sockaddr_in6 *in6 = (const struct sockaddr_in6 *)ss;
        e->port = in6->sin6_port;
        if (IN6_IS_ADDR_V4MAPPED(&in6->sin6_addr)) {
            /* The client of a dual-stack listener holds a plain AF_INET socket. */
            e->family = AF_INET;
            memcpy(&e->addr[0], &in6->sin6_addr.s6_addr[12], 4);
        } else {
            e->family = AF_INET6;
            memcpy(e->addr, &in6->sin6_addr, 16);
        }
        return 0;
    }
    errno = EAFNOSUPPORT;
    return -1;
}

int peer_tcp_uid(int fd, uid_t *uid)
{
    struct sockaddr_storage local, peer;
    socklen_t ll = sizeof local, pl = sizeof peer;
    endpoint me, them;
    if (getsockname(fd, (struct sockaddr *)&local, &ll) ||
        getpeername(fd, (struct sockaddr *)&peer, &pl) || to_endpoint(&local, &me) ||
        to_endpoint(&peer, &them))
        return -1;
    if (me.family != them.family) {
        errno = EAFNOSUPPORT;
        return -1;
    }
    /* The client's socket: its source is our peer, its destination is us. Without NLM_F_DUMP
     * the kernel does an exact lookup and answers one message (or an error). */
    struct {
        struct nlmsghdr nlh;
        struct inet_diag_req_v2 r;
    } req;
    memset(&req, 0, sizeof req);
    req.nlh.nlmsg_len = sizeof req;
    req.nlh.nlmsg_type = SOCK_DIAG_BY_FAMILY;
    req.nlh.nlmsg_flags = NLM_F_REQUEST;
    req.nlh.nlmsg_seq = 1;
    req.r.sdiag_family = (__u8)me.family;
    req.r.sdiag_protocol = IPPROTO_TCP;
    req.r.idiag_states = ~0u;
    req.r.id.idiag_sport = them.port;
    req.r.id.idiag_dport = me.port;
    memcpy(req.r.id.idiag_src, them.addr, sizeof them.addr);
    memcpy(req.r.id.idiag_dst, me.addr, sizeof me.addr);
    req.r.id.idiag_cookie[0] = req.r.id.idiag_cookie[1] = INET_DIAG_NOCOOKIE;

    int nl = socket(AF_NETLINK, SOCK_DGRAM | SOCK_CLOEXEC, NETLINK_SOCK_DIAG);
    if (nl < 0)
        return -1;
    /* The kernel answers at once; the timeout only guards the accept thread against surprises. */
    struct timeval tv = {.tv_sec = 1};
    setsockopt(nl, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    struct sockaddr_nl kernel = {.nl_family = AF_NETLINK};
    if (sendto(nl, &req, sizeof req, 0, (struct sockaddr *)&kernel, sizeof kernel) < 0) {
        close(nl);
        return -1;
    }
    union {
        struct nlmsghdr h;
        char buf[8192];
    } ans;
    ssize_t n = recv(nl, &ans, sizeof ans, 0);
    int saved = errno;
    close(nl);
    if (n < 0) {
        errno = saved;
        return -1;
    }
    for (struct nlmsghdr *h = &ans.h; NLMSG_OK(h, (size_t)n); h = NLMSG_NEXT(h, n)) {
        if (h->nlmsg_type == NLMSG_ERROR) {
            const struct nlmsgerr *e = NLMSG_DATA(h);
            errno = h->nlmsg_len >= NLMSG_LENGTH(sizeof *e) && e->error ? -e->error : EPROTO;
            return -1;
        }
        if (h->nlmsg_type == SOCK_DIAG_BY_FAMILY &&
            h->nlmsg_len >= NLMSG_LENGTH(sizeof(struct inet_diag_msg))) {
            const struct inet_diag_msg *m = NLMSG_DATA(h);
            if (m->id.idiag_sport != them.port || m->id.idiag_dport != me.port)
                continue;
            *uid = (uid_t)m->idiag_uid;
            return 0;
        }
    }
    errno = ENOENT;
    return -1;
}
