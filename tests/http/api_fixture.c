#define _GNU_SOURCE
#include "api_fixture.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

api_fixture *api_fixture_open(const char *name, void (*configure)(aalab_config *cfg))
{
    api_fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    snprintf(f->dir, sizeof f->dir, "/tmp/aalab-test-%s-XXXXXX", name);
    assert_non_null(mkdtemp(f->dir));
    config_defaults(&f->cfg);
    snprintf(f->cfg.state_dir, sizeof f->cfg.state_dir, "%s/state", f->dir);
    if (configure)
        configure(&f->cfg);
    aa_error err = {0};
    f->ctx = api_context_create(&f->cfg, &err);
    if (!f->ctx)
        fail_msg("context: %s", err.message);
    return f;
}

int api_fixture_close(api_fixture *f)
{
    api_context_destroy(f->ctx);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", f->dir);
    if (system(cmd) != 0)
        return -1;
    free(f);
    return 0;
}

void api_fixture_restart(api_fixture *f)
{
    api_context_destroy(f->ctx);
    aa_error err = {0};
    f->ctx = api_context_create(&f->cfg, &err);
    if (!f->ctx)
        fail_msg("context: %s", err.message);
}

void api_request_raw(api_fixture *f, const char *method, const char *path, const char *body,
                     uid_t uid, api_response *resp)
{
    api_request req = {.method = method,
                       .path = path,
                       .content_type = body ? "application/json" : NULL,
                       .body = body,
                       .body_len = body ? strlen(body) : 0,
                       .peer_known = true,
                       .peer_uid = uid};
    char p[256], q[64];
    const char *qm = strchr(path, '?');
    if (qm) {
        snprintf(p, sizeof p, "%.*s", (int)(qm - path), path);
        snprintf(q, sizeof q, "%s", qm + 1);
        req.path = p;
        req.query = q;
    }
    memset(resp, 0, sizeof *resp);
    api_handle(f->ctx, &req, resp);
}

json_t *api_call(api_fixture *f, const char *method, const char *path, const char *body, uid_t uid,
                 int *status)
{
    api_response resp;
    api_request_raw(f, method, path, body, uid, &resp);
    *status = resp.status;
    json_t *j = json_loadb(resp.body, resp.body_len, 0, NULL);
    api_response_free(&resp);
    return j;
}

long long api_submit(api_fixture *f, const char *body, uid_t uid)
{
    int st;
    json_t *j = api_call(f, "POST", "/v1/jobs", body, uid, &st);
    if (st != 202) {
        char *dump = j ? json_dumps(j, 0) : NULL;
        fail_msg("submit %s: %d %s", body, st, dump ? dump : "");
    }
    long long id = json_integer_value(json_object_get(j, "id"));
    json_decref(j);
    return id;
}
