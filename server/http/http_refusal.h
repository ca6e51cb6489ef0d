/* A complete, tiny HTTP/1.1 answer written to a socket libmicrohttpd never saw (a connection
 * refused at accept): status line, JSON error document, Connection: close. Written with one
 * non-blocking send (it fits any socket buffer); the socket is closed afterwards either way. */
#ifndef AALAB_HTTP_REFUSAL_H
#define AALAB_HTTP_REFUSAL_H

#include "wire_error.h"

/* Status, wire code and Retry-After come from e's row of the error table. message must not need
 * JSON escaping (our own fixed texts). */
void http_refuse(int fd, proto_wire_error e, const char *message);

#endif
