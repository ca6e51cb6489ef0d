/* The libmicrohttpd layer: listeners on a Unix socket (0660, stale files handled) and an
 * optional loopback TCP port. Each admits connections on its own accept thread (loopback peers,
 * per-uid and total connection limits), serves them on --http-threads libmicrohttpd daemons,
 * collects the request (headers, body up to --max-body, peer uid), calls api_handle() (on the
 * compute pool for evaluate and render) and sends the api_response. */
#ifndef AALAB_MHD_ADAPTER_H
#define AALAB_MHD_ADAPTER_H

#include <stdbool.h>

#include "api.h"
#include "compute_pool.h"
#include "config.h"

typedef struct http_listener http_listener;

/* Creates and binds the Unix socket at path: parent directory created (0755) if missing, a
 * stale socket file (nobody accepting) replaced, a live one or a non-socket refused. Mode 0660,
 * group changed to group if not empty. Returns the listening fd or -1 (message in msg). */
int http_unix_socket_open(const char *path, const char *group, char *msg, size_t cap);
/* Binds host:port (host must be a loopback address). Returns fd or -1. */
int http_tcp_socket_open(const char *host, int port, char *msg, size_t cap);

/* One line about a refused peer (the daemon writes it to its log). */
typedef void (*http_log_fn)(const char *line);

/* Starts serving fd (already listening): admission at accept, requests on libmicrohttpd,
 * evaluate and render on pool (shared by the listeners; NULL runs them inline). is_unix
 * enables SO_PEERCRED; otherwise the TCP rules apply (loopback peers only, Host/token checks,
 * static files). On failure fd is still the caller's. */
http_listener *http_listener_start(api_context *ctx, const aalab_config *cfg, int fd, bool is_unix,
                                   compute_pool *pool, http_log_fn log, char *msg, size_t cap);
/* Stops accepting new connections and closes the listening fd (before the final drain). */
void http_listener_quiesce(http_listener *l);
void http_listener_stop(http_listener *l);

#endif
