/* A complete, tiny HTTP/1.1 answer written to a socket libmicrohttpd never saw (a connection
 * refused at accept): status line, JSON error document, Connection: close. Written with one
 * non-blocking send (it fits any socket buffer); the socket is closed afterwards either way. */
#ifndef AALAB_HTTP_REFUSAL_H
#define AALAB_HTTP_REFUSAL_H

/* message must not need JSON escaping (our own fixed texts). retry_after > 0 adds Retry-After. */
void http_refuse(int fd, int status, const char *code, const char *message, int retry_after);

#endif
