/* api_handle called directly (no socket): routing, errors, limits, access control, jobs. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "api.h"
#include "api_context.h"
#include "config.h"

typedef struct fixture {
    char dir[64];
    aalab_config cfg;
    api_context *ctx;
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    snprintf(f->dir, sizeof f->dir, "/tmp/aalab-test-api-XXXXXX");
    assert_non_null(mkdtemp(f->dir));
    config_defaults(&f->cfg);
    snprintf(f->cfg.state_dir, sizeof f->cfg.state_dir, "%s/state", f->dir);
    f->cfg.workers = 1;
    f->cfg.queue_size = 2;
    f->cfg.user_quota = 2;
    f->cfg.max_body = 4096;
    f->cfg.test_kinds = true;
    aa_error err = {0};
    bool created = false;
    f->ctx = api_context_create(&f->cfg, &created, &err);
    if (!f->ctx)
        fail_msg("context: %s", err.message);
    assert_true(created);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    api_context_destroy(f->ctx);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", f->dir);
    if (system(cmd) != 0)
        return -1;
    free(f);
    return 0;
}

/* One request over the "Unix socket" as uid. */
static json_t *call(fixture *f, const char *method, const char *path, const char *body, uid_t uid,
                    int *status)
{
    api_request req = {.method = method,
                       .path = path,
                       .content_type = body ? "application/json" : NULL,
                       .body = body,
                       .body_len = body ? strlen(body) : 0,
                       .peer_known = true,
                       .peer_uid = uid};
    char q[64];
    const char *qm = strchr(path, '?');
    char p[256];
    if (qm) {
        snprintf(p, sizeof p, "%.*s", (int)(qm - path), path);
        snprintf(q, sizeof q, "%s", qm + 1);
        req.path = p;
        req.query = q;
    }
    api_response resp;
    api_handle(f->ctx, &req, &resp);
    *status = resp.status;
    json_t *j = json_loadb(resp.body, resp.body_len, 0, NULL);
    api_response_free(&resp);
    return j;
}

static const char *error_field(json_t *j)
{
    json_t *e = json_object_get(j, "error");
    assert_non_null(e);
    assert_non_null(json_object_get(e, "code"));
    assert_non_null(json_object_get(e, "message"));
    return json_string_value(json_object_get(e, "field"));
}

static void test_routes_and_errors(void **state)
{
    fixture *f = *state;
    int st;
    json_t *j = call(f, "GET", "/v1/health", NULL, 1000, &st);
    assert_int_equal(st, 200);
    assert_string_equal(json_string_value(json_object_get(j, "status")), "ok");
    json_decref(j);
    j = call(f, "HEAD", "/v1/presets", NULL, 1000, &st);
    assert_int_equal(st, 200);
    json_decref(j);
    j = call(f, "POST", "/v1/health", "{}", 1000, &st);
    assert_int_equal(st, 405);
    json_decref(j);
    j = call(f, "GET", "/v1/nothing", NULL, 1000, &st);
    assert_int_equal(st, 404);
    json_decref(j);
    j = call(f, "GET", "/index.html", NULL, 1000, &st); /* static only on TCP */
    assert_int_equal(st, 404);
    json_decref(j);
    j = call(f, "GET", "/v1/presets/rgss", NULL, 1000, &st);
    assert_int_equal(st, 200);
    json_decref(j);
    j = call(f, "GET", "/v1/presets/..", NULL, 1000, &st);
    assert_int_equal(st, 404);
    assert_string_equal(error_field(j), "name");
    json_decref(j);
    j = call(f, "GET", "/v1/jobs/00", NULL, 1000, &st);
    assert_int_equal(st, 404);
    json_decref(j);

    j = call(f, "POST", "/v1/evaluate", "{\"pattern\":{\"preset\":\"rgss\"}}", 1000, &st);
    assert_int_equal(st, 200);
    assert_true(json_real_value(json_object_get(j, "e2")) > 0.43);
    json_decref(j);
    j = call(f, "POST", "/v1/evaluate", "{\"pattern\":{\"kernels\":[[[0,0,1],[0,[],0]]]}}", 1000,
             &st);
    assert_int_equal(st, 400);
    assert_string_equal(error_field(j), "pattern.kernels[0][1][1]");
    json_decref(j);
    j = call(f, "POST", "/v1/evaluate", "{\"pattern\":{\"preset\":\"rgss\"},\"angles\":[1e999]}",
             1000, &st);
    assert_int_equal(st, 400);
    json_decref(j);
    j = call(f, "POST", "/v1/evaluate", "{\"pattern\":{\"preset\":\"rgss\"},\"angles\":[0,\"x\"]}",
             1000, &st);
    assert_int_equal(st, 400);
    assert_string_equal(error_field(j), "angles[1]");
    json_decref(j);
    j = call(f, "POST", "/v1/evaluate", "{\"pattern\":{\"preset\":\"rgss\"},\"detail\":1}", 1000,
             &st);
    assert_int_equal(st, 400);
    assert_string_equal(error_field(j), "detail");
    json_decref(j);
    j = call(f, "POST", "/v1/evaluate", "{\"a\":1,\"a\":2}", 1000, &st);
    assert_int_equal(st, 400);
    json_decref(j);
}

static void test_limits(void **state)
{
    fixture *f = *state;
    char *big = malloc(8192);
    memset(big, ' ', 8191);
    big[8191] = 0;
    big[0] = '{';
    big[8190] = '}';
    int st;
    json_t *j = call(f, "POST", "/v1/evaluate", big, 1000, &st);
    assert_int_equal(st, 413);
    json_decref(j);
    free(big);
    api_request req = {.method = "POST",
                       .path = "/v1/evaluate",
                       .content_type = "text/plain",
                       .body = "{}",
                       .body_len = 2};
    api_response resp;
    api_handle(f->ctx, &req, &resp);
    assert_int_equal(resp.status, 415);
    api_response_free(&resp);
}

/* A synchronous evaluate is bounded in kernel samples x angles. */
/* Enumerations are cached by cost: the second answer is the same bytes, served from the cache. */
static void test_enumerate_cached(void **state)
{
    fixture *f = *state;
    int st;
    json_t *a = call(f, "POST", "/v1/families/enumerate", "{\"family\":\"P(4,1+,n)\",\"cost\":2}",
                     1000, &st);
    assert_int_equal(st, 200);
    json_t *b = call(f, "POST", "/v1/families/enumerate", "{\"cost\":2.0,\"family\":\"P(4,1+,2)\"}",
                     1000, &st);
    assert_int_equal(st, 200);
    assert_int_equal(json_integer_value(json_object_get(a, "count")), 38);
    assert_true(json_equal(a, b));
    json_t *c = call(f, "POST", "/v1/families/enumerate",
                     "{\"family\":\"P(4,1+,n)\",\"cost\":1.75}", 1000, &st);
    assert_int_equal(json_integer_value(json_object_get(c, "count")), 19);
    json_t *h = call(f, "GET", "/v1/health", NULL, 1000, &st);
    json_t *cache = json_object_get(h, "eval_cache");
    assert_int_equal(json_integer_value(json_object_get(cache, "hits")), 1);
    assert_int_equal(json_integer_value(json_object_get(cache, "entries")), 2);
    json_decref(a);
    json_decref(b);
    json_decref(c);
    json_decref(h);
}

static void test_evaluate_work_limit(void **state)
{
    fixture *f = *state;
    size_t cap = 1 << 20, n = 0;
    char *body = malloc(cap);
    n += (size_t)snprintf(body + n, cap - n, "{\"pattern\":{\"normalize\":true,\"kernels\":[[");
    for (int i = 0; i < 4096; i++)
        n += (size_t)snprintf(body + n, cap - n, "%s[%g,%g,1]", i ? "," : "", (i % 64) / 64.0 - 0.5,
                              (i / 64) / 64.0 - 0.5);
    n += (size_t)snprintf(body + n, cap - n, "]]},\"angles\":[");
    for (int i = 0; i < 4096; i++)
        n += (size_t)snprintf(body + n, cap - n, "%s%g", i ? "," : "", i * 180.0 / 4096);
    snprintf(body + n, cap - n, "]}");
    f->cfg.max_body = cap;
    int st;
    api_context_destroy(f->ctx);
    aa_error err = {0};
    f->ctx = api_context_create(&f->cfg, NULL, &err);
    assert_non_null(f->ctx);
    json_t *j = call(f, "POST", "/v1/evaluate", body, 1000, &st);
    assert_int_equal(st, 400);
    assert_string_equal(error_field(j), "angles");
    json_decref(j);
    free(body);
}

static void test_tcp_access(void **state)
{
    fixture *f = *state;
    char auth[128];
    snprintf(auth, sizeof auth, "Bearer %s", api_context_token(f->ctx));
    struct {
        const char *method, *host, *auth;
        int status;
    } cases[] = {
        {"GET", "127.0.0.1:8765", NULL, 200}, {"GET", "localhost", NULL, 200},
        {"GET", "[::1]:1", NULL, 200},        {"GET", "evil.example", NULL, 403},
        {"GET", "127.0.0.1.evil", NULL, 403}, {"GET", NULL, NULL, 403},
        {"POST", "localhost", NULL, 401},     {"POST", "localhost", "Bearer nope", 401},
        {"POST", "localhost", auth, 200},     {"POST", "evil.example", auth, 403},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        bool post = !strcmp(cases[i].method, "POST");
        const char *body = "{\"pattern\":{\"preset\":\"rgss\"}}";
        api_request req = {.method = cases[i].method,
                           .path = post ? "/v1/evaluate" : "/v1/health",
                           .content_type = "application/json",
                           .host = cases[i].host,
                           .authorization = cases[i].auth,
                           .body = post ? body : NULL,
                           .body_len = post ? strlen(body) : 0,
                           .via_tcp = true};
        api_response resp;
        api_handle(f->ctx, &req, &resp);
        if (resp.status != cases[i].status)
            fail_msg("case %zu: %d, expected %d", i, resp.status, cases[i].status);
        assert_null(strstr(resp.body ? resp.body : "", "Access-Control"));
        api_response_free(&resp);
    }
}

static json_t *wait_state(fixture *f, long long id, const char *want)
{
    char path[64];
    snprintf(path, sizeof path, "/v1/jobs/%lld", id);
    for (int i = 0; i < 500; i++) {
        int st;
        json_t *j = call(f, "GET", path, NULL, 1000, &st);
        assert_int_equal(st, 200);
        if (!strcmp(json_string_value(json_object_get(j, "state")), want))
            return j;
        json_decref(j);
        struct timespec d = {0, 10 * 1000 * 1000};
        nanosleep(&d, NULL);
    }
    fail_msg("job %lld never reached %s", id, want);
    return NULL;
}

static void test_jobs_owner_quota_queue(void **state)
{
    fixture *f = *state;
    int st;
    json_t *j = call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":30}", 1000, &st);
    assert_int_equal(st, 202);
    long long a = json_integer_value(json_object_get(j, "id"));
    json_decref(j);
    json_decref(wait_state(f, a, "running"));
    j = call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":30}", 1000, &st);
    assert_int_equal(st, 202);
    long long b = json_integer_value(json_object_get(j, "id"));
    json_decref(j);
    /* quota 2 for uid 1000 */
    j = call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":30}", 1000, &st);
    assert_int_equal(st, 429);
    json_decref(j);
    /* another user: queue holds 1 of 2 */
    j = call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":30}", 1001, &st);
    assert_int_equal(st, 202);
    long long c = json_integer_value(json_object_get(j, "id"));
    json_decref(j);
    /* queue full (2 queued) */
    j = call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":30}", 1002, &st);
    assert_int_equal(st, 429);
    json_decref(j);

    char path[64];
    snprintf(path, sizeof path, "/v1/jobs/%lld", a);
    j = call(f, "DELETE", path, NULL, 1001, &st); /* not the owner */
    assert_int_equal(st, 403);
    json_decref(j);
    j = call(f, "DELETE", path, NULL, 0, &st); /* root may */
    assert_int_equal(st, 202);
    json_decref(j);
    json_decref(wait_state(f, a, "cancelled"));
    j = call(f, "DELETE", path, NULL, 0, &st);
    assert_int_equal(st, 409);
    json_decref(j);
    snprintf(path, sizeof path, "/v1/jobs/%lld", b);
    j = call(f, "DELETE", path, NULL, 1000, &st);
    assert_int_equal(st, 202);
    json_decref(j);
    snprintf(path, sizeof path, "/v1/jobs/%lld", c);
    j = call(f, "DELETE", path, NULL, 1001, &st);
    assert_int_equal(st, 202);
    json_decref(j);
    json_decref(wait_state(f, c, "cancelled"));

    j = call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":0,\"bogus\":1}", 1000, &st);
    assert_int_equal(st, 400);
    assert_string_equal(error_field(j), "bogus");
    json_decref(j);
}

static void test_pattern_refs(void **state)
{
    fixture *f = *state;
    int st;
    json_t *j =
        call(f, "POST", "/v1/jobs",
             "{\"kind\":\"sleep\",\"seconds\":0,\"pattern\":{\"preset\":\"quincunx\"}}", 1000, &st);
    assert_int_equal(st, 202);
    long long id = json_integer_value(json_object_get(j, "id"));
    json_decref(j);
    json_decref(wait_state(f, id, "done"));
    char body[160];
    snprintf(body, sizeof body,
             "{\"x\":{\"pattern\":{\"job\":%lld}},\"patterns\":[{\"preset\":\"rgss\"},{\"job\":\"%"
             "lld\"}]}",
             id, id);
    json_t *doc = json_loads(body, 0, NULL);
    aa_error err = {0};
    assert_int_equal(api_resolve_pattern_refs(f->ctx, doc, &err), AA_OK);
    json_t *p1 = json_object_get(json_object_get(doc, "x"), "pattern");
    json_t *p2 = json_array_get(json_object_get(doc, "patterns"), 1);
    assert_non_null(json_object_get(p1, "kernels"));
    assert_true(json_equal(p1, p2));
    json_decref(doc);
    doc = json_loads("{\"patterns\":[{\"preset\":\"rgss\"},{\"job\":424242}]}", 0, NULL);
    assert_int_not_equal(api_resolve_pattern_refs(f->ctx, doc, &err), AA_OK);
    assert_string_equal(err.field, "patterns[1].job");
    json_decref(doc);

    char path[80];
    snprintf(path, sizeof path, "/v1/patterns/%lld/export?format=d3d12", id);
    j = call(f, "GET", path, NULL, 1000, &st);
    assert_int_equal(st, 200);
    json_decref(j);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_routes_and_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_limits, setup, teardown),
        cmocka_unit_test_setup_teardown(test_tcp_access, setup, teardown),
        cmocka_unit_test_setup_teardown(test_evaluate_work_limit, setup, teardown),
        cmocka_unit_test_setup_teardown(test_enumerate_cached, setup, teardown),
        cmocka_unit_test_setup_teardown(test_jobs_owner_quota_queue, setup, teardown),
        cmocka_unit_test_setup_teardown(test_pattern_refs, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
