/* The error table (proto/wire_error.h): every engine code has a row, statuses are errors,
 * Retry-After only where waiting helps, and the HTTP helpers answer from it. */
#include <ctype.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "handlers.h"
#include "job_manager.h"
#include "service_error.h"
#include "wire_error.h"

static const proto_wire_engine_row *engine_row(const char *aa_name)
{
    for (size_t i = 0; i < proto_wire_engine_row_count; i++)
        if (!strcmp(proto_wire_engine_rows[i].aa_name, aa_name))
            return &proto_wire_engine_rows[i];
    return NULL;
}

/* Reads the engine's error header: a code added there without a row here fails this test. */
static void test_every_engine_code_has_a_row(void **state)
{
    (void)state;
    FILE *f = fopen(AA_ERROR_HEADER, "r");
    assert_non_null(f);
    char line[256];
    int found = 0;
    while (fgets(line, sizeof line, f)) {
        const char *p = line;
        while (isspace((unsigned char)*p))
            p++;
        if (strncmp(p, "AA_E", 4))
            continue;
        char name[64];
        size_t n = 0;
        while (n + 1 < sizeof name && (isalnum((unsigned char)p[n]) || p[n] == '_')) {
            name[n] = p[n];
            n++;
        }
        name[n] = 0;
        if (!strchr(p + n, '=')) /* a mention, not an enumerator */
            continue;
        const proto_wire_engine_row *r = engine_row(name);
        if (!r)
            fail_msg("%s has no row in PROTO_WIRE_ENGINE_ERRORS", name);
        assert_int_equal(proto_wire_error_of_aa(r->aa_code), r->error);
        found++;
    }
    fclose(f);
    assert_true(found >= 4); /* EINVAL, ENOMEM, ERANGE, ECANCELED at least */
    assert_int_equal((size_t)found, proto_wire_engine_row_count);
    assert_int_equal(proto_wire_error_of_aa(-9999), WIRE_INTERNAL);
    assert_int_equal(proto_wire_error_of_aa(AA_OK), WIRE_INTERNAL);
}

static void test_rows_are_errors_with_sensible_retry_after(void **state)
{
    (void)state;
    for (int e = 0; e < WIRE_ERROR_COUNT; e++) {
        const proto_wire_row *r = proto_wire_row_of((proto_wire_error)e);
        if (r->status < 400 || r->status > 599)
            fail_msg("%s: status %d", r->name, r->status);
        /* Waiting helps only when the daemon is busy (503) or the caller over a rate (429). */
        bool waits = r->status == 429 || r->status == 503;
        if (waits != (r->retry_after > 0))
            fail_msg("%s: status %d with Retry-After %d", r->name, r->status, r->retry_after);
        assert_true(r->retry_after <= 60);
        assert_non_null(r->code);
        for (const char *c = r->code; *c; c++)
            assert_true(islower((unsigned char)*c) || *c == '_');
        for (int k = 0; k < e; k++)
            assert_string_not_equal(proto_wire_row_of((proto_wire_error)k)->name, r->name);
        /* A client finds a row (the first of equal status and code) and reads the same code. */
        const proto_wire_row *back = proto_wire_row_find(r->status, r->code);
        assert_non_null(back);
        assert_string_equal(back->code, r->code);
        assert_int_equal(back->status, r->status);
    }
    assert_null(proto_wire_row_find(200, "ok"));
    assert_null(proto_wire_row_find(404, "queue_full"));
    assert_ptr_equal(proto_wire_row_of((proto_wire_error)-1), proto_wire_row_of(WIRE_INTERNAL));
    assert_ptr_equal(proto_wire_row_of(WIRE_ERROR_COUNT), proto_wire_row_of(WIRE_INTERNAL));
}

static void test_decisions(void **state)
{
    (void)state;
    /* An allocation failure is a transient refusal, the same wherever it happens. */
    const proto_wire_row *nomem = proto_wire_row_of(proto_wire_error_of_aa(AA_ENOMEM));
    assert_int_equal(nomem->status, 503);
    assert_string_equal(nomem->code, "unavailable");
    assert_true(nomem->retry_after > 0);
    assert_int_equal(proto_wire_row_of(proto_wire_error_of_aa(AA_EINVAL))->status, 400);
    assert_string_equal(proto_wire_row_of(proto_wire_error_of_aa(AA_ERANGE))->code, "out_of_range");
    assert_int_equal(proto_wire_row_of(WIRE_QUEUE_FULL)->status, 429);
    assert_int_equal(proto_wire_row_of(WIRE_QUOTA_EXCEEDED)->retry_after, 0);
}

/* The answer api_reply_* produced: status, Retry-After and the error document. */
static void expect_answer(api_response *resp, int status, const char *code, const char *field,
                          int retry_after)
{
    assert_int_equal(resp->status, status);
    assert_int_equal(resp->retry_after, retry_after);
    json_error_t je;
    json_t *j = json_loadb(resp->body, resp->body_len, 0, &je);
    assert_non_null(j);
    json_t *e = json_object_get(j, "error");
    assert_string_equal(json_string_value(json_object_get(e, "code")), code);
    assert_string_equal(json_string_value(json_object_get(e, "field")), field);
    assert_true(strlen(json_string_value(json_object_get(e, "message"))) > 0);
    assert_int_equal(json_object_size(e), 3);
    json_decref(j);
    api_response_free(resp);
    *resp = (api_response){0};
}

static void test_http_answers_come_from_the_table(void **state)
{
    (void)state;
    api_response resp = {0};
    aa_error err = {0};
    aa_error_set(&err, AA_ENOMEM, "pattern", "out of memory");
    api_reply_aa_error(&resp, &err);
    expect_answer(&resp, 503, "unavailable", "pattern", 5);
    aa_error_set(&err, AA_ERANGE, "angles", "too many angles");
    api_reply_aa_error(&resp, &err);
    expect_answer(&resp, 400, "out_of_range", "angles", 0);
    err = (aa_error){.code = AA_EINVAL}; /* no message: the code's own text */
    api_reply_aa_error(&resp, &err);
    expect_answer(&resp, 400, "invalid_field", "", 0);

    /* The job manager's codes and the store's that reach HTTP as they are (submit, cancel,
     * purge, pin): a missing job names the field "id". */
    const struct {
        int rc, status;
        const char *code, *field;
        int retry_after;
    } jobs[] = {
        {JM_EQUEUE_FULL, 429, "queue_full", "", 5},
        {JM_EQUOTA, 429, "too_many_requests", "", 10},
        {JOB_STORE_EQUOTA, 403, "quota_exceeded", "", 0},
        {JM_ESTORE, 503, "unavailable", "", 30},
        {JOB_STORE_EUNAVAILABLE, 503, "unavailable", "", 30},
        {JM_ENOENT, 404, "not_found", "id", 0},
        {JOB_STORE_ENOENT, 404, "not_found", "id", 0},
        {JM_EFORBIDDEN, 403, "forbidden", "", 0},
        {JM_EFINISHED, 409, "conflict", "", 0},
        {JM_EACTIVE, 409, "conflict", "", 0},
    };
    for (size_t i = 0; i < sizeof jobs / sizeof jobs[0]; i++) {
        aa_error_set(&err, AA_EINVAL, "kind", "refused");
        api_reply_service_error(&resp, jobs[i].rc, &err);
        expect_answer(&resp, jobs[i].status, jobs[i].code, jobs[i].field, jobs[i].retry_after);
    }
    /* Not a job manager code: an engine error with its field. */
    aa_error_set(&err, AA_EINVAL, "seconds", "must be a number");
    api_reply_service_error(&resp, AA_EINVAL, &err);
    expect_answer(&resp, 400, "invalid_field", "seconds", 0);

    api_reply_wire(&resp, WIRE_NOT_FOUND, "id", "no job %d", 7);
    expect_answer(&resp, 404, "not_found", "id", 0);
}

/* The subsystem ranges of proto/service_error.h, by name prefix. */
static const struct {
    const char *prefix;
    int hi, lo;
} service_ranges[] = {{"JM_E", -1001, -1999},
                      {"JOB_STORE_E", -2001, -2999},
                      {"CLUSTER_E", -3001, -3999},
                      {"TOKEN_E", -4001, -4999},
                      {"TILE_E", -5001, -5999}};

/* Every service code walked through the HTTP answer: its row's status, wire code, field and
 * default message; ranges disjoint and no value shared, with each other or the engine's. */
static void test_every_service_code_answers_from_its_row(void **state)
{
    (void)state;
    assert_true(proto_service_row_count >= 20);
    for (size_t i = 0; i < proto_service_row_count; i++) {
        const proto_service_row *r = &proto_service_rows[i];
        assert_ptr_equal(proto_service_row_of(r->value), r);
        int in = 0;
        for (size_t k = 0; k < sizeof service_ranges / sizeof service_ranges[0]; k++)
            if (!strncmp(r->name, service_ranges[k].prefix, strlen(service_ranges[k].prefix)) &&
                !(k == 0 && !strncmp(r->name, "JOB_", 4))) {
                if (r->value > service_ranges[k].hi || r->value < service_ranges[k].lo)
                    fail_msg("%s = %d is outside %s's range", r->name, r->value,
                             service_ranges[k].prefix);
                in++;
            }
        if (in != 1)
            fail_msg("%s is in %d subsystem ranges", r->name, in);
        for (size_t j = 0; j < i; j++)
            if (proto_service_rows[j].value == r->value)
                fail_msg("%s and %s share %d", r->name, proto_service_rows[j].name, r->value);
        for (size_t j = 0; j < proto_wire_engine_row_count; j++)
            assert_int_not_equal(proto_wire_engine_rows[j].aa_code, r->value);
        assert_true(r->error != WIRE_ERROR_COUNT);
        assert_non_null(r->field);
        assert_true(r->message && r->message[0]);

        const proto_wire_row *w = proto_wire_row_of(r->error);
        api_response resp = {0};
        aa_error err = {.code = r->value}; /* no message: the row's */
        api_reply_service_error(&resp, r->value, &err);
        assert_int_equal(resp.status, w->status);
        assert_int_equal(resp.retry_after, w->retry_after);
        json_t *j = json_loadb(resp.body, resp.body_len, 0, NULL);
        json_t *e = json_object_get(j, "error");
        assert_string_equal(json_string_value(json_object_get(e, "code")), w->code);
        assert_string_equal(json_string_value(json_object_get(e, "field")), r->field);
        assert_string_equal(json_string_value(json_object_get(e, "message")), r->message);
        json_decref(j);
        api_response_free(&resp);
        /* The HTTP status line has a phrase for every status a row answers. */
        assert_string_not_equal(proto_http_reason(w->status), "Error");
    }
    assert_null(proto_service_row_of(0));
    assert_null(proto_service_row_of(AA_EINVAL));
    assert_string_equal(proto_http_reason(503), "Service Unavailable");
    assert_string_equal(proto_http_reason(299), "Error");
}

/* Every code a subsystem header names has a row, and none defines one itself. */
static void test_every_subsystem_code_has_a_row(void **state)
{
    (void)state;
    static const char *const headers[] = {"jobs/job_manager.h", "jobs/job_store.h",
                                          "http/token_store.h", "cluster/cluster_driver.h",
                                          "tiles/tile_store.h"};
    int found = 0;
    for (size_t h = 0; h < sizeof headers / sizeof headers[0]; h++) {
        char path[512];
        snprintf(path, sizeof path, "%s/%s", SERVER_SOURCE_DIR, headers[h]);
        FILE *f = fopen(path, "r");
        assert_non_null(f);
        char line[512];
        while (fgets(line, sizeof line, f)) {
            for (const char *p = line; *p; p++) {
                if (p > line && (isalnum((unsigned char)p[-1]) || p[-1] == '_'))
                    continue;
                size_t k = 0;
                for (; k < sizeof service_ranges / sizeof service_ranges[0]; k++)
                    if (!strncmp(p, service_ranges[k].prefix, strlen(service_ranges[k].prefix)))
                        break;
                if (k == sizeof service_ranges / sizeof service_ranges[0])
                    continue;
                char name[64];
                size_t n = 0;
                while (n + 1 < sizeof name && (isalnum((unsigned char)p[n]) || p[n] == '_')) {
                    name[n] = p[n];
                    n++;
                }
                name[n] = 0;
                if (n && name[n - 1] == '_') /* "JOB_STORE_E*"-style prose */
                    continue;
                int has = 0;
                for (size_t i = 0; i < proto_service_row_count; i++)
                    has |= !strcmp(proto_service_rows[i].name, name);
                if (!has)
                    fail_msg("%s (%s) has no row in PROTO_SERVICE_ERRORS", name, headers[h]);
                const char *rest = p + n;
                while (*rest == ' ')
                    rest++;
                if (*rest == '=' || (p - line >= 8 && !strncmp(p - 8, "#define ", 8)))
                    fail_msg("%s is defined in %s, not taken from the table", name, headers[h]);
                found++;
                p += n - 1;
            }
        }
        fclose(f);
    }
    assert_true(found >= 10);
}

static void test_unknown_keys_through_the_one_check(void **state)
{
    (void)state;
    static const char *const allowed[] = {"pattern", "angles", NULL};
    json_t *j = json_pack("{s:i, s:i}", "pattern", 1, "colour", 2);
    api_response resp = {0};
    assert_int_equal(api_reject_unknown(j, allowed, "body", &resp), -1);
    expect_answer(&resp, 400, "invalid_field", "body.colour", 0);
    assert_int_equal(api_reject_unknown(j, allowed, "", &resp), -1);
    expect_answer(&resp, 400, "invalid_field", "colour", 0);
    json_object_del(j, "colour");
    assert_int_equal(api_reject_unknown(j, allowed, "", &resp), 0);
    assert_null(resp.body);
    json_decref(j);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_engine_code_has_a_row),
        cmocka_unit_test(test_rows_are_errors_with_sensible_retry_after),
        cmocka_unit_test(test_decisions),
        cmocka_unit_test(test_http_answers_come_from_the_table),
        cmocka_unit_test(test_every_service_code_answers_from_its_row),
        cmocka_unit_test(test_every_subsystem_code_has_a_row),
        cmocka_unit_test(test_unknown_keys_through_the_one_check),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
