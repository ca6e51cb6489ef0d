/* The job contract through api_handle: GET /v1/kinds, the unknown-kind and unknown-preset
 * errors, families refused at submit, the envelope's label, the job list's family / label /
 * best_e2 and its kind filter, {"job": ID} references to a kind's best pattern. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <math.h>
#include <unistd.h>

#include <cmocka.h>

#include "api_fixture.h"
#include "kinds.h"
#include "schemas_embedded.h"

typedef api_fixture fixture;

static void configure(aalab_config *cfg)
{
    cfg->workers = 2;
    cfg->test_kinds = true;
    cfg->max_job_seconds = 50;
}

static int setup(void **state)
{
    *state = api_fixture_open("kinds", configure);
    return 0;
}

static int teardown(void **state)
{
    return api_fixture_close(*state);
}

/* Every request here is made as uid 1000, and every answer has a JSON body. */
static json_t *call(fixture *f, const char *method, const char *path, const char *body, int *status)
{
    json_t *j = api_call(f, method, path, body, 1000, status);
    assert_non_null(j);
    return j;
}

/* A 400 naming field; returns its message (valid while j lives). */
static const char *bad_request(json_t *j, int st, const char *field)
{
    assert_int_equal(st, 400);
    json_t *e = json_object_get(j, "error");
    assert_string_equal(json_string_value(json_object_get(e, "field")), field);
    return json_string_value(json_object_get(e, "message"));
}

static bool ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), m = strlen(tail);
    return n >= m && !strcmp(s + n - m, tail);
}

static json_t *wait_done(fixture *f, long long id)
{
    char path[64];
    snprintf(path, sizeof path, "/v1/jobs/%lld", id);
    for (int i = 0; i < 3000; i++) {
        int st;
        json_t *j = call(f, "GET", path, NULL, &st);
        const char *s = json_string_value(json_object_get(j, "state"));
        if (strcmp(s, "queued") && strcmp(s, "running")) {
            assert_string_equal(s, "done");
            return j;
        }
        json_decref(j);
        struct timespec d = {0, 10 * 1000 * 1000};
        nanosleep(&d, NULL);
    }
    fail_msg("job %lld did not finish", id);
    return NULL;
}

static long long submit(fixture *f, const char *body)
{
    return api_submit(f, body, 1000);
}

/* The kinds are those of proto/schemas/kinds (the schemas this daemon embeds): one
 * <name>.spec.json each. */
static bool is_kind_schema(const char *name)
{
    char path[128];
    snprintf(path, sizeof path, "kinds/%s.spec.json", name);
    for (size_t i = 0; i < embedded_schema_count; i++)
        if (!strcmp(embedded_schemas[i].path, path))
            return true;
    return false;
}

static size_t kind_schema_count(void)
{
    size_t n = 0;
    for (size_t i = 0; i < embedded_schema_count; i++)
        n += !strncmp(embedded_schemas[i].path, "kinds/", 6) &&
             ends_with(embedded_schemas[i].path, ".spec.json");
    return n;
}

/* kind_list.h's ids, in order, are the table's kinds with '_' for '-' (kind_<id>.c defines
 * job_kind_<id>, the row of the kind named <id> with dashes). */
static void test_kind_list_ids(void **state)
{
    static const char *const ids[] = {
#define KIND(id) #id,
#include "kind_list.h"
#undef KIND
    };
    size_t count;
    const job_kind *const *table = job_kinds_table(&count);
    assert_int_equal(count, sizeof ids / sizeof ids[0]);
    for (size_t k = 0; k < count; k++) {
        char name[64];
        snprintf(name, sizeof name, "%s", ids[k]);
        for (char *c = name; *c; c++)
            *c = *c == '_' ? '-' : *c;
        assert_string_equal(table[k]->name, name);
        assert_ptr_equal(job_kind_find(name), table[k]);
    }
}

static void test_kinds_listing(void **state)
{
    fixture *f = *state;
    int st;
    json_t *j = call(f, "GET", "/v1/kinds", NULL, &st);
    assert_int_equal(st, 200);
    assert_true(json_is_object(json_object_get(j, "envelope_schema")));
    json_t *kinds = json_object_get(j, "kinds");
    size_t found = 0;
    size_t i;
    json_t *k;
    json_array_foreach(kinds, i, k)
    {
        const char *name = json_string_value(json_object_get(k, "name"));
        assert_non_null(name);
        found += is_kind_schema(name);
        assert_true(strlen(json_string_value(json_object_get(k, "summary"))) > 20);
        assert_true(json_is_array(json_object_get(k, "examples")));
        if (strcmp(name, "sleep")) {
            assert_true(json_is_object(json_object_get(k, "spec_schema")));
            assert_true(json_is_object(json_object_get(k, "result_schema")));
            assert_true(json_array_size(json_object_get(k, "examples")) >= 1);
            /* The examples are the spec schema's. */
            assert_true(json_equal(json_object_get(k, "examples"),
                                   json_object_get(json_object_get(k, "spec_schema"), "examples")));
        }
    }
    /* Every kind has its schemas in proto/schemas/kinds, and every kind there is listed. */
    assert_int_equal(found, json_array_size(kinds));
    assert_int_equal(json_array_size(kinds), kind_schema_count());
    assert_true(json_array_size(kinds) >= 10);
    assert_string_equal(json_string_value(json_object_get(json_array_get(kinds, 0), "name")),
                        "optimize");
    json_decref(j);
}

static void test_unknown_kind_and_preset(void **state)
{
    fixture *f = *state;
    int st;
    json_t *j = call(f, "POST", "/v1/jobs", "{\"kind\":\"foo\"}", &st);
    const char *msg = bad_request(j, st, "kind");
    assert_string_equal(json_string_value(json_object_get(json_object_get(j, "error"), "code")),
                        "invalid_field");
    const char *want = "unknown job kind \"foo\"; known kinds: optimize, family-sweep, "
                       "random-stats, table3, temporal-optimize, compare, animation, "
                       "reference-convergence";
    assert_memory_equal(msg, want, strlen(want));
    json_decref(j);

    j = call(f, "GET", "/v1/jobs?kind=foo", NULL, &st);
    assert_memory_equal(bad_request(j, st, "kind"), want, strlen(want));
    json_decref(j);

    /* The same suggestion from evaluate and from a job spec. */
    j = call(f, "POST", "/v1/evaluate", "{\"pattern\":{\"preset\":\"flipqaud\"}}", &st);
    msg = bad_request(j, st, "pattern.preset");
    assert_non_null(strstr(msg, "did you mean \"flipquad\""));
    assert_true(ends_with(msg, "?"));
    json_decref(j);
    j = call(f, "POST", "/v1/jobs",
             "{\"kind\":\"compare\",\"scene\":{\"name\":\"siemens-star\",\"width\":16,"
             "\"height\":16},\"patterns\":[\"rgss\",\"flipqaud\"]}",
             &st);
    msg = bad_request(j, st, "patterns[1]");
    assert_non_null(strstr(msg, "unknown preset \"flipqaud\"; did you mean \"flipquad\""));
    json_decref(j);
    j = call(f, "POST", "/v1/jobs",
             "{\"kind\":\"optimize\",\"pattern\":{\"preset\":\"rgs\"},\"max_seconds\":1}", &st);
    assert_non_null(strstr(bad_request(j, st, "pattern.preset"), "did you mean \"rgss\""));
    json_decref(j);
}

static void test_invalid_at_submit(void **state)
{
    fixture *f = *state;
    int st;
    struct {
        const char *body, *field;
    } cases[] = {
        {"{\"kind\":\"random-stats\",\"family\":\"P(4,1,2)\"}", "family"},
        {"{\"kind\":\"optimize\",\"family\":\"P(4,1,x)\"}", "family"},
        {"{\"kind\":\"optimize\",\"family\":\"P(3,1,2)\"}", "family"},
        {"{\"kind\":\"family-sweep\",\"family\":\"P(16,16,4)\"}", "family"},
        {"{\"kind\":\"optimize\",\"pattern\":{\"kernels\":[[[0.5,0.5]]]}}",
         "pattern.kernels[0][0]"},
        {"{\"kind\":\"optimize\",\"family\":\"P(4,1+,2)\",\"label\":7}", "label"},
        {"{\"kind\":\"optimize\",\"family\":\"P(4,1+,2)\",\"priority\":11}", "priority"},
        /* Above this daemon's --max-job-seconds (50), read from the decoded spec. */
        {"{\"kind\":\"random-stats\",\"family\":\"P(1,1,3)\",\"max_seconds\":100}", "max_seconds"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        json_t *j = call(f, "POST", "/v1/jobs", cases[i].body, &st);
        bad_request(j, st, cases[i].field);
        json_decref(j);
    }
    char body[400];
    snprintf(body, sizeof body, "{\"kind\":\"sleep\",\"seconds\":0,\"label\":\"%0201d\"}", 0);
    json_t *j = call(f, "POST", "/v1/jobs", body, &st);
    bad_request(j, st, "label");
    json_decref(j);
}

static void test_list_fields_and_references(void **state)
{
    fixture *f = *state;
    int st;
    long long s = submit(f, "{\"kind\":\"sleep\",\"seconds\":0.05,\"label\":\"nap\","
                            "\"pattern\":{\"preset\":\"rgss\"}}");
    long long o = submit(f, "{\"kind\":\"optimize\",\"family\":\"P(4,1+,1)\",\"seeds\":1,"
                            "\"max_seconds\":1,\"rng_seed\":3}");
    json_t *done = wait_done(f, s);
    /* The envelope is not part of the stored spec. */
    json_t *spec = json_object_get(done, "spec");
    assert_null(json_object_get(spec, "label"));
    assert_string_equal(json_string_value(json_object_get(spec, "kind")), "sleep");
    assert_string_equal(json_string_value(json_object_get(done, "label")), "nap");
    json_decref(done);
    json_t *opt = wait_done(f, o);
    double e2 = json_number_value(json_object_get(json_object_get(opt, "result"), "e2"));
    json_decref(opt);

    json_t *j = call(f, "GET", "/v1/jobs", NULL, &st);
    assert_int_equal(st, 200);
    size_t i, seen = 0;
    json_t *job;
    json_array_foreach(json_object_get(j, "jobs"), i, job)
    {
        long long id = json_integer_value(json_object_get(job, "id"));
        json_t *family = json_object_get(job, "family"), *label = json_object_get(job, "label"),
               *best = json_object_get(job, "best_e2");
        assert_non_null(family);
        assert_non_null(label);
        assert_non_null(best);
        if (id == s) {
            assert_string_equal(json_string_value(label), "nap");
            assert_true(json_is_null(best)); /* a sleep has no E2 */
            seen++;
        } else if (id == o) {
            assert_true(json_is_null(label));
            assert_string_equal(json_string_value(family), "P(4,1+,1)");
            assert_true(json_number_value(best) == e2);
            seen++;
        }
    }
    assert_int_equal(seen, 2);
    json_decref(j);

    j = call(f, "GET", "/v1/jobs?kind=optimize", NULL, &st);
    assert_int_equal(st, 200);
    assert_true(json_array_size(json_object_get(j, "jobs")) >= 1);
    json_array_foreach(json_object_get(j, "jobs"), i, job)
        assert_string_equal(json_string_value(json_object_get(job, "kind")), "optimize");
    json_decref(j);

    /* {"job": ID} takes the job's best pattern, for every kind that has one. */
    char body[200];
    long long ids[2] = {s, o};
    for (int k = 0; k < 2; k++) {
        snprintf(body, sizeof body, "{\"pattern\":{\"job\":%lld}}", ids[k]);
        j = call(f, "POST", "/v1/evaluate", body, &st);
        assert_int_equal(st, 200);
        if (ids[k] == o)
            assert_true(fabs(json_number_value(json_object_get(j, "e2")) - e2) < 1e-9);
        json_decref(j);
    }
}

/* animation: its pattern's E2 is its best, so the list shows it (issue 34: "-" there, 0.438987
 * in the detail); its best names the pattern's family and cost only, so there is no pattern to
 * export or to reference ({"job": ID}), said as before (409 and 400), not a 500. */
static void test_animation_best(void **state)
{
    fixture *f = *state;
    int st;
    long long a = submit(f, "{\"kind\":\"animation\",\"scene\":{\"name\":\"rotating-triangle\","
                            "\"frames\":2,\"width\":16,\"height\":16},\"reference\":{\"spp\":16},"
                            "\"pattern\":{\"preset\":\"rgss\"}}");
    json_t *done = wait_done(f, a);
    double e2 = json_number_value(json_object_get(json_object_get(done, "result"), "e2"));
    assert_true(e2 > 0);
    json_decref(done);
    json_t *j = call(f, "GET", "/v1/jobs?kind=animation", NULL, &st);
    json_t *row = json_array_get(json_object_get(j, "jobs"), 0);
    assert_true(json_is_number(json_object_get(row, "best_e2")));
    assert_true(json_number_value(json_object_get(row, "best_e2")) == e2);
    assert_string_equal(json_string_value(json_object_get(row, "family")), "P(1,1,4)");
    json_decref(j);
    char path[80];
    snprintf(path, sizeof path, "/v1/patterns/%lld/export?format=json", a);
    j = api_call(f, "GET", path, NULL, 1000, &st);
    assert_int_equal(st, 409);
    json_decref(j);
    char body[80];
    snprintf(body, sizeof body, "{\"pattern\":{\"job\":%lld}}", a);
    j = call(f, "POST", "/v1/evaluate", body, &st);
    bad_request(j, st, "pattern.job");
    json_decref(j);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_animation_best, setup, teardown),
        cmocka_unit_test_setup_teardown(test_kinds_listing, setup, teardown),
        cmocka_unit_test(test_kind_list_ids),
        cmocka_unit_test_setup_teardown(test_unknown_kind_and_preset, setup, teardown),
        cmocka_unit_test_setup_teardown(test_invalid_at_submit, setup, teardown),
        cmocka_unit_test_setup_teardown(test_list_fields_and_references, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
