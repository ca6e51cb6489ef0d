/* HTTP over the daemon's Unix socket (libcurl, CURLOPT_UNIX_SOCKET_PATH). One handle per
 * process, reused across requests so polling keeps one connection. */
#ifndef AALAB_HTTP_H
#define AALAB_HTTP_H

#include <stddef.h>

typedef struct http_client http_client;

typedef struct http_response {
    long status;
    char *body; /* NUL-terminated (the NUL is not counted in len); malloc'd */
    size_t len;
    char content_type[128];
    long retry_after; /* seconds from a Retry-After header (429, 503), 0 if none */
} http_response;

/* timeout_ms <= 0 means no overall timeout. Returns NULL when libcurl cannot start. */
http_client *http_client_new(const char *socket_path, long timeout_ms);
void http_client_free(http_client *c);
/* The socket path the client connects to. */
const char *http_client_socket(const http_client *c);

enum { HTTP_BROKEN = -1, HTTP_NO_DAEMON = -2 };

/* method "GET", "POST", "DELETE"; path with query, e.g. "/v1/jobs/3". body may be NULL.
 * Returns 0 when an HTTP answer arrived (any status); HTTP_NO_DAEMON when nothing listens on the
 * socket (missing, refused, not permitted); HTTP_BROKEN when the exchange broke (err filled). */
int http_request(http_client *c, const char *method, const char *path, const char *body,
                 size_t body_len, http_response *out, char *err, size_t errcap);
void http_response_free(http_response *r);

#endif
