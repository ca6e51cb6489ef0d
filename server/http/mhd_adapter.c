#define _GNU_SOURCE
#include "mhd_adapter.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <grp.h>
#include <netinet/in.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <microhttpd.h>

#include "accept_loop.h"
#include "api_context.h"
#include "body_budget.h"
#include "conn_admission.h"
#include "eval_cache.h"
#include "http_refusal.h"
#include "request_deadline.h"
#include "token_store.h"

/* Each listener: an accept thread of our own (accept_loop) that admits a connection
 * (conn_admission: loopback peer on TCP, peer uid, per-uid and total counts) before handing it
 * with MHD_add_connection to one of --http-threads libmicrohttpd daemons (round robin; each
 * has one epoll thread and no listen socket, since MHD_USE_NO_LISTEN_SOCKET rules out MHD's own
 * thread pool). Refused connections get a complete 429/503 JSON answer and are closed. The
 * counts are given back at MHD_CONNECTION_NOTIFY_CLOSED. POST /v1/evaluate (unless cached or
 * within --inline-work), POST /v1/predict and POST /v1/render are suspended and run on the shared
 * compute pool, which resumes them. */
#define MAX_HTTP_DAEMONS 64

struct http_listener {
    struct MHD_Daemon *daemons[MAX_HTTP_DAEMONS];
    int ndaemons;
    unsigned next; /* round robin; only the accept thread touches it */
    api_context *ctx;
    size_t max_body;
    size_t inline_work; /* --inline-work */
    bool is_unix;
    int fd;
    request_deadline *deadline;
    conn_admission *adm;
    compute_pool *pool;
    accept_loop *acceptor;
    http_log_fn log;
};

typedef struct request_state {
    char *body;
    size_t len, cap;
    size_t limit;   /* this endpoint's body limit (api_body_limit) */
    size_t counted; /* bytes held in the user's --user-body-bytes budget */
    uint64_t user;  /* the peer uid (COMPUTE_USER_UNKNOWN): the budget's key and req's peer */
    bool too_large, over_budget;
    /* A request run on the compute pool: req/resp are handed over through the pool's queue
     * and back through done (release/acquire), since libmicrohttpd's resume is not a
     * synchronisation the race detector can see. */
    bool offloaded;
    atomic_bool done;
    http_listener *l;
    struct MHD_Connection *conn;
    api_request req;
    api_response resp;
    api_deferred *deferred; /* decoded on the HTTP thread, run on the pool (try_inline) */
    char query[1024];
    compute_task task;
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
    /* Mode and group are set through an O_PATH descriptor of the socket file, checked to be
     * a socket of ours: a name swapped for a symlink or another file meanwhile is never
     * followed or changed. The mode again, since a default ACL on the directory overrides the
     * umask; /proc/self/fd is how an O_PATH descriptor is chmod'ed. */
    int pfd = open(path, O_PATH | O_NOFOLLOW | O_CLOEXEC);
    struct stat sst;
    if (pfd >= 0 && (fstat(pfd, &sst) || !S_ISSOCK(sst.st_mode) || sst.st_uid != geteuid())) {
        close(pfd);
        pfd = -1;
    }
    if (pfd < 0) {
        snprintf(msg, cap, "%s changed under us after bind (not our socket any more)", path);
        close(fd);
        return -1;
    }
    char fd_path[40];
    snprintf(fd_path, sizeof fd_path, "/proc/self/fd/%d", pfd);
    chmod(fd_path, 0660);
    if (group && *group) {
        struct group *g = getgrnam(group);
        int crc = g ? fchownat(pfd, "", (uid_t)-1, g->gr_gid, AT_EMPTY_PATH) : -1;
        if (!g || crc) {
            snprintf(msg, cap, "cannot give %s to group %s: %s", path, group,
                     g ? strerror(errno) : "no such group");
            close(pfd);
            close(fd);
            unlink(path);
            return -1;
        }
    }
    close(pfd);
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

static enum MHD_Result send_response(struct MHD_Connection *conn, api_response *r, bool close)
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
    if (close)
        MHD_add_response_header(resp, MHD_HTTP_HEADER_CONNECTION, "close");
    enum MHD_Result ret = MHD_queue_response(conn, (unsigned)r->status, resp);
    MHD_destroy_response(resp);
    request_deadline_sending(conn);
    return ret;
}

/* Counts more of a request's body in its user's budget (rounded up to 64 KiB for chunked
 * uploads, so a trickle does not take the lock per byte). */
static bool count_body(http_listener *l, request_state *st, size_t more)
{
    size_t step = st->counted ? ((more + 65535) & ~(size_t)65535) : more;
    if (!body_budget_acquire(api_context_body_budget(l->ctx), st->user, step))
        return false;
    st->counted += step;
    return true;
}

static enum MHD_Result reply_body_limit(struct MHD_Connection *conn, size_t limit, size_t max_body)
{
    api_response r = {0};
    api_reply_wire(&r, WIRE_PAYLOAD_TOO_LARGE, "",
                   "the body exceeds %zu bytes, this endpoint's limit%s", limit,
                   limit == max_body ? " (--max-body)" : "");
    return send_response(conn, &r, true);
}

static enum MHD_Result reply_over_budget(http_listener *l, struct MHD_Connection *conn)
{
    api_response r = {0};
    api_reply_wire(&r, WIRE_TOO_MANY_REQUESTS, "",
                   "your request bodies in flight would exceed %zu bytes (--user-body-bytes); "
                   "retry when one has been answered",
                   body_budget_limit(api_context_body_budget(l->ctx)));
    return send_response(conn, &r, true);
}

static void pool_run(void *arg)
{
    request_state *st = arg;
    if (st->deferred) {
        memset(&st->resp, 0, sizeof st->resp);
        st->deferred->run(st->deferred, &st->resp);
        st->deferred->free(st->deferred);
        st->deferred = NULL;
    } else {
        api_handle(st->l->ctx, &st->req, &st->resp);
    }
}

static void pool_done(void *arg)
{
    request_state *st = arg;
    struct MHD_Connection *conn = st->conn;
    atomic_store_explicit(&st->done, true, memory_order_release);
    MHD_resume_connection(conn); /* last touch: the connection may be answered and freed now */
}

/* Bodies up to this size are decoded on the HTTP thread to see whether the evaluate is small
 * enough to run there (about 48 explicit samples). Larger bodies go to the pool undecoded: a
 * 10 KB pattern of 256 samples decodes in hundreds of microseconds, and a second user's flood of
 * such bodies decoded here made the first user's p50 2.2 ms instead of 0.5 ms (bench_http_pool,
 * with a 16 KiB limit). */
#define INLINE_MAX_BODY (2u << 10)

/* An uncached evaluate small enough to cost less than the hand-off to the compute pool runs
 * here, in the user's evaluate share (docs/http.md: the threshold and its measurement). True if
 * it was answered (*ret then holds the result); false to hand it to the pool, with the decoded
 * call in st->deferred when the handler got that far (the pool does not decode it again). */
static bool try_inline(http_listener *l, struct MHD_Connection *conn, request_state *st,
                       const api_request *req, uint64_t user, enum MHD_Result *ret)
{
    if (!l->inline_work || req->body_len > INLINE_MAX_BODY || strcmp(req->path, "/v1/evaluate"))
        return false;
    /* Without room in the share only what costs no work is answered here: a cached answer
     * (outside the share, as before) or a bad request; the rest meets the pool's 429. */
    bool shared = compute_pool_acquire_share(l->pool, COMPUTE_EVALUATE, user);
    api_request small = *req;
    small.inline_work_limit = shared ? l->inline_work : 1;
    api_response resp;
    api_handle(l->ctx, &small, &resp);
    if (shared)
        compute_pool_release_share(l->pool, COMPUTE_EVALUATE, user);
    if (resp.needs_pool) {
        st->deferred = resp.deferred;
        resp.deferred = NULL;
        api_response_free(&resp);
        return false;
    }
    *ret = send_response(conn, &resp, false);
    return true;
}

/* Evaluate (not cached, not small: try_inline, which also answers cache hits, keyed per user)
 * and render go to the compute pool: the
 * connection is suspended until the pool has the answer. True if the request was taken
 * (suspended, answered inline or answered 429/503); *ret is then what to return. */
static bool run_on_pool(http_listener *l, struct MHD_Connection *conn, request_state *st,
                        const api_request *req, enum MHD_Result *ret)
{
    /* A large job spec is API_CLASS_PREDICT: the evaluate share, never the evaluate cache. */
    api_request_class cls = api_classify(req->method, req->path, req->body_len);
    if (!l->pool || cls == API_CLASS_OTHER)
        return false;
    compute_class compute = cls == API_CLASS_RENDER ? COMPUTE_RENDER : COMPUTE_EVALUATE;
    bool known = l->is_unix ? req->peer_known : req->tcp_peer_known;
    uid_t uid = l->is_unix ? req->peer_uid : req->tcp_peer_uid;
    uint64_t user = known ? (uint64_t)uid : COMPUTE_USER_UNKNOWN;
    *ret = MHD_YES;
    if (cls == API_CLASS_EVALUATE && try_inline(l, conn, st, req, user, ret))
        return true;
    st->l = l;
    st->conn = conn;
    st->req = *req;
    st->task = (compute_task){
        .run = pool_run, .done = pool_done, .arg = st, .compute = compute, .user = user};
    /* Suspend before submitting: the pool may resume the connection at once. */
    st->offloaded = true;
    MHD_suspend_connection(conn);
    compute_admit a = compute_pool_submit(l->pool, &st->task);
    if (a == COMPUTE_QUEUED)
        return true;
    if (st->deferred) {
        st->deferred->free(st->deferred);
        st->deferred = NULL;
    }
    api_response *r = &st->resp;
    if (a == COMPUTE_OVER_SHARE)
        api_reply_wire(r, WIRE_TOO_MANY_REQUESTS, "",
                       "you already have %d %s running (%s); retry when one has finished",
                       compute_pool_share(l->pool, compute),
                       compute == COMPUTE_RENDER ? "render(s)" : "evaluate(s)",
                       compute == COMPUTE_RENDER ? "--user-renders" : "--user-evaluates");
    else
        api_reply_wire(r, WIRE_BUSY, "",
                       a == COMPUTE_FULL ? "the compute queue is full; retry shortly"
                                         : "the daemon is shutting down");
    atomic_store_explicit(&st->done, true, memory_order_release);
    MHD_resume_connection(conn);
    return true;
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
        if (!l->is_unix) {
            const union MHD_ConnectionInfo *ci =
                MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CONNECTION_FD);
            const char *auth =
                MHD_lookup_connection_value(conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_AUTHORIZATION);
            /* Counted by the token's validated id (a SHA-256 and a lookup, once per
             * connection); an invalid token is not counted and the router answers 401. */
            long long token_uid, token_id = -1;
            if (auth && !strncasecmp(auth, "Bearer ", 7) &&
                token_store_check(api_context_tokens(l->ctx), auth + 7, &token_uid, &token_id))
                token_id = -1;
            if (ci && !conn_admission_token(l->adm, ci->connect_fd, token_id)) {
                api_response r = {0};
                api_reply_wire(&r, WIRE_TOO_MANY_REQUESTS, "",
                               "this token already has %d open connections "
                               "(--token-connections)",
                               conn_admission_token_limit(l->adm));
                return send_response(conn, &r, true);
            }
        }
        /* Bounds before the body is read: this endpoint's limit (413), then the user's bodies in
         * flight (429): a flood of 8 MiB bodies to a small endpoint costs nothing. */
        const char *cl =
            MHD_lookup_connection_value(conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_LENGTH);
        unsigned long long announced = cl ? strtoull(cl, NULL, 10) : 0;
        st->limit = api_body_limit(method, url, l->max_body);
        if (announced > st->limit)
            return reply_body_limit(conn, st->limit, l->max_body);
        const union MHD_ConnectionInfo *fdi =
            MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CONNECTION_FD);
        conn_peer peer;
        st->user = fdi && conn_admission_peer(l->adm, fdi->connect_fd, &peer) && peer.uid_known
                       ? (uint64_t)peer.uid
                       : COMPUTE_USER_UNKNOWN;
        if (announced && !count_body(l, st, (size_t)announced))
            return reply_over_budget(l, conn);
        return MHD_YES;
    }
    if (*upload_data_size) {
        size_t n = *upload_data_size;
        *upload_data_size = 0;
        if (!st->too_large && !st->over_budget && st->len + n > st->counted &&
            !count_body(l, st, st->len + n - st->counted))
            st->over_budget = true; /* a chunked upload past the user's budget */
        if (st->too_large || st->over_budget || st->len + n > st->limit) {
            st->too_large = !st->over_budget; /* keep reading and dropping; answer at the end */
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
    if (st->over_budget)
        return reply_over_budget(l, conn);
    if (st->too_large)
        return reply_body_limit(conn, st->limit, l->max_body);

    if (st->offloaded) {
        /* Resumed: the pool has stored the answer. */
        if (!atomic_load_explicit(&st->done, memory_order_acquire))
            return MHD_YES;
        return send_response(conn, &st->resp, false);
    }

    query_builder q = {.len = 0};
    MHD_get_connection_values(conn, MHD_GET_ARGUMENT_KIND, add_query_arg, &q);
    memcpy(st->query, q.buf, q.len + 1 <= sizeof st->query ? q.len + 1 : sizeof st->query);
    st->query[sizeof st->query - 1] = 0;
    api_request req = {
        .method = method,
        .path = url,
        .query = q.len ? st->query : NULL,
        .content_type =
            MHD_lookup_connection_value(conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_TYPE),
        .host = MHD_lookup_connection_value(conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_HOST),
        .authorization =
            MHD_lookup_connection_value(conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_AUTHORIZATION),
        .body = st->body,
        .body_len = st->len,
        .via_tcp = !l->is_unix,
    };
    /* The peer as the request's first call found it (st->user). */
    if (st->user != COMPUTE_USER_UNKNOWN) {
        if (l->is_unix) {
            req.peer_known = true;
            req.peer_uid = (uid_t)st->user;
        } else {
            req.tcp_peer_known = true;
            req.tcp_peer_uid = (uid_t)st->user;
        }
    }
    request_deadline_received(conn);
    enum MHD_Result ret;
    if (run_on_pool(l, conn, st, &req, &ret))
        return ret;
    api_response resp;
    api_handle(l->ctx, &req, &resp);
    return send_response(conn, &resp, false);
}

static void on_completed(void *cls, struct MHD_Connection *conn, void **con_cls,
                         enum MHD_RequestTerminationCode toe)
{
    request_deadline_completed(conn);
    request_state *st = *con_cls;
    if (st) {
        http_listener *l = cls;
        if (st->counted)
            body_budget_release(api_context_body_budget(l->ctx), st->user, st->counted);
        if (st->offloaded && atomic_load_explicit(&st->done, memory_order_acquire))
            api_response_free(&st->resp); /* not sent (the client went away) */
        free(st->body);
        free(st);
        *con_cls = NULL;
    }
}

static void on_connection(void *cls, struct MHD_Connection *conn, void **socket_context,
                          enum MHD_ConnectionNotificationCode code)
{
    http_listener *l = cls;
    request_deadline_notify(l->deadline, conn, socket_context, code);
    const union MHD_ConnectionInfo *fdi =
        MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CONNECTION_FD);
    double accepted;
    /* The request clock started at accept, not when the request line had arrived. */
    if (code == MHD_CONNECTION_NOTIFY_STARTED && fdi &&
        conn_admission_accepted_at(l->adm, fdi->connect_fd, &accepted))
        request_deadline_backdate(*socket_context, accepted);
    if (code == MHD_CONNECTION_NOTIFY_CLOSED) {
        const union MHD_ConnectionInfo *ci =
            MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CONNECTION_FD);
        if (ci)
            conn_admission_release(l->adm, ci->connect_fd);
    }
}

/* libmicrohttpd's own messages, through the daemon's log. A connection handed over with
 * MHD_add_connection is not known to be a Unix socket, so libmicrohttpd tries TCP_NODELAY and
 * TCP_CORK on it and reports each failure: harmless there (no Nagle on AF_UNIX), so dropped. */
__attribute__((format(printf, 2, 0))) static void mhd_log(void *cls, const char *fmt, va_list ap)
{
    http_listener *l = cls;
    char line[512];
    vsnprintf(line, sizeof line, fmt, ap);
    line[strcspn(line, "\n")] = 0;
    if (l->is_unix && (strstr(line, "TCP_NODELAY") || strstr(line, "TCP_CORK") ||
                       strstr(line, "Failed to push the data")))
        return;
    if (l->log)
        l->log(line);
}

/* The accept thread: admit (loopback, uid, counts). Never blocks: sock_diag is a local kernel
 * round trip, refusals are one non-blocking send. */
static bool on_accepted(void *cls, int fd, const struct sockaddr *sa, socklen_t len)
{
    http_listener *l = cls;
    conn_peer peer;
    char line[160], host[INET6_ADDRSTRLEN] = "?";
    switch (conn_admission_admit(l->adm, fd, sa, len, &peer)) {
    case ADMIT_OK:
        return true;
    case ADMIT_NOT_LOOPBACK:
        if (sa->sa_family == AF_INET)
            inet_ntop(AF_INET, &((const struct sockaddr_in *)sa)->sin_addr, host, sizeof host);
        else if (sa->sa_family == AF_INET6)
            inet_ntop(AF_INET6, &((const struct sockaddr_in6 *)sa)->sin6_addr, host, sizeof host);
        snprintf(line, sizeof line, "refused a TCP connection from %s: not a loopback address",
                 host);
        if (l->log)
            l->log(line);
        close(fd);
        return false;
    case ADMIT_USER_LIMIT:
        snprintf(line, sizeof line,
                 "this user already has %d open connections (--user-connections)",
                 conn_admission_user_limit(l->adm));
        http_refuse(fd, WIRE_TOO_MANY_REQUESTS, line);
        return false;
    case ADMIT_TOTAL_LIMIT:
        snprintf(line, sizeof line, "the daemon has %d open connections (--connection-limit)",
                 conn_admission_total_limit(l->adm));
        http_refuse(fd, WIRE_BUSY, line);
        return false;
    case ADMIT_NO_MEMORY:
        break;
    }
    close(fd);
    return false;
}

/* The request line has arrived (accept_loop): serve it, or answer the malformations
 * libmicrohttpd would answer in HTML with the JSON error document. */
static void on_first_line(void *cls, int fd, const struct sockaddr *sa, socklen_t len,
                          accept_outcome outcome)
{
    http_listener *l = cls;
    if (outcome != ACCEPT_HANDOVER) {
        conn_admission_release(l->adm, fd); /* before the fd is closed and can be reused */
        if (outcome == ACCEPT_BAD_VERSION)
            http_refuse(fd, WIRE_HTTP_VERSION, "this server speaks HTTP/1.0 and HTTP/1.1");
        else if (outcome == ACCEPT_BAD_REQUEST)
            http_refuse(fd, WIRE_BAD_REQUEST,
                        "malformed request line (expected: METHOD /path HTTP/1.1)");
        else
            close(fd);
        return;
    }
    struct MHD_Daemon *d = l->daemons[l->next++ % (unsigned)l->ndaemons];
    /* An unnamed Unix peer has a 2-byte address; libmicrohttpd takes a short address for an IP
     * socket and tries TCP options on it, so it is given a whole sockaddr_un. */
    struct sockaddr_un un = {.sun_family = AF_UNIX};
    if (sa->sa_family == AF_UNIX) {
        sa = (const struct sockaddr *)&un;
        len = sizeof un;
    }
    if (MHD_add_connection(d, fd, sa, len) != MHD_YES)
        conn_admission_release(l->adm, fd); /* MHD has closed fd */
}

http_listener *http_listener_start(api_context *ctx, const aalab_config *cfg, int fd, bool is_unix,
                                   compute_pool *pool, http_log_fn log, char *msg, size_t cap)
{
    http_listener *l = calloc(1, sizeof *l);
    if (!l) {
        snprintf(msg, cap, "out of memory");
        return NULL;
    }
    l->ctx = ctx;
    l->max_body = cfg->max_body;
    l->inline_work = cfg->inline_work;
    l->is_unix = is_unix;
    l->fd = fd;
    l->pool = pool;
    l->log = log;
    l->deadline = request_deadline_start(cfg->request_timeout, cfg->answer_timeout);
    l->adm = conn_admission_create(is_unix, cfg->connection_limit, cfg->user_connections,
                                   cfg->token_connections);
    if (!l->deadline || !l->adm) {
        snprintf(msg, cap, "could not start the request watchdog");
        http_listener_stop(l);
        return NULL;
    }
    /* One epoll thread per daemon; handlers only do fast work (jobs go to the worker pool,
     * evaluate and render to the compute pool). The admission enforces --connection-limit;
     * each daemon's own limit is only a backstop. */
    unsigned int flags = MHD_USE_EPOLL_INTERNAL_THREAD | MHD_USE_ERROR_LOG | MHD_USE_ITC |
                         MHD_USE_NO_LISTEN_SOCKET | MHD_ALLOW_SUSPEND_RESUME;
    int n = cfg->http_threads < 1                  ? 1
            : cfg->http_threads > MAX_HTTP_DAEMONS ? MAX_HTTP_DAEMONS
                                                   : cfg->http_threads;
    for (; l->ndaemons < n; l->ndaemons++) {
        struct MHD_Daemon *d = MHD_start_daemon(
            flags, 0, NULL, NULL, on_request, l, MHD_OPTION_EXTERNAL_LOGGER, mhd_log, l,
            MHD_OPTION_CONNECTION_LIMIT, (unsigned int)cfg->connection_limit,
            MHD_OPTION_CONNECTION_TIMEOUT, (unsigned int)cfg->connection_timeout,
            MHD_OPTION_CONNECTION_MEMORY_LIMIT, cfg->connection_memory,
            MHD_OPTION_UNESCAPE_CALLBACK, unescape_keep_nul, NULL, MHD_OPTION_NOTIFY_COMPLETED,
            on_completed, l, MHD_OPTION_NOTIFY_CONNECTION, on_connection, l, MHD_OPTION_END);
        if (!d) {
            snprintf(msg, cap, "libmicrohttpd could not start for fd %d", fd);
            http_listener_stop(l);
            return NULL;
        }
        l->daemons[l->ndaemons] = d;
    }
    l->acceptor =
        accept_loop_start(fd, (double)cfg->request_timeout, on_accepted, on_first_line, l);
    if (!l->acceptor) {
        snprintf(msg, cap, "could not start the accept thread for fd %d", fd);
        l->fd = -1; /* the caller still owns it */
        http_listener_stop(l);
        return NULL;
    }
    return l;
}

void http_listener_quiesce(http_listener *l)
{
    if (l && l->acceptor) {
        accept_loop_stop(l->acceptor);
        l->acceptor = NULL;
        close(l->fd);
        l->fd = -1;
    }
}

void http_listener_stop(http_listener *l)
{
    if (!l)
        return;
    http_listener_quiesce(l);
    for (int i = 0; i < l->ndaemons; i++)
        MHD_stop_daemon(l->daemons[i]);
    request_deadline_stop(l->deadline);
    conn_admission_destroy(l->adm);
    free(l);
}
