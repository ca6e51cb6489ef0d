#define _GNU_SOURCE
#include "mhd_adapter.h"

#include <arpa/inet.h>
#include <errno.h>
#include <grp.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <microhttpd.h>

#include "request_deadline.h"

struct http_listener {
    struct MHD_Daemon *daemon;
    api_context *ctx;
    size_t max_body;
    bool is_unix;
    int fd;
    request_deadline *deadline;
};

typedef struct request_state {
    char *body;
    size_t len, cap;
    bool too_large;
} request_state;

/* --- sockets ------------------------------------------------------------------------------ */

static int make_parent_dir(const char *path)
{
    char dir[sizeof(((struct sockaddr_un *)0)->sun_path)];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (!slash || slash == dir)
        return 0;
    *slash = 0;
    for (char *p = dir + 1; *p; p++) {
        if (*p == '/') {
            *p = 0;
            mkdir(dir, 0755);
            *p = '/';
        }
    }
    if (mkdir(dir, 0755) && errno != EEXIST)
        return -1;
    return 0;
}

int http_unix_socket_open(const char *path, const char *group, char *msg, size_t cap)
{
    struct sockaddr_un addr = {.sun_family = AF_UNIX};
    if (strlen(path) >= sizeof addr.sun_path) {
        snprintf(msg, cap, "socket path too long: %s", path);
        return -1;
    }
    strcpy(addr.sun_path, path);
    if (make_parent_dir(path)) {
        snprintf(msg, cap, "cannot create the directory of %s: %s", path, strerror(errno));
        return -1;
    }
    struct stat st;
    if (lstat(path, &st) == 0) {
        if (!S_ISSOCK(st.st_mode)) {
            snprintf(msg, cap, "%s exists and is not a socket; refusing to replace it", path);
            return -1;
        }
        /* A socket file: live if someone accepts on it, stale otherwise. */
        int probe = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        int live = probe >= 0 && connect(probe, (struct sockaddr *)&addr, sizeof addr) == 0;
        int probe_errno = errno;
        if (probe >= 0)
            close(probe);
        if (live) {
            snprintf(msg, cap, "another daemon is listening on %s", path);
            return -1;
        }
        if (probe_errno != ECONNREFUSED && probe_errno != ENOENT) {
            snprintf(msg, cap, "cannot probe %s: %s", path, strerror(probe_errno));
            return -1;
        }
        unlink(path);
    }
    int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd < 0) {
        snprintf(msg, cap, "socket: %s", strerror(errno));
        return -1;
    }
    mode_t old = umask(0117); /* born 0660: no window with a wider mode */
    int rc = bind(fd, (struct sockaddr *)&addr, sizeof addr);
    umask(old);
    if (rc) {
        snprintf(msg, cap, "bind %s: %s", path, strerror(errno));
        close(fd);
        return -1;
    }
    chmod(path, 0660);
    if (group && *group) {
        struct group *g = getgrnam(group);
        if (!g || chown(path, (uid_t)-1, g->gr_gid)) {
            snprintf(msg, cap, "cannot give %s to group %s: %s", path, group,
                     g ? strerror(errno) : "no such group");
            close(fd);
            unlink(path);
            return -1;
        }
    }
    if (listen(fd, 128)) {
        snprintf(msg, cap, "listen %s: %s", path, strerror(errno));
        close(fd);
        unlink(path);
        return -1;
    }
    return fd;
}

int http_tcp_socket_open(const char *host, int port, char *msg, size_t cap)
{
    struct sockaddr_storage ss;
    memset(&ss, 0, sizeof ss);
    socklen_t len;
    int family;
    const char *h = !strcmp(host, "localhost") ? "127.0.0.1" : host;
    struct sockaddr_in *in4 = (struct sockaddr_in *)&ss;
    struct sockaddr_in6 *in6 = (struct sockaddr_in6 *)&ss;
    char h6[64];
    snprintf(h6, sizeof h6, "%s", h);
    if (h6[0] == '[') {
        memmove(h6, h6 + 1, strlen(h6));
        h6[strcspn(h6, "]")] = 0;
    }
    if (inet_pton(AF_INET, h, &in4->sin_addr) == 1) {
        family = AF_INET;
        in4->sin_family = AF_INET;
        in4->sin_port = htons((uint16_t)port);
        len = sizeof *in4;
        if ((ntohl(in4->sin_addr.s_addr) >> 24) != 127) {
            snprintf(msg, cap, "--tcp must bind a loopback address (127.0.0.0/8 or ::1)");
            return -1;
        }
    } else if (inet_pton(AF_INET6, h6, &in6->sin6_addr) == 1) {
        family = AF_INET6;
        in6->sin6_family = AF_INET6;
        in6->sin6_port = htons((uint16_t)port);
        len = sizeof *in6;
        if (!IN6_IS_ADDR_LOOPBACK(&in6->sin6_addr)) {
            snprintf(msg, cap, "--tcp must bind a loopback address (127.0.0.0/8 or ::1)");
            return -1;
        }
    } else {
        snprintf(msg, cap, "--tcp: '%s' is not an IP address or localhost", host);
        return -1;
    }
    int fd = socket(family, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    int one = 1;
    if (fd < 0 || setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) ||
        bind(fd, (struct sockaddr *)&ss, len) || listen(fd, 128)) {
        snprintf(msg, cap, "cannot listen on %s:%d: %s", host, port, strerror(errno));
        if (fd >= 0)
            close(fd);
        return -1;
    }
    return fd;
}

/* --- request handling --------------------------------------------------------------------- */

/* Percent-decoding that keeps "%00" literal: a decoded NUL would silently truncate the path
 * ("/index.html%00.png" must not become "/index.html"). */
static size_t unescape_keep_nul(void *cls, struct MHD_Connection *c, char *s)
{
    char *w = s;
    for (const char *r = s; *r;) {
        if (r[0] == '%' && r[1] && r[2]) {
            char hex[3] = {r[1], r[2], 0};
            char *end;
            unsigned long v = strtoul(hex, &end, 16);
            if (!*end && v != 0 && (hex[0] != '+' && hex[0] != '-' && hex[0] != ' ')) {
                *w++ = (char)v;
                r += 3;
                continue;
            }
        }
        *w++ = *r++;
    }
    *w = 0;
    return (size_t)(w - s);
}

typedef struct query_builder {
    char buf[1024];
    size_t len;
} query_builder;

static enum MHD_Result add_query_arg(void *cls, enum MHD_ValueKind kind, const char *key,
                                     const char *value)
{
    query_builder *q = cls;
    int n = snprintf(q->buf + q->len, sizeof q->buf - q->len, "%s%s=%s", q->len ? "&" : "", key,
                     value ? value : "");
    if (n > 0 && (size_t)n < sizeof q->buf - q->len)
        q->len += (size_t)n;
    return MHD_YES;
}

static enum MHD_Result send_response(struct MHD_Connection *conn, api_response *r)
{
    struct MHD_Response *resp =
        MHD_create_response_from_buffer(r->body_len, r->body ? r->body : (void *)"",
                                        r->body ? MHD_RESPMEM_MUST_FREE : MHD_RESPMEM_PERSISTENT);
    if (!resp) {
        api_response_free(r);
        return MHD_NO;
    }
    r->body = NULL; /* owned by MHD now */
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE,
                            r->content_type ? r->content_type : "application/json");
    MHD_add_response_header(resp, "X-Content-Type-Options", "nosniff");
    if (r->cache_control)
        MHD_add_response_header(resp, MHD_HTTP_HEADER_CACHE_CONTROL, r->cache_control);
    if (r->retry_after > 0) {
        char ra[16];
        snprintf(ra, sizeof ra, "%d", r->retry_after);
        MHD_add_response_header(resp, MHD_HTTP_HEADER_RETRY_AFTER, ra);
    }
    enum MHD_Result ret = MHD_queue_response(conn, (unsigned)r->status, resp);
    MHD_destroy_response(resp);
    return ret;
}

static enum MHD_Result reply_simple_error(struct MHD_Connection *conn, int status, const char *code,
                                          const char *message)
{
    api_response r = {0};
    api_reply_error(&r, status, code, "", "%s", message);
    return send_response(conn, &r);
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *conn, const char *url,
                                  const char *method, const char *version, const char *upload_data,
                                  size_t *upload_data_size, void **con_cls)
{
    http_listener *l = cls;
    request_state *st = *con_cls;
    if (!st) {
        st = calloc(1, sizeof *st);
        if (!st)
            return MHD_NO;
        *con_cls = st;
        const char *cl =
            MHD_lookup_connection_value(conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_LENGTH);
        if (cl && strtoull(cl, NULL, 10) > l->max_body)
            return reply_simple_error(conn, 413, "payload_too_large",
                                      "the body exceeds the daemon's --max-body");
        return MHD_YES;
    }
    if (*upload_data_size) {
        size_t n = *upload_data_size;
        *upload_data_size = 0;
        if (st->too_large || st->len + n > l->max_body) {
            st->too_large = true; /* keep reading and dropping; answer 413 at the end */
            free(st->body);
            st->body = NULL;
            st->len = st->cap = 0;
            return MHD_YES;
        }
        if (st->len + n > st->cap) {
            size_t cap = st->cap ? st->cap : 4096;
            while (cap < st->len + n)
                cap *= 2;
            char *b = realloc(st->body, cap);
            if (!b)
                return MHD_NO;
            st->body = b;
            st->cap = cap;
        }
        memcpy(st->body + st->len, upload_data, n);
        st->len += n;
        return MHD_YES;
    }
    if (st->too_large)
        return reply_simple_error(conn, 413, "payload_too_large",
                                  "the body exceeds the daemon's --max-body");

    query_builder q = {.len = 0};
    MHD_get_connection_values(conn, MHD_GET_ARGUMENT_KIND, add_query_arg, &q);
    api_request req = {
        .method = method,
        .path = url,
        .query = q.len ? q.buf : NULL,
        .content_type =
            MHD_lookup_connection_value(conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_TYPE),
        .host = MHD_lookup_connection_value(conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_HOST),
        .authorization =
            MHD_lookup_connection_value(conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_AUTHORIZATION),
        .body = st->body,
        .body_len = st->len,
        .via_tcp = !l->is_unix,
    };
    if (l->is_unix) {
        const union MHD_ConnectionInfo *ci =
            MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CONNECTION_FD);
        struct ucred cred;
        socklen_t len = sizeof cred;
        if (ci && getsockopt(ci->connect_fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) == 0) {
            req.peer_known = true;
            req.peer_uid = cred.uid;
        }
    }
    request_deadline_received(conn);
    api_response resp;
    api_handle(l->ctx, &req, &resp);
    return send_response(conn, &resp);
}

static void on_completed(void *cls, struct MHD_Connection *conn, void **con_cls,
                         enum MHD_RequestTerminationCode toe)
{
    request_deadline_completed(conn);
    request_state *st = *con_cls;
    if (st) {
        free(st->body);
        free(st);
        *con_cls = NULL;
    }
}

http_listener *http_listener_start(api_context *ctx, const aalab_config *cfg, int fd, bool is_unix,
                                   char *msg, size_t cap)
{
    http_listener *l = calloc(1, sizeof *l);
    if (!l) {
        snprintf(msg, cap, "out of memory");
        return NULL;
    }
    l->ctx = ctx;
    l->max_body = cfg->max_body;
    l->is_unix = is_unix;
    l->fd = fd;
    /* epoll with a small internal thread pool: request handlers only do fast work (jobs go
     * to the worker pool), so a pool the size of the core count keeps both cores busy. */
    unsigned int flags = MHD_USE_EPOLL_INTERNAL_THREAD | MHD_USE_ERROR_LOG | MHD_USE_ITC;
    l->deadline = request_deadline_start(cfg->request_timeout);
    if (!l->deadline) {
        snprintf(msg, cap, "could not start the request watchdog");
        free(l);
        return NULL;
    }
    l->daemon = MHD_start_daemon(
        flags, 0, NULL, NULL, on_request, l, MHD_OPTION_LISTEN_SOCKET, (MHD_socket)fd,
        MHD_OPTION_THREAD_POOL_SIZE, (unsigned int)cfg->http_threads, MHD_OPTION_CONNECTION_LIMIT,
        (unsigned int)cfg->connection_limit, MHD_OPTION_CONNECTION_TIMEOUT,
        (unsigned int)cfg->connection_timeout, MHD_OPTION_CONNECTION_MEMORY_LIMIT,
        cfg->connection_memory, MHD_OPTION_UNESCAPE_CALLBACK, unescape_keep_nul, NULL,
        MHD_OPTION_NOTIFY_COMPLETED, on_completed, NULL, MHD_OPTION_NOTIFY_CONNECTION,
        request_deadline_notify, l->deadline, MHD_OPTION_LISTEN_BACKLOG_SIZE, 128u, MHD_OPTION_END);
    if (!l->daemon) {
        snprintf(msg, cap, "libmicrohttpd could not start on fd %d", fd);
        request_deadline_stop(l->deadline);
        free(l);
        return NULL;
    }
    return l;
}

void http_listener_quiesce(http_listener *l)
{
    if (l && l->daemon) {
        MHD_socket s = MHD_quiesce_daemon(l->daemon);
        if (s != MHD_INVALID_SOCKET)
            close(s);
    }
}

void http_listener_stop(http_listener *l)
{
    if (!l)
        return;
    if (l->daemon)
        MHD_stop_daemon(l->daemon);
    request_deadline_stop(l->deadline);
    free(l);
}
