/* data/acuity-naiman.json and the knots the engine embeds (server/engine/metric/acuity.c) agree:
 * "knots" and "version" are the default table naiman, "alternatives.naiman-envelope" is the named
 * table naiman-envelope (version 1). Editing one without the other fails here. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include <jansson.h>

#include "aa_metric.h"
#include "codec.h"
#include "job_result_util.h"

static json_t *load_data(void)
{
    json_error_t je;
    json_t *j = json_load_file(AALAB_DATA_DIR "/acuity-naiman.json", JSON_REJECT_DUPLICATES, &je);
    if (!j)
        fail_msg("acuity-naiman.json: %s (line %d)", je.text, je.line);
    return j;
}

static void assert_knots_equal(const json_t *knots, const aa_acuity *a)
{
    assert_true(json_is_array(knots));
    assert_int_equal(json_array_size(knots), a->count);
    for (size_t i = 0; i < a->count; i++) {
        const json_t *pair = json_array_get(knots, i);
        assert_int_equal(json_array_size(pair), 2);
        assert_true(json_number_value(json_array_get(pair, 0)) == a->angle_deg[i]);
        assert_true(json_number_value(json_array_get(pair, 1)) == a->weight[i]);
    }
}

static void test_default_table_matches_data(void **state)
{
    (void)state;
    json_t *j = load_data();
    aa_acuity a;
    aa_acuity_naiman(&a);
    assert_string_equal(json_string_value(json_object_get(j, "name")), a.name);
    assert_true(json_is_integer(json_object_get(j, "version")));
    assert_int_equal(json_integer_value(json_object_get(j, "version")), a.version);
    assert_knots_equal(json_object_get(j, "knots"), &a);
    json_decref(j);
}

static void test_envelope_matches_data(void **state)
{
    (void)state;
    json_t *j = load_data();
    const json_t *alt = json_object_get(json_object_get(j, "alternatives"), "naiman-envelope");
    assert_non_null(alt);
    aa_acuity a;
    aa_error err = {0};
    assert_int_equal(aa_acuity_by_name(&a, "naiman-envelope", &err), AA_OK);
    assert_int_equal(a.version, 1);
    assert_non_null(strstr(json_string_value(json_object_get(alt, "note")), "version 1"));
    assert_knots_equal(json_object_get(alt, "knots"), &a);
    json_decref(j);
}

/* The wire side: both names decode, results record name and version (custom: the name only),
 * and a recorded reference decodes back or is refused naming the field. */
static void test_acuity_wire_names(void **state)
{
    (void)state;
    const char *names[] = {"naiman", "naiman-envelope", "uniform"};
    const int versions[] = {2, 1, 1};
    for (size_t i = 0; i < 3; i++) {
        json_t *req = json_pack("{s:s}", "name", names[i]);
        aa_acuity a;
        aa_error err = {0};
        assert_int_equal(proto_decode_acuity(req, &a, "acuity", &err), AA_OK);
        json_t *ref = proto_encode_acuity_ref(&a);
        assert_string_equal(json_string_value(json_object_get(ref, "name")), names[i]);
        assert_int_equal(json_integer_value(json_object_get(ref, "version")), versions[i]);
        json_t *holder = json_pack("{s:o}", "acuity", ref);
        char name[24];
        int version = -1;
        assert_int_equal(proto_acuity_ref_decode(holder, name, sizeof name, &version, &err), AA_OK);
        assert_string_equal(name, names[i]);
        assert_int_equal(version, versions[i]);
        json_decref(holder);
        json_decref(req);
    }
    json_t *req = json_pack("{s:[[f,f],[f,f]]}", "knots", 0.0, 3.0, 45.0, 2.0);
    aa_acuity a;
    aa_error err = {0};
    assert_int_equal(proto_decode_acuity(req, &a, "acuity", &err), AA_OK);
    json_t *ref = proto_encode_acuity_ref(&a);
    assert_string_equal(json_string_value(json_object_get(ref, "name")), "custom");
    assert_null(json_object_get(ref, "version"));
    json_decref(ref);
    json_decref(req);
    req = json_pack("{s:s}", "name", "naiman-v1");
    assert_int_not_equal(proto_decode_acuity(req, &a, "acuity", &err), AA_OK);
    assert_string_equal(err.field, "acuity.name");
    json_decref(req);
    const char *bad[] = {"{\"acuity\":{\"name\":\"naiman\"}}",
                         "{\"acuity\":{\"name\":\"custom\",\"version\":1}}",
                         "{\"acuity\":{\"name\":\"naiman\",\"version\":0}}",
                         "{\"acuity\":{\"name\":\"naiman\",\"version\":2,\"knots\":[]}}"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        json_t *j = json_loads(bad[i], 0, NULL);
        char name[24];
        int version;
        assert_non_null(j);
        assert_int_not_equal(proto_acuity_ref_decode(j, name, sizeof name, &version, &err), AA_OK);
        assert_non_null(strstr(err.field, "acuity"));
        json_decref(j);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_table_matches_data),
        cmocka_unit_test(test_envelope_matches_data),
        cmocka_unit_test(test_acuity_wire_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
