/* A first look at the request line of a new connection, before libmicrohttpd parses it, so that
 * the two malformations libmicrohttpd 0.9.75 answers with its own HTML (or not at all) get the
 * JSON error document instead: a version other than HTTP/1.x (505: "GET / HTTP/9.9", the
 * HTTP/2 preface "PRI * HTTP/2.0") and a line that is no request line (400). Tolerant where
 * libmicrohttpd is (leading empty lines, runs of spaces): anything it would serve passes. */
#ifndef AALAB_REQUEST_LINE_H
#define AALAB_REQUEST_LINE_H

#include <stddef.h>

typedef enum {
    REQUEST_LINE_INCOMPLETE, /* no line end yet: look again when more bytes arrive */
    REQUEST_LINE_OK,         /* hand the connection to libmicrohttpd */
    REQUEST_LINE_BAD,        /* 400: not "METHOD TARGET HTTP/x.y" */
    REQUEST_LINE_BAD_VERSION /* 505: HTTP/x.y with x != 1 */
} request_line_verdict;

/* buf holds the first n bytes received (not NUL-terminated). */
request_line_verdict request_line_check(const char *buf, size_t n);

#endif
