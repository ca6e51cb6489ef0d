/* What every command gets: the parsed arguments, the HTTP client and the output streams, plus
 * the one place that turns an HTTP exchange into an exit code and an error message. */
#ifndef AALAB_CLI_H
#define AALAB_CLI_H

#include <stdbool.h>
#include <stdio.h>

#include <jansson.h>

#include "args.h"
#include "http.h"

typedef struct cli_session {
    const cli_args *args;
    http_client *http;
    FILE *out; /* results (tables or JSON) */
    FILE *err; /* messages, progress */
} cli_session;

/* Sends body (borrowed, may be NULL) and, on a 2xx JSON answer, stores the parsed document in
 * *result (caller frees; may be NULL if not wanted). Otherwise prints the error (to err, and as
 * JSON to out with --json) and returns the exit code: 2 for 4xx, 3 for 5xx, 4 for no connection. */
int cli_call(cli_session *s, const char *method, const char *path, const json_t *body,
             json_t **result);
/* What a command prints of an answer without --json: a table, or text lines. */
typedef void (*cli_view)(FILE *out, const json_t *resp, bool csv);
/* cli_call, then the answer as JSON with --json, else through view (with --csv). Returns the
 * exit code. */
int cli_show(cli_session *s, const char *method, const char *path, const json_t *body,
             cli_view view);
/* Same, but keeps the raw 2xx body (PNG, export text) in *resp. */
int cli_call_raw(cli_session *s, const char *method, const char *path, http_response *resp);
/* cli_call_raw with a JSON body (borrowed). */
int cli_call_raw_body(cli_session *s, const char *method, const char *path, const json_t *body,
                      http_response *resp);

/* Prints a JSON document for scripts (indent 2, sorted as received, newline). */
void cli_print_json(FILE *out, const json_t *doc);
/* Prints an {"error":{...}} body (or a plain one) as one human-readable line to err. */
void cli_print_error(FILE *err, long status, const char *body);

/* What to do when no daemon answers at socket: why (no such file, permission, refused), the
 * paths tried (socket_path_tried) and how to start the daemon or point the client at it. */
void cli_print_no_daemon(FILE *err, const char *socket, const char *tried);

/* Percent-encodes everything but RFC 3986 unreserved characters (malloc'd; NULL on failure). */
char *url_escape_segment(const char *s);

/* Formatting helpers for table cells; buffers are the caller's. decimals FMT_FULL: the
 * shortest text that reads back as the same double (for CSV, where nothing should be lost). */
enum { FMT_FULL = -1 };
const char *fmt_number(char *buf, size_t cap, const json_t *v, int decimals);
/* decimals for a text table, FMT_FULL for CSV. */
static inline int fmt_decimals(bool csv, int decimals)
{
    return csv ? FMT_FULL : decimals;
}
const char *fmt_string(const json_t *v);

#endif
