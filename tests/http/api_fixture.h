/* A fixture for tests that call api_handle directly (no socket): an api_context on a fresh
 * temporary state dir, and requests sent as if over the Unix socket. */
#ifndef AALAB_TESTS_API_FIXTURE_H
#define AALAB_TESTS_API_FIXTURE_H

#include <sys/types.h>

#include <jansson.h>

#include "api.h"
#include "api_context.h"
#include "config.h"

typedef struct api_fixture {
    char dir[64];
    aalab_config cfg;
    api_context *ctx;
} api_fixture;

/* Config defaults with the state dir under a new /tmp/aalab-test-<name>-XXXXXX, changed by
 * configure (may be NULL) before the context is created; fails the test on any error. */
api_fixture *api_fixture_open(const char *name, void (*configure)(aalab_config *cfg));

/* Destroys the context and removes the temporary dir; 0, or -1 if the dir was not removed. */
int api_fixture_close(api_fixture *f);

/* Destroys and re-creates the context on the same state dir and cfg (a daemon restart). */
void api_fixture_restart(api_fixture *f);

/* One request over the "Unix socket" as uid; path may carry a ?query. The answer as it is, in
 * *resp (free with api_response_free): for bodies that are not JSON (PNG tiles). */
void api_request_raw(api_fixture *f, const char *method, const char *path, const char *body,
                     uid_t uid, api_response *resp);

/* api_request_raw, returning the parsed body (NULL if there is none) and setting *status. */
json_t *api_call(api_fixture *f, const char *method, const char *path, const char *body, uid_t uid,
                 int *status);

/* POST /v1/jobs as uid; fails the test unless it is accepted (202). Returns the job id. */
long long api_submit(api_fixture *f, const char *body, uid_t uid);

#endif
