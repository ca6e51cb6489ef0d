/* The libmicrohttpd layer: listeners on a Unix socket (0660, stale files handled) and an
 * optional loopback TCP port, each an MHD daemon with an internal epoll thread pool. It only
 * collects the request (headers, body up to --max-body, SO_PEERCRED uid), calls api_handle()
 * and sends the api_response. */
#ifndef AALAB_MHD_ADAPTER_H
#define AALAB_MHD_ADAPTER_H

#include <stdbool.h>

#include "api.h"
#include "config.h"

typedef struct http_listener http_listener;

/* Creates and binds the Unix socket at path: parent directory created (0755) if missing, a
 * stale socket file (nobody accepting) replaced, a live one or a non-socket refused. Mode 0660,
 * group changed to group if not empty. Returns the listening fd or -1 (message in msg). */
int http_unix_socket_open(const char *path, const char *group, char *msg, size_t cap);
/* Binds host:port (host must be a loopback address). Returns fd or -1. */
int http_tcp_socket_open(const char *host, int port, char *msg, size_t cap);

/* Starts serving fd (already listening). is_unix enables SO_PEERCRED; via_tcp marks requests
 * for the Host/token checks and static files. */
http_listener *http_listener_start(api_context *ctx, const aalab_config *cfg, int fd, bool is_unix,
                                   char *msg, size_t cap);
/* Stops accepting new connections (before the final drain). */
void http_listener_quiesce(http_listener *l);
void http_listener_stop(http_listener *l);

#endif
