/* Exit codes of `aalab`, documented in the README and `aalab --help`; scripts rely on them. */
#ifndef AALAB_EXIT_CODES_H
#define AALAB_EXIT_CODES_H

enum {
    EXIT_OK = 0,
    EXIT_USAGE = 1,      /* bad arguments, or a local input file that is unreadable or invalid */
    EXIT_CLIENT_4XX = 2, /* the server answered 4xx (bad request, unknown id, not yours, 429) */
    EXIT_SERVER_5XX = 3, /* the server answered 5xx */
    EXIT_NO_CONNECT = 4, /* could not connect to the socket, or the connection broke */
    EXIT_JOB_FAILED = 5  /* --wait: the job ended failed, cancelled or interrupted */
};

/* Exit code for an HTTP status (2xx -> 0). */
int exit_code_for_status(long status);

#endif
