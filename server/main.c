/* aalabd: the aalab daemon. Listens on a Unix socket (and optionally loopback TCP), serves the
 * JSON API and runs jobs on a worker pool; SIGTERM/SIGINT stop it gracefully (running jobs are
 * checkpointed as queued and re-run at the next start). Socket activation via LISTEN_FDS and
 * readiness via sd_notify when run by systemd. */
#define _GNU_SOURCE
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <systemd/sd-daemon.h>

#include "aalab_version.h"
#include "api_context.h"
#include "config.h"
#include "fallback_dir.h"
#include "mhd_adapter.h"
#include "owned_path.h"
#include "peer_identity.h"

#define MAX_LISTENERS 8

/* The group of the Unix socket's file (ours, or the first activated one with a path): who may
 * connect, so whose tokens count. -1 if not found. */
static int socket_file_stat(int activated, const char *own_path, struct stat *out)
{
    struct stat st;
    if (activated <= 0)
        return stat(own_path, &st) == 0 && S_ISSOCK(st.st_mode) ? (*out = st, 0) : -1;
    for (int i = 0; i < activated; i++) {
        struct sockaddr_un un;
        socklen_t len = sizeof un;
        memset(&un, 0, sizeof un);
        if (getsockname(SD_LISTEN_FDS_START + i, (struct sockaddr *)&un, &len) == 0 &&
            un.sun_family == AF_UNIX && un.sun_path[0] && stat(un.sun_path, &st) == 0 &&
            S_ISSOCK(st.st_mode)) {
            *out = st;
            return 0;
        }
    }
    return -1;
}

static void log_line(const char *line)
{
    fprintf(stderr, "aalabd: %s\n", line);
}

/* A TCP socket handed over by systemd must be bound to loopback: the listener serves loopback
 * peers only, and a wider bind is a configuration mistake to report, not to half-serve. */
static bool activated_tcp_is_loopback(int fd, char *msg, size_t cap)
{
    struct sockaddr_storage ss;
    socklen_t len = sizeof ss;
    if (getsockname(fd, (struct sockaddr *)&ss, &len)) {
        snprintf(msg, cap, "cannot read the address of socket-activated fd %d: %s", fd,
                 strerror(errno));
        return false;
    }
    if (peer_addr_is_loopback((struct sockaddr *)&ss, len))
        return true;
    char host[INET6_ADDRSTRLEN] = "?";
    int port = 0;
    if (ss.ss_family == AF_INET) {
        inet_ntop(AF_INET, &((struct sockaddr_in *)&ss)->sin_addr, host, sizeof host);
        port = ntohs(((struct sockaddr_in *)&ss)->sin_port);
    } else if (ss.ss_family == AF_INET6) {
        inet_ntop(AF_INET6, &((struct sockaddr_in6 *)&ss)->sin6_addr, host, sizeof host);
        port = ntohs(((struct sockaddr_in6 *)&ss)->sin6_port);
    }
    snprintf(msg, cap,
             "the socket-activated TCP socket (fd %d) is bound to %s port %d, not a loopback "
             "address; bind it to 127.0.0.1 or [::1] (ListenStream=127.0.0.1:%d)",
             fd, host, port, port ? port : 8765);
    return false;
}

int main(int argc, char **argv)
{
    aalab_config cfg;
    config_defaults(&cfg);
    int prc = config_parse_args(&cfg, argc, argv, stdout, stderr);
    if (prc)
        return prc > 0 ? 0 : 2;

    /* Block the stop signals before any thread exists, so that only sigwait() sees them. */
    sigset_t stop;
    sigemptyset(&stop);
    sigaddset(&stop, SIGTERM);
    sigaddset(&stop, SIGINT);
    sigaddset(&stop, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &stop, NULL);
    signal(SIGPIPE, SIG_IGN);

    /* Claim the socket first: a second daemon must fail before it touches the job store. */
    char msg[512];
    int activated = sd_listen_fds(1);
    int unix_fd = -1;
    if ((activated <= 0 && fallback_dir_check(cfg.socket_path, msg, sizeof msg)) ||
        fallback_dir_check(cfg.state_dir, msg, sizeof msg)) {
        fprintf(stderr, "aalabd: %s\n", msg);
        return 1;
    }
    /* Another user who can write the state or socket directory could plant jobs.db, tokens.db
     * or a symlink for the socket: such directories are refused, not trusted. */
    char socket_dir[sizeof cfg.socket_path];
    snprintf(socket_dir, sizeof socket_dir, "%s", cfg.socket_path);
    char *slash = strrchr(socket_dir, '/');
    if (slash)
        *(slash == socket_dir ? slash + 1 : slash) = 0;
    else
        snprintf(socket_dir, sizeof socket_dir, ".");
    if ((activated <= 0 &&
         owned_dir_prepare(socket_dir, 0755, "socket directory", msg, sizeof msg)) ||
        owned_dir_prepare(cfg.state_dir, 0700, "state directory", msg, sizeof msg)) {
        fprintf(stderr, "aalabd: %s\n", msg);
        return 1;
    }
    if (activated <= 0) {
        unix_fd = http_unix_socket_open(cfg.socket_path, cfg.socket_group, msg, sizeof msg);
        if (unix_fd < 0) {
            fprintf(stderr, "aalabd: %s\n", msg);
            return 1;
        }
    }
    for (int i = 0; i < activated; i++) {
        int fd = SD_LISTEN_FDS_START + i;
        if (sd_is_socket_unix(fd, SOCK_STREAM, 1, NULL, 0) <= 0 &&
            !activated_tcp_is_loopback(fd, msg, sizeof msg)) {
            fprintf(stderr, "aalabd: %s\n", msg);
            return 1;
        }
    }
    /* Name an activated TCP listener before the context copies cfg: the dashboard line and
     * GET /v1/health's "dashboard" (aalab token prints it) show it. */
    for (int i = 0; i < activated && !cfg.tcp_port; i++) {
        int fd = SD_LISTEN_FDS_START + i;
        struct sockaddr_storage ss;
        socklen_t len = sizeof ss;
        char host[INET6_ADDRSTRLEN] = "";
        if (sd_is_socket_unix(fd, SOCK_STREAM, 1, NULL, 0) <= 0 &&
            !getsockname(fd, (struct sockaddr *)&ss, &len) && ss.ss_family == AF_INET) {
            struct sockaddr_in *in = (struct sockaddr_in *)&ss;
            inet_ntop(AF_INET, &in->sin_addr, host, sizeof host);
            snprintf(cfg.tcp_host, sizeof cfg.tcp_host, "%s", host);
            cfg.tcp_port = ntohs(in->sin_port);
        }
    }
    aa_error err = {0};
    api_context *ctx = api_context_create(&cfg, &err);
    if (!ctx) {
        fprintf(stderr, "aalabd: %s\n", err.message);
        if (unix_fd >= 0) {
            close(unix_fd);
            unlink(cfg.socket_path);
        }
        return 1;
    }

    /* A token counts only while its owner may still connect to the socket, and so does a
     * connection already open on the socket (api_context_socket_peer_ok). */
    struct stat socket_st;
    bool socket_known = socket_file_stat(activated, cfg.socket_path, &socket_st) == 0;
    if (socket_known)
        api_context_tie_socket_access(ctx, socket_st.st_uid, socket_st.st_mode);
    if (socket_known && api_context_tie_tokens_to_group(ctx, socket_st.st_gid)) {
        fprintf(stderr, "aalabd: out of memory\n");
        api_context_destroy(ctx);
        if (unix_fd >= 0) {
            close(unix_fd);
            unlink(cfg.socket_path);
        }
        return 1;
    }

    /* Evaluate and render run here, shared by the listeners so the per-user shares are the
     * daemon's. The queue holds at most one task per allowed connection. */
    compute_pool *pool = compute_pool_create(cfg.compute_threads, cfg.user_evaluates,
                                             cfg.user_renders, cfg.connection_limit);
    if (!pool) {
        fprintf(stderr, "aalabd: could not start %d compute threads\n", cfg.compute_threads);
        api_context_destroy(ctx);
        if (unix_fd >= 0) {
            close(unix_fd);
            unlink(cfg.socket_path);
        }
        return 1;
    }

    http_listener *listeners[MAX_LISTENERS] = {0};
    int nl = 0;
    bool own_socket = false, have_tcp = false;
    if (activated > 0) {
        for (int i = 0; i < activated && nl < MAX_LISTENERS; i++) {
            int fd = SD_LISTEN_FDS_START + i;
            bool is_unix = sd_is_socket_unix(fd, SOCK_STREAM, 1, NULL, 0) > 0;
            listeners[nl] =
                http_listener_start(ctx, &cfg, fd, is_unix, pool, log_line, msg, sizeof msg);
            if (!listeners[nl]) {
                fprintf(stderr, "aalabd: %s\n", msg);
                goto fail;
            }
            have_tcp |= !is_unix;
            nl++;
        }
        printf("aalabd %s: socket-activated with %d listening socket(s)\n", aalab_version,
               activated);
    } else {
        int fd = unix_fd;
        own_socket = true;
        listeners[nl] = http_listener_start(ctx, &cfg, fd, true, pool, log_line, msg, sizeof msg);
        if (!listeners[nl]) {
            close(fd);
            fprintf(stderr, "aalabd: %s\n", msg);
            goto fail;
        }
        nl++;
        printf("aalabd %s listening on unix:%s\n", aalab_version, cfg.socket_path);
    }
    if (cfg.tcp_port && !have_tcp) {
        int fd = http_tcp_socket_open(cfg.tcp_host, cfg.tcp_port, msg, sizeof msg);
        if (fd < 0 || !(listeners[nl] = http_listener_start(ctx, &cfg, fd, false, pool, log_line,
                                                            msg, sizeof msg))) {
            if (fd >= 0)
                close(fd);
            fprintf(stderr, "aalabd: %s\n", msg);
            goto fail;
        }
        nl++;
        have_tcp = true;
    }
    /* No URL here: the page needs a token, and 'aalab token' prints the URL that carries one. */
    if (have_tcp && cfg.tcp_port)
        printf("dashboard: served on %s:%d (web dir %s); its URL with a token: aalab token\n",
               strchr(cfg.tcp_host, ':') ? "[::1]" : cfg.tcp_host, cfg.tcp_port, cfg.web_dir);
    else if (have_tcp)
        printf("dashboard: served on the activated TCP listener (web dir %s); its URL with a "
               "token: aalab token\n",
               cfg.web_dir);
    else
        printf("dashboard: off (start with --tcp 127.0.0.1:8765 to serve it)\n");
    printf("state: %s (%d workers)\n", cfg.state_dir, cfg.workers);
    if (have_tcp)
        printf("TCP requests need a bearer token: issue one on the socket with 'aalab token'\n");
    fflush(stdout);
    sd_notify(0, "READY=1\nSTATUS=serving");

    int sig = 0;
    sigwait(&stop, &sig);
    printf("aalabd: signal %d, shutting down\n", sig);
    fflush(stdout);
    sd_notify(0, "STOPPING=1\nSTATUS=stopping");

    for (int i = 0; i < nl; i++)
        http_listener_quiesce(listeners[i]);
    /* Checkpoint jobs first (running ones go back to queued), then drain HTTP. */
    api_context_shutdown(ctx);
    /* Finish the evaluates and renders in flight: their connections are resumed and answered
     * before the listeners stop. */
    compute_pool_stop(pool);
    for (int i = 0; i < nl; i++)
        http_listener_stop(listeners[i]);
    compute_pool_destroy(pool);
    if (own_socket)
        unlink(cfg.socket_path);
    api_context_destroy(ctx);
    printf("aalabd: stopped\n");
    return 0;

fail:
    compute_pool_stop(pool);
    for (int i = 0; i < nl; i++)
        http_listener_stop(listeners[i]);
    compute_pool_destroy(pool);
    if (own_socket)
        unlink(cfg.socket_path);
    api_context_destroy(ctx);
    return 1;
}
