/* api_handle called directly for the job store's endpoints: the spec size limit, envelope
 * keys, the store quota, PATCH pinned, purge and its permissions, GET /v1/usage, and the list
 * filtered by viewer and kind. */
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

#include "api_fixture.h"

typedef api_fixture fixture;

static void configure(aalab_config *cfg)
{
    cfg->workers = 1;
    cfg->test_kinds = true;
    cfg->max_spec_bytes = 2048;
    /* Room for two unfinished jobs' reserves (each 2 x spec + 256 KiB), not three. */
    cfg->user_store_bytes = 600 * 1024;
}

static int setup(void **state)
{
    *state = api_fixture_open("api-store", configure);
    return 0;
}

static int teardown(void **state)
{
    return api_fixture_close(*state);
}

static const char *error_code(json_t *j)
{
    json_t *e = json_object_get(j, "error");
    assert_non_null(e);
    assert_non_null(json_object_get(e, "field"));
    return json_string_value(json_object_get(e, "code"));
}

static const char *state_of(fixture *f, long long id, char *buf, size_t cap)
{
    char path[64];
    snprintf(path, sizeof path, "/v1/jobs/%lld", id);
    int st;
    json_t *j = api_call(f, "GET", path, NULL, 0, &st);
    snprintf(buf, cap, "%s", st == 200 ? json_string_value(json_object_get(j, "state")) : "gone");
    json_decref(j);
    return buf;
}

static void wait_final(fixture *f, long long id)
{
    char buf[32];
    for (int i = 0; i < 500; i++) {
        state_of(f, id, buf, sizeof buf);
        if (strcmp(buf, "queued") && strcmp(buf, "running"))
            return;
        usleep(10000);
    }
    fail_msg("job %lld did not end", id);
}

static void test_spec_limit_and_envelope(void **state)
{
    fixture *f = *state;
    int st;
    char big[3000];
    memset(big, ' ', sizeof big - 1);
    big[sizeof big - 1] = 0;
    memcpy(big, "{\"kind\":\"sleep\",\"seconds\":0}", 28);
    json_t *j = api_call(f, "POST", "/v1/jobs", big, 1000, &st);
    assert_int_equal(st, 413);
    assert_string_equal(error_code(j), "payload_too_large");
    json_decref(j);
    j = api_call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":0,\"visibility\":\"all\"}",
                 1000, &st);
    assert_int_equal(st, 400);
    assert_string_equal(json_string_value(json_object_get(json_object_get(j, "error"), "field")),
                        "visibility");
    json_decref(j);
    j = api_call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":0,\"pinned\":1}", 1000,
                 &st);
    assert_int_equal(st, 400);
    json_decref(j);
    j = api_call(f, "POST", "/v1/jobs", "{\"kind\":\"sleep\",\"seconds\":0,\"priority\":-11}", 1000,
                 &st);
    assert_int_equal(st, 400);
    json_decref(j);
    /* Accepted: the envelope is stored in its columns, not in the kind's spec. */
    long long id =
        api_submit(f,
                   "{\"kind\":\"sleep\",\"seconds\":0,\"visibility\":\"private\",\"pinned\":true,"
                   "\"priority\":3}",
                   1000);
    char path[64];
    snprintf(path, sizeof path, "/v1/jobs/%lld", id);
    j = api_call(f, "GET", path, NULL, 1000, &st);
    assert_int_equal(st, 200);
    assert_string_equal(json_string_value(json_object_get(j, "visibility")), "private");
    assert_true(json_is_true(json_object_get(j, "pinned")));
    assert_null(json_object_get(json_object_get(j, "spec"), "pinned"));
    json_decref(j);
    /* The list: the private job is hidden from others, shown to its owner and root. */
    for (uid_t uid = 0; uid < 3; uid++) {
        uid_t who = uid == 0 ? 0 : uid == 1 ? 1000 : 1001;
        j = api_call(f, "GET", "/v1/jobs?kind=sleep", NULL, who, &st);
        assert_int_equal(st, 200);
        assert_int_equal(json_array_size(json_object_get(j, "jobs")), who == 1001 ? 0 : 1);
        json_decref(j);
    }
    j = api_call(f, "GET", "/v1/jobs?kind=optimize", NULL, 0, &st);
    assert_int_equal(json_array_size(json_object_get(j, "jobs")), 0);
    json_decref(j);
    j = api_call(f, "GET", "/v1/jobs?kind=nonsense", NULL, 0, &st);
    assert_int_equal(st, 400);
    json_decref(j);
}

static void test_quota_pin_purge_usage(void **state)
{
    fixture *f = *state;
    int st;
    const char *running = "{\"kind\":\"sleep\",\"seconds\":30}";
    long long a = api_submit(f, running, 1000);
    long long b = api_submit(f, running, 1000);
    /* A third unfinished job would not fit: refused, naming the limit. */
    json_t *j = api_call(f, "POST", "/v1/jobs", running, 1000, &st);
    assert_int_equal(st, 403);
    assert_string_equal(error_code(j), "quota_exceeded");
    assert_non_null(strstr(
        json_string_value(json_object_get(json_object_get(j, "error"), "message")), "614400"));
    json_decref(j);
    long long other = api_submit(f, "{\"kind\":\"sleep\",\"seconds\":0}", 1001);

    j = api_call(f, "GET", "/v1/usage", NULL, 1000, &st);
    assert_int_equal(st, 200);
    assert_int_equal(json_integer_value(json_object_get(j, "store_limit")), 600 * 1024);
    long long used = json_integer_value(json_object_get(j, "store_bytes"));
    assert_true(used > 512 * 1024 && used <= 600 * 1024);
    assert_int_equal(json_integer_value(json_object_get(j, "jobs")), 2);
    assert_null(json_object_get(j, "users"));
    json_decref(j);
    j = api_call(f, "GET", "/v1/usage", NULL, 0, &st);
    assert_int_equal(json_array_size(json_object_get(j, "users")), 2);
    json_decref(j);

    /* Purge: not someone else's, not a running job, yes a queued one (cancelled first). */
    char pa[64], pb[64], po[64];
    snprintf(pa, sizeof pa, "/v1/jobs/%lld?purge=1", a);
    snprintf(pb, sizeof pb, "/v1/jobs/%lld?purge=1", b);
    snprintf(po, sizeof po, "/v1/jobs/%lld?purge=1", other);
    j = api_call(f, "DELETE", pa, NULL, 1001, &st);
    assert_int_equal(st, 403);
    json_decref(j);
    char buf[32];
    for (int i = 0; i < 500 && strcmp(state_of(f, a, buf, sizeof buf), "running"); i++)
        usleep(10000);
    j = api_call(f, "DELETE", pa, NULL, 1000, &st);
    assert_int_equal(st, 409);
    json_decref(j);
    assert_string_equal(state_of(f, b, buf, sizeof buf), "queued"); /* one worker */
    j = api_call(f, "DELETE", pb, NULL, 1000, &st);
    assert_int_equal(st, 200);
    assert_true(json_is_true(json_object_get(j, "purged")));
    json_decref(j);
    assert_string_equal(state_of(f, b, buf, sizeof buf), "gone");
    j = api_call(f, "DELETE", pb, NULL, 1000, &st);
    assert_int_equal(st, 404);
    json_decref(j);
    j = api_call(f, "DELETE", "/v1/jobs/1?purge=yes", NULL, 1000, &st);
    assert_int_equal(st, 400);
    json_decref(j);

    /* Plain DELETE still cancels; then the owner may purge. */
    snprintf(pa, sizeof pa, "/v1/jobs/%lld", a);
    j = api_call(f, "DELETE", pa, NULL, 1000, &st);
    assert_int_equal(st, 202);
    json_decref(j);
    wait_final(f, a);
    assert_string_equal(state_of(f, a, buf, sizeof buf), "cancelled");

    /* PATCH pinned: owner yes, others no, bad bodies 400. */
    j = api_call(f, "PATCH", pa, "{\"pinned\":true}", 1001, &st);
    assert_int_equal(st, 403);
    json_decref(j);
    j = api_call(f, "PATCH", pa, "{\"pinned\":\"yes\"}", 1000, &st);
    assert_int_equal(st, 400);
    json_decref(j);
    j = api_call(f, "PATCH", pa, "{\"pinned\":true,\"x\":1}", 1000, &st);
    assert_int_equal(st, 400);
    json_decref(j);
    j = api_call(f, "PATCH", "/v1/jobs/99999", "{\"pinned\":true}", 1000, &st);
    assert_int_equal(st, 404);
    json_decref(j);
    j = api_call(f, "PATCH", pa, "{\"pinned\":true}", 1000, &st);
    assert_int_equal(st, 200);
    assert_true(json_is_true(json_object_get(j, "pinned")));
    json_decref(j);

    snprintf(pa, sizeof pa, "/v1/jobs/%lld?purge=1", a);
    j = api_call(f, "DELETE", pa, NULL, 1000, &st);
    assert_int_equal(st, 200);
    json_decref(j);
    j = api_call(f, "GET", "/v1/usage", NULL, 1000, &st);
    assert_int_equal(json_integer_value(json_object_get(j, "store_bytes")), 0);
    json_decref(j);
    /* Root may purge anyone's finished job. */
    wait_final(f, other);
    j = api_call(f, "DELETE", po, NULL, 0, &st);
    assert_int_equal(st, 200);
    json_decref(j);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_spec_limit_and_envelope, setup, teardown),
        cmocka_unit_test_setup_teardown(test_quota_pin_purge_usage, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
