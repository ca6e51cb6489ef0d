/* api_handle called directly (no socket): routing, errors, limits, access control, jobs. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "api.h"
#include "api_fixture.h"
#include "pattern_refs.h"

typedef api_fixture fixture;

static void configure(aalab_config *cfg)
{
    cfg->workers = 1;
    cfg->queue_size = 2;
    cfg->user_quota = 2;
    cfg->max_body = 4096;
    cfg->test_kinds = true;
}

static int setup(void **state)
{
    *state = api_fixture_open("api", configure);
    return 0;
}

static int teardown(void **state)
{
    return api_fixture_close(*state);
}

static const char *error_field(json_t *j)
{
    json_t *e = json_object_get(j, "error");
    assert_non_null(e);
    assert_non_null(json_object_get(e, "code"));
    assert_non_null(json_object_get(e, "message"));
    return json_string_value(json_object_get(e, "field"));
}

/* A request that must fail with status, naming field. */
static void expect_error(fixture *f, const char *method, const char *path, const char *body,
                         uid_t uid, int status, const char *field)
{
    int st;
    json_t *j = api_call(f, method, path, body, uid, &st);
    assert_int_equal(st, status);
    assert_string_equal(error_field(j), field);
    json_decref(j);
}

static void test_routes_and_errors(void **state)
{
    fixture *f = *state;
    int st;
    json_t *j = api_call(f, "GET", "/v1/health", NULL, 1000, &st);
    assert_int_equal(st, 200);
    assert_string_equal(json_string_value(json_object_get(j, "status")), "ok");
    json_decref(j);
    j = api_call(f, "HEAD", "/v1/presets", NULL, 1000, &st);
    assert_int_equal(st, 200);
    json_decref(j);
    j = api_call(f, "POST", "/v1/health", "{}", 1000, &st);
    assert_int_equal(st, 405);
    json_decref(j);
    j = api_call(f, "GET", "/v1/nothing", NULL, 1000, &st);
    assert_int_equal(st, 404);
    json_decref(j);
    j = api_call(f, "GET", "/index.html", NULL, 1000, &st); /* static only on TCP */
    assert_int_equal(st, 404);
    json_decref(j);
    j = api_call(f, "GET", "/v1/presets/rgss", NULL, 1000, &st);
    assert_int_equal(st, 200);
    json_decref(j);
    expect_error(f, "GET", "/v1/presets/..", NULL, 1000, 404, "name");
    j = api_call(f, "GET", "/v1/jobs/00", NULL, 1000, &st);
    assert_int_equal(st, 404);
    json_decref(j);

    j = api_call(f, "POST", "/v1/evaluate", "{\"pattern\":{\"preset\":\"rgss\"}}", 1000, &st);
    assert_int_equal(st, 200);
    assert_true(json_real_value(json_object_get(j, "e2")) > 0.43);
    json_decref(j);
    expect_error(f, "POST", "/v1/evaluate", "{\"pattern\":{\"kernels\":[[[0,0,1],[0,[],0]]]}}",
                 1000, 400, "pattern.kernels[0][1][1]");
    j = api_call(f, "POST", "/v1/evaluate",
                 "{\"pattern\":{\"preset\":\"rgss\"},\"angles\":[1e999]}", 1000, &st);
    assert_int_equal(st, 400);
    json_decref(j);
    expect_error(f, "POST", "/v1/evaluate",
                 "{\"pattern\":{\"preset\":\"rgss\"},\"angles\":[0,\"x\"]}", 1000, 400,
                 "angles[1]");
    expect_error(f, "POST", "/v1/evaluate", "{\"pattern\":{\"preset\":\"rgss\"},\"detail\":1}",
                 1000, 400, "detail");
    j = api_call(f, "POST", "/v1/evaluate", "{\"a\":1,\"a\":2}", 1000, &st);
    assert_int_equal(st, 400);
    json_decref(j);
    /* A broken escape before a 2-byte character: jansson's text echoes "\\" and the lone first
     * byte. The answer keeps where and why, with that byte as '?' (and is valid JSON text, or
     * api_call could not parse it). */
    j = api_call(f, "POST", "/v1/evaluate", "{\"aal\\\xcf\x9d\":1}", 1000, &st);
    assert_int_equal(st, 400);
    json_t *e = json_object_get(j, "error");
    assert_string_equal(json_string_value(json_object_get(e, "code")), "invalid_json");
    const char *msg = json_string_value(json_object_get(e, "message"));
    assert_non_null(msg);
    assert_non_null(strstr(msg, "invalid JSON at line 1 column "));
    assert_non_null(strstr(msg, "near '\"aal\\?'"));
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
    json_t *j = api_call(f, "POST", "/v1/evaluate", big, 1000, &st);
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
    json_t *a = api_call(f, "POST", "/v1/families/enumerate",
                         "{\"family\":\"P(4,1+,n)\",\"cost\":2}", 1000, &st);
    assert_int_equal(st, 200);
    json_t *b = api_call(f, "POST", "/v1/families/enumerate",
                         "{\"cost\":2.0,\"family\":\"P(4,1+,2)\"}", 1000, &st);
    assert_int_equal(st, 200);
    assert_int_equal(json_integer_value(json_object_get(a, "count")), 38);
    assert_true(json_equal(a, b));
    json_t *c = api_call(f, "POST", "/v1/families/enumerate",
                         "{\"family\":\"P(4,1+,n)\",\"cost\":1.75}", 1000, &st);
    assert_int_equal(json_integer_value(json_object_get(c, "count")), 19);
    json_t *h = api_call(f, "GET", "/v1/health", NULL, 1000, &st);
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
    api_fixture_restart(f);
    expect_error(f, "POST", "/v1/evaluate", body, 1000, 400, "angles");
    free(body);
}

/* An evaluate as the HTTP thread sends it (inline_work_limit set): answered at once when small;
 * otherwise no answer, the decoded call handed over (api_deferred), whose answer is byte for
 * byte the answer of the request run whole; a job reference is never decoded there. */
static void evaluate_inline(fixture *f, const char *body, size_t limit, api_response *resp)
{
    api_request req = {.method = "POST",
                       .path = "/v1/evaluate",
                       .content_type = "application/json",
                       .body = body,
                       .body_len = strlen(body),
                       .peer_known = true,
                       .peer_uid = 1000,
                       .inline_work_limit = limit};
    api_handle(f->ctx, &req, resp);
}

static void test_evaluate_inline_limit(void **state)
{
    fixture *f = *state;
    f->cfg.eval_cache = 0; /* every call computes */
    api_fixture_restart(f);
    const char *rgss = "{\"pattern\":{\"preset\":\"rgss\"}}"; /* 4 samples x 36 angles */
    api_response small, whole, big;
    evaluate_inline(f, rgss, 144, &small);
    assert_false(small.needs_pool);
    assert_null(small.deferred);
    assert_int_equal(small.status, 200);
    api_request_raw(f, "POST", "/v1/evaluate", rgss, 1000, &whole);
    assert_int_equal(whole.body_len, small.body_len);
    assert_memory_equal(whole.body, small.body, whole.body_len);

    evaluate_inline(f, rgss, 143, &big); /* one unit over the limit */
    assert_true(big.needs_pool);
    assert_non_null(big.deferred);
    assert_null(big.body);
    api_response later = {0};
    big.deferred->run(big.deferred, &later);
    big.deferred->free(big.deferred);
    assert_int_equal(later.status, 200);
    assert_int_equal(later.body_len, whole.body_len);
    assert_memory_equal(later.body, whole.body, whole.body_len);
    api_response_free(&small);
    api_response_free(&whole);
    api_response_free(&later);

    /* A bad request is answered on the HTTP thread whatever its size. */
    api_response bad;
    evaluate_inline(f, "{\"pattern\":{\"preset\":\"rgss\"},\"lp\":0}", 1, &bad);
    assert_false(bad.needs_pool);
    assert_int_equal(bad.status, 400);
    api_response_free(&bad);

    api_response ref;
    evaluate_inline(f, "{\"pattern\":{\"job\":1}}", 1 << 20, &ref);
    assert_true(ref.needs_pool);
    assert_null(ref.deferred);
    assert_null(ref.body);
}

/* One request over the "TCP listener" with an optional bearer token. */
static json_t *call_tcp(fixture *f, const char *method, const char *path, const char *body,
                        const char *token, int *status)
{
    char auth[256];
    snprintf(auth, sizeof auth, "Bearer %s", token ? token : "");
    api_request req = {.method = method,
                       .path = path,
                       .content_type = body ? "application/json" : NULL,
                       .host = "127.0.0.1:8765",
                       .authorization = token ? auth : NULL,
                       .body = body,
                       .body_len = body ? strlen(body) : 0,
                       .via_tcp = true};
    api_response resp;
    api_handle(f->ctx, &req, &resp);
    *status = resp.status;
    json_t *j = json_loadb(resp.body, resp.body_len, 0, NULL);
    api_response_free(&resp);
    return j;
}

/* POST /v1/tokens on the socket as uid; returns the secret (malloc'd) and its id. */
static char *issue_token(fixture *f, uid_t uid, long long *id)
{
    int st;
    json_t *j = api_call(f, "POST", "/v1/tokens", "{\"label\":\"test\"}", uid, &st);
    assert_int_equal(st, 201);
    assert_int_equal(json_integer_value(json_object_get(j, "uid")), uid);
    const char *t = json_string_value(json_object_get(j, "token"));
    assert_non_null(t);
    char *out = strdup(t);
    if (id)
        *id = json_integer_value(json_object_get(j, "id"));
    json_decref(j);
    return out;
}

static void test_tcp_access(void **state)
{
    fixture *f = *state;
    char *tok = issue_token(f, 1000, NULL);
    char auth[256];
    snprintf(auth, sizeof auth, "Bearer %s", tok);
    struct {
        const char *method, *path, *host, *auth;
        int status;
    } cases[] = {
        /* every API request needs the token, GET and HEAD included */
        {"GET", "/v1/health", "127.0.0.1:8765", NULL, 401},
        {"HEAD", "/v1/health", "localhost", NULL, 401},
        {"GET", "/v1/jobs", "localhost", NULL, 401},
        {"GET", "/v1/presets", "localhost", NULL, 401},
        {"GET", "/v1/patterns/1/export", "localhost", NULL, 401},
        {"GET", "/v1/tiles/0123456789abcdef0123456789abcdef.png", "localhost", NULL, 401},
        {"GET", "/v1/nothing", "localhost", NULL, 401},
        {"GET", "/v1/health", "localhost", "Bearer nope", 401},
        {"GET", "/v1/health", "localhost",
         "Bearer aalab_1_0000000000000000000000000000000000000000"
         "000000000000000000000000",
         401},
        /* the dashboard's files are the one exception */
        {"GET", "/", "localhost", NULL, 200},
        {"POST", "/", "localhost", NULL, 401},
        {"GET", "/v1/health", "127.0.0.1:8765", auth, 200},
        {"GET", "/v1/health", "[::1]:1", auth, 200},
        {"GET", "/v1/health", "evil.example", auth, 403},
        {"GET", "/v1/health", "127.0.0.1.evil", auth, 403},
        {"GET", "/v1/health", NULL, auth, 403},
        {"POST", "/v1/evaluate", "localhost", NULL, 401},
        {"POST", "/v1/evaluate", "localhost", auth, 200},
        {"POST", "/v1/evaluate", "evil.example", auth, 403},
        /* tokens come from the socket only */
        {"POST", "/v1/tokens", "localhost", auth, 403},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        bool post = !strcmp(cases[i].method, "POST");
        const char *body = "{\"pattern\":{\"preset\":\"rgss\"}}";
        api_request req = {.method = cases[i].method,
                           .path = cases[i].path,
                           .content_type = "application/json",
                           .host = cases[i].host,
                           .authorization = cases[i].auth,
                           .body = post ? body : NULL,
                           .body_len = post ? strlen(body) : 0,
                           .via_tcp = true};
        api_response resp;
        api_handle(f->ctx, &req, &resp);
        if (resp.status != cases[i].status)
            fail_msg("case %zu (%s %s): %d, expected %d", i, cases[i].method, cases[i].path,
                     resp.status, cases[i].status);
        assert_null(strstr(resp.body ? resp.body : "", "Access-Control"));
        api_response_free(&resp);
    }
    free(tok);
}

/* The status of a call whose body is not needed (st is read after the call filled it). */
static int status_of(json_t *j, const int *st)
{
    json_decref(j);
    return *st;
}

static bool list_has_id(json_t *list, const char *key, long long id)
{
    size_t i;
    json_t *o;
    json_array_foreach(json_object_get(list, key), i, o)
    {
        if (json_integer_value(json_object_get(o, "id")) == id)
            return true;
    }
    return false;
}

static void test_tokens(void **state)
{
    fixture *f = *state;
    int st;
    long long id = 0, other = 0;
    char *tok = issue_token(f, 1000, &id);
    free(issue_token(f, 1001, &other));
    json_t *j = api_call(f, "GET", "/v1/tokens", NULL, 1000, &st);
    assert_int_equal(st, 200);
    assert_true(list_has_id(j, "tokens", id));
    assert_false(list_has_id(j, "tokens", other));
    char *dump = json_dumps(j, 0);
    assert_null(strstr(dump, strrchr(tok, '_') + 1)); /* the secret is shown once */
    free(dump);
    json_t *first = json_array_get(json_object_get(j, "tokens"), 0);
    assert_null(json_object_get(first, "token"));
    assert_string_equal(json_string_value(json_object_get(first, "label")), "test");
    json_decref(j);
    j = api_call(f, "GET", "/v1/tokens", NULL, 0, &st); /* root sees all */
    assert_true(list_has_id(j, "tokens", id) && list_has_id(j, "tokens", other));
    json_decref(j);
    j = call_tcp(f, "GET", "/v1/tokens", NULL, tok, &st); /* over TCP: the token's uid */
    assert_int_equal(st, 200);
    assert_true(list_has_id(j, "tokens", id));
    assert_false(list_has_id(j, "tokens", other));
    json_decref(j);

    expect_error(f, "POST", "/v1/tokens", "{\"label\":7}", 1000, 400, "label");
    expect_error(f, "POST", "/v1/tokens", "{\"uid\":0}", 1000, 400, "uid");

    char path[64];
    snprintf(path, sizeof path, "/v1/tokens/%lld", id);
    j = api_call(f, "DELETE", path, NULL, 1001, &st); /* not the owner */
    assert_int_equal(st, 403);
    json_decref(j);
    j = call_tcp(f, "GET", "/v1/health", NULL, tok, &st);
    assert_int_equal(st, 200);
    json_decref(j);
    j = api_call(f, "DELETE", path, NULL, 1000, &st);
    assert_int_equal(st, 200);
    json_decref(j);
    j = call_tcp(f, "GET", "/v1/health", NULL, tok, &st); /* revoked at once */
    assert_int_equal(st, 401);
    json_decref(j);
    j = api_call(f, "DELETE", path, NULL, 1000, &st);
    assert_int_equal(st, 404);
    json_decref(j);
    snprintf(path, sizeof path, "/v1/tokens/%lld", other);
    j = api_call(f, "DELETE", path, NULL, 0, &st); /* root may revoke anyone's */
    assert_int_equal(st, 200);
    json_decref(j);
    free(tok);

    /* Tied to the socket group: a token counts only while its owner is a member (root always);
     * uid 4000000 has no account, so it is in no group. */
    char *ghost = issue_token(f, 4000000, NULL), *root_tok = issue_token(f, 0, NULL);
    assert_int_equal(status_of(call_tcp(f, "GET", "/v1/health", NULL, ghost, &st), &st), 200);
    assert_int_equal(api_context_tie_tokens_to_group(f->ctx, getgid()), AA_OK);
    assert_int_equal(status_of(call_tcp(f, "GET", "/v1/health", NULL, ghost, &st), &st), 401);
    assert_int_equal(status_of(call_tcp(f, "GET", "/v1/health", NULL, root_tok, &st), &st), 200);
    free(ghost);
    free(root_tok);
}

static json_t *wait_state(fixture *f, long long id, const char *want)
{
    char path[64];
    snprintf(path, sizeof path, "/v1/jobs/%lld", id);
    for (int i = 0; i < 500; i++) {
        int st;
        json_t *j = api_call(f, "GET", path, NULL, 1000, &st);
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
    json_t *j = api_call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":30}", 1000, &st);
    assert_int_equal(st, 202);
    long long a = json_integer_value(json_object_get(j, "id"));
    json_decref(j);
    json_decref(wait_state(f, a, "running"));
    j = api_call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":30}", 1000, &st);
    assert_int_equal(st, 202);
    long long b = json_integer_value(json_object_get(j, "id"));
    json_decref(j);
    /* quota 2 for uid 1000 */
    j = api_call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":30}", 1000, &st);
    assert_int_equal(st, 429);
    json_decref(j);
    /* another user: queue holds 1 of 2 */
    j = api_call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":30}", 1001, &st);
    assert_int_equal(st, 202);
    long long c = json_integer_value(json_object_get(j, "id"));
    json_decref(j);
    /* queue full (2 queued) */
    j = api_call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":30}", 1002, &st);
    assert_int_equal(st, 429);
    json_decref(j);

    char path[64];
    snprintf(path, sizeof path, "/v1/jobs/%lld", a);
    j = api_call(f, "DELETE", path, NULL, 1001, &st); /* not the owner */
    assert_int_equal(st, 403);
    json_decref(j);
    j = api_call(f, "DELETE", path, NULL, 0, &st); /* root may */
    assert_int_equal(st, 202);
    json_decref(j);
    json_decref(wait_state(f, a, "cancelled"));
    j = api_call(f, "DELETE", path, NULL, 0, &st);
    assert_int_equal(st, 409);
    json_decref(j);
    snprintf(path, sizeof path, "/v1/jobs/%lld", b);
    j = api_call(f, "DELETE", path, NULL, 1000, &st);
    assert_int_equal(st, 202);
    json_decref(j);
    snprintf(path, sizeof path, "/v1/jobs/%lld", c);
    j = api_call(f, "DELETE", path, NULL, 1001, &st);
    assert_int_equal(st, 202);
    json_decref(j);
    json_decref(wait_state(f, c, "cancelled"));

    j = api_call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":0,\"bogus\":1}", 1000,
                 &st);
    assert_int_equal(st, 400);
    assert_string_equal(error_field(j), "bogus");
    json_decref(j);
}

static void test_private_jobs(void **state)
{
    fixture *f = *state;
    int st;
    long long priv = api_submit(f,
                                "{\"kind\":\"sleep\",\"seconds\":0,\"visibility\":\"private\","
                                "\"pattern\":{\"preset\":\"quincunx\"}}",
                                1000);
    long long team = api_submit(f, "{\"kind\":\"sleep\",\"seconds\":0}", 1000);
    json_t *j = wait_state(f, priv, "done");
    assert_string_equal(json_string_value(json_object_get(j, "visibility")), "private");
    json_decref(j);
    json_decref(wait_state(f, team, "done"));
    char *tok_root = issue_token(f, 0, NULL), *tok_alice = issue_token(f, 1000, NULL);
    char *tok_bob = issue_token(f, 1001, NULL);

    char job[64], export[80];
    snprintf(job, sizeof job, "/v1/jobs/%lld", priv);
    snprintf(export, sizeof export, "/v1/patterns/%lld/export", priv);
    assert_int_equal(status_of(api_call(f, "GET", job, NULL, 1001, &st), &st), 404);
    assert_int_equal(status_of(call_tcp(f, "GET", job, NULL, tok_bob, &st), &st), 404);
    assert_int_equal(status_of(api_call(f, "GET", job, NULL, 1000, &st), &st), 200);
    assert_int_equal(status_of(call_tcp(f, "GET", job, NULL, tok_alice, &st), &st), 200);
    assert_int_equal(status_of(api_call(f, "GET", job, NULL, 0, &st), &st), 200); /* root, socket */
    /* a token issued to root acts for uid 0 without root's powers */
    assert_int_equal(status_of(call_tcp(f, "GET", job, NULL, tok_root, &st), &st), 404);
    assert_int_equal(status_of(api_call(f, "GET", export, NULL, 1001, &st), &st), 404);
    assert_int_equal(status_of(call_tcp(f, "GET", export, NULL, tok_root, &st), &st), 404);
    assert_int_equal(status_of(api_call(f, "GET", export, NULL, 1000, &st), &st), 200);
    assert_int_equal(status_of(api_call(f, "GET", export, NULL, 0, &st), &st), 200);

    /* the list: filtered for bob, complete for alice */
    j = api_call(f, "GET", "/v1/jobs", NULL, 1001, &st);
    assert_int_equal(st, 200);
    assert_false(list_has_id(j, "jobs", priv));
    assert_true(list_has_id(j, "jobs", team));
    json_decref(j);
    j = call_tcp(f, "GET", "/v1/jobs", NULL, tok_alice, &st);
    assert_true(list_has_id(j, "jobs", priv) && list_has_id(j, "jobs", team));
    json_decref(j);

    /* {"job": ID} references: someone else's private job reads as no job */
    char body[128];
    snprintf(body, sizeof body, "{\"pattern\":{\"job\":%lld}}", priv);
    expect_error(f, "POST", "/v1/evaluate", body, 1001, 400, "pattern.job");
    assert_int_equal(status_of(api_call(f, "POST", "/v1/evaluate", body, 1000, &st), &st), 200);
    snprintf(body, sizeof body, "{\"kind\":\"sleep\",\"seconds\":0,\"pattern\":{\"job\":%lld}}",
             priv);
    expect_error(f, "POST", "/v1/jobs", body, 1001, 400, "pattern.job");
    api_caller bob = {.uid = 1001}, root_tcp = {.uid = 0, .via_tcp = true}, root = {.admin = true};
    snprintf(body, sizeof body, "{\"patterns\":[{\"job\":%lld}]}", priv);
    json_t *doc = json_loads(body, 0, NULL);
    aa_error err = {0};
    assert_int_not_equal(api_resolve_pattern_refs(f->ctx, &bob, doc, &err), AA_OK);
    assert_string_equal(err.field, "patterns[0].job");
    assert_int_not_equal(api_resolve_pattern_refs(f->ctx, &root_tcp, doc, &err), AA_OK);
    assert_int_equal(api_resolve_pattern_refs(f->ctx, &root, doc, &err), AA_OK);
    json_decref(doc);

    expect_error(f, "POST", "/v1/jobs",
                 "{\"kind\":\"sleep\",\"seconds\":0,\"visibility\":\"secret\"}", 1000, 400,
                 "visibility");
    free(tok_root);
    free(tok_alice);
    free(tok_bob);
}

static void test_cancel_rights(void **state)
{
    fixture *f = *state;
    int st;
    long long team = api_submit(f, "{\"kind\":\"sleep\",\"seconds\":30}", 1000);
    long long priv =
        api_submit(f, "{\"kind\":\"sleep\",\"seconds\":30,\"visibility\":\"private\"}", 1000);
    char *tok_root = issue_token(f, 0, NULL), *tok_bob = issue_token(f, 1001, NULL);
    char a[64], b[64];
    snprintf(a, sizeof a, "/v1/jobs/%lld", team);
    snprintf(b, sizeof b, "/v1/jobs/%lld", priv);
    assert_int_equal(status_of(api_call(f, "DELETE", a, NULL, 1001, &st), &st), 403);
    assert_int_equal(status_of(call_tcp(f, "DELETE", a, NULL, tok_bob, &st), &st), 403);
    assert_int_equal(status_of(call_tcp(f, "DELETE", a, NULL, tok_root, &st), &st), 403);
    assert_int_equal(status_of(api_call(f, "DELETE", b, NULL, 1001, &st), &st), 404);
    assert_int_equal(status_of(call_tcp(f, "DELETE", b, NULL, tok_root, &st), &st), 404);
    assert_int_equal(status_of(api_call(f, "DELETE", b, NULL, 0, &st), &st), 202);
    assert_int_equal(status_of(api_call(f, "DELETE", a, NULL, 1000, &st), &st), 202);
    json_decref(wait_state(f, team, "cancelled"));
    free(tok_root);
    free(tok_bob);
}

/* A queued private job across a restart: the kind re-parses its spec (visibility is no kind
 * field) and the job stays private. */
static void test_private_job_restart(void **state)
{
    fixture *f = *state;
    int st;
    long long run = api_submit(f, "{\"kind\":\"sleep\",\"seconds\":30}", 1000);
    json_decref(wait_state(f, run, "running"));
    long long priv =
        api_submit(f, "{\"kind\":\"sleep\",\"seconds\":0,\"visibility\":\"private\"}", 1000);
    api_fixture_restart(f);
    char path[64];
    snprintf(path, sizeof path, "/v1/jobs/%lld", run); /* re-queued first: out of the way */
    assert_int_equal(status_of(api_call(f, "DELETE", path, NULL, 1000, &st), &st), 202);
    json_t *j = wait_state(f, priv, "done"); /* not "interrupted": the spec still parses */
    assert_string_equal(json_string_value(json_object_get(j, "visibility")), "private");
    json_decref(j);
    snprintf(path, sizeof path, "/v1/jobs/%lld", priv);
    assert_int_equal(status_of(api_call(f, "GET", path, NULL, 1001, &st), &st), 404);
}

static void test_private_tiles(void **state)
{
    fixture *f = *state;
    int st;
    json_t *j =
        api_call(f, "POST", "/v1/render",
                 "{\"pattern\":{\"preset\":\"rgss\"},\"size\":[16,16],\"visibility\":\"private\"}",
                 1000, &st);
    assert_int_equal(st, 200);
    char url[128];
    snprintf(url, sizeof url, "%s",
             json_string_value(
                 json_object_get(json_object_get(json_object_get(j, "tiles"), "pattern"), "url")));
    json_decref(j);
    char *tok_alice = issue_token(f, 1000, NULL), *tok_bob = issue_token(f, 1001, NULL);
    assert_int_equal(status_of(api_call(f, "GET", url, NULL, 1001, &st), &st), 404);
    assert_int_equal(status_of(call_tcp(f, "GET", url, NULL, tok_bob, &st), &st), 404);
    assert_int_equal(status_of(api_call(f, "GET", url, NULL, 1000, &st), &st), 200);
    assert_int_equal(status_of(call_tcp(f, "GET", url, NULL, tok_alice, &st), &st), 200);
    assert_int_equal(status_of(api_call(f, "GET", url, NULL, 0, &st), &st), 200);
    /* the same tile rendered for the team is the team's */
    j = api_call(f, "POST", "/v1/render", "{\"pattern\":{\"preset\":\"rgss\"},\"size\":[16,16]}",
                 1001, &st);
    assert_int_equal(st, 200);
    json_decref(j);
    assert_int_equal(status_of(call_tcp(f, "GET", url, NULL, tok_bob, &st), &st), 200);
    expect_error(f, "POST", "/v1/render",
                 "{\"pattern\":{\"preset\":\"rgss\"},\"size\":[16,16],\"visibility\":\"all\"}",
                 1001, 400, "visibility");
    free(tok_alice);
    free(tok_bob);
}

static void test_pattern_refs(void **state)
{
    fixture *f = *state;
    int st;
    json_t *j = api_call(f, "POST", "/v1/jobs",
                         "{\"kind\":\"sleep\",\"seconds\":0,\"pattern\":{\"preset\":\"quincunx\"}}",
                         1000, &st);
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
    api_caller alice = {.uid = 1000};
    assert_int_equal(api_resolve_pattern_refs(f->ctx, &alice, doc, &err), AA_OK);
    json_t *p1 = json_object_get(json_object_get(doc, "x"), "pattern");
    json_t *p2 = json_array_get(json_object_get(doc, "patterns"), 1);
    assert_non_null(json_object_get(p1, "kernels"));
    assert_true(json_equal(p1, p2));
    json_decref(doc);
    doc = json_loads("{\"patterns\":[{\"preset\":\"rgss\"},{\"job\":424242}]}", 0, NULL);
    assert_int_not_equal(api_resolve_pattern_refs(f->ctx, &alice, doc, &err), AA_OK);
    assert_string_equal(err.field, "patterns[1].job");
    json_decref(doc);

    char path[80];
    snprintf(path, sizeof path, "/v1/patterns/%lld/export?format=d3d12", id);
    j = api_call(f, "GET", path, NULL, 1000, &st);
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
        cmocka_unit_test_setup_teardown(test_evaluate_inline_limit, setup, teardown),
        cmocka_unit_test_setup_teardown(test_enumerate_cached, setup, teardown),
        cmocka_unit_test_setup_teardown(test_jobs_owner_quota_queue, setup, teardown),
        cmocka_unit_test_setup_teardown(test_pattern_refs, setup, teardown),
        cmocka_unit_test_setup_teardown(test_tokens, setup, teardown),
        cmocka_unit_test_setup_teardown(test_private_jobs, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cancel_rights, setup, teardown),
        cmocka_unit_test_setup_teardown(test_private_job_restart, setup, teardown),
        cmocka_unit_test_setup_teardown(test_private_tiles, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
