/* The endpoints' request decoders (proto/request_*.h): each refuses bad input naming the field
 * with the wire's message, in the wire's order of checks, and decodes good input. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

#include "codec_check.h"
#include "request_enumerate.h"
#include "request_evaluate.h"
#include "request_export.h"
#include "request_token.h"

typedef int (*decode_fn)(const json_t *j, aa_error *err);

/* text decodes with decode to code, err naming field with message. */
static void refused(decode_fn decode, const char *text, int code, const char *field,
                    const char *message)
{
    json_t *j = parse(text);
    aa_error e = {0};
    assert_int_equal(decode(j, &e), code);
    assert_string_equal(e.field, field);
    assert_string_equal(e.message, message);
    json_decref(j);
}

static int enumerate(const json_t *j, aa_error *e)
{
    proto_enumerate_request r;
    return proto_decode_enumerate_request(j, &r, e);
}

static int token(const json_t *j, aa_error *e)
{
    proto_token_request r;
    return proto_decode_token_request(j, &r, e);
}

static int evaluate(const json_t *j, aa_error *e)
{
    proto_evaluate_request r;
    int rc = proto_decode_evaluate_request(j, NULL, &r, e);
    proto_evaluate_request_free(&r);
    return rc;
}

static int export_post(const json_t *j, aa_error *e)
{
    proto_export_request r;
    int rc = proto_decode_export_request(j, NULL, &r, e);
    if (!rc && !r.temporal)
        aa_pattern_free(&r.decoded);
    return rc;
}

static void enumerate_request(void **state)
{
    (void)state;
    refused(enumerate, "{\"x\":1}", AA_EINVAL, "x", "unknown field");
    refused(enumerate, "{}", AA_EINVAL, "family", "family is required");
    refused(enumerate, "{\"family\":\"P(4,1+,n)\"}", AA_EINVAL, "cost",
            "cost is required with P(4,1+,n)");
    refused(enumerate, "{\"family\":\"P(4,1+,n)\",\"cost\":17}", AA_ERANGE, "cost",
            "cost must be in (0, 16] samples per pixel");
    refused(enumerate, "{\"family\":\"P(4,1+,2)\",\"cost\":1.25}", AA_EINVAL, "cost",
            "cost disagrees with the family's n");
    json_t *j = parse("{\"family\":\"P(4,1+,1.25)\"}");
    proto_enumerate_request r;
    aa_error e = {0};
    assert_int_equal(proto_decode_enumerate_request(j, &r, &e), AA_OK);
    assert_true(r.cost == 1.25);
    json_decref(j);
}

static void token_request(void **state)
{
    (void)state;
    refused(token, "{\"label\":1}", AA_EINVAL, "label",
            "label must be a string of at most 100 bytes");
    refused(token, "{\"label\":\"a\",\"b\":1}", AA_EINVAL, "b", "unknown field");
    json_t *j = parse("{\"label\":\"ci\"}");
    proto_token_request r;
    aa_error e = {0};
    assert_int_equal(proto_decode_token_request(j, &r, &e), AA_OK);
    assert_string_equal(r.label, "ci");
    json_decref(j);
}

static void evaluate_request(void **state)
{
    (void)state;
    refused(evaluate, "{}", AA_EINVAL, "pattern", "pattern is required");
    refused(evaluate, "{\"pattern\":\"rgss\",\"detail\":1}", AA_EINVAL, "detail",
            "must be true or false");
    refused(evaluate, "{\"pattern\":\"rgss\",\"lp\":0.5}", AA_EINVAL, "lp",
            "must be a number >= 1");
    refused(evaluate, "{\"pattern\":{\"temporal\":{\"preset\":\"halton23-8\"}},\"lp\":2}",
            AA_EINVAL, "lp", "lp is not computed for temporal patterns");
    /* Unknown keys come before a reference that did not resolve; that before the rest. */
    json_t *j = parse("{\"pattern\":{\"job\":\"x\"},\"bogus\":1}");
    aa_error refs = {0}, e = {0};
    aa_error_set(&refs, AA_EINVAL, "pattern.job", "not a job id");
    proto_evaluate_request r;
    assert_int_equal(proto_decode_evaluate_request(j, &refs, &r, &e), AA_EINVAL);
    assert_string_equal(e.field, "bogus");
    proto_evaluate_request_free(&r);
    json_object_del(j, "bogus");
    json_object_set_new(j, "detail", json_integer(1));
    assert_int_equal(proto_decode_evaluate_request(j, &refs, &r, &e), AA_EINVAL);
    assert_string_equal(e.field, "pattern.job");
    proto_evaluate_request_free(&r);
    json_decref(j);
    j = parse("{\"pattern\":{\"preset\":\"rgss\"},\"angles\":[0,45],\"detail\":true}");
    assert_int_equal(proto_decode_evaluate_request(j, NULL, &r, &e), AA_OK);
    assert_false(r.temporal);
    assert_true(r.detail);
    assert_int_equal(r.angle_count, 2);
    assert_int_equal(r.pattern.kernel_count, 1);
    proto_evaluate_request_free(&r);
    json_decref(j);
}

static void export_request(void **state)
{
    (void)state;
    refused(export_post, "{\"pattern\":\"rgss\"}", AA_EINVAL, "format",
            "is required: " PROTO_EXPORT_FORMATS);
    refused(export_post, "{\"format\":\"csv\"}", AA_EINVAL, "pattern", "pattern is required");
    refused(export_post, "{\"pattern\":\"rgss\",\"format\":\"bmp\"}", AA_EINVAL, "format",
            "must be " PROTO_EXPORT_FORMATS ", jitter-c or jitter-hlsl");
    proto_export_query q;
    aa_error e = {0};
    assert_int_equal(proto_decode_export_query("bmp", NULL, &q, &e), AA_EINVAL);
    assert_string_equal(e.field, "format");
    proto_export_query_free(&q);
    assert_int_equal(proto_decode_export_query(NULL, "3", &q, &e), AA_OK);
    assert_int_equal(q.writer, PROTO_EXPORT_PATTERN);
    assert_int_equal(json_integer_value(q.phase), 3);
    proto_export_query_free(&q);
    assert_int_equal(proto_decode_export_query("csv", "x1", &q, &e), AA_OK);
    assert_int_equal(q.writer, PROTO_EXPORT_POINTS);
    assert_string_equal(json_string_value(q.phase), "x1");
    proto_export_query_free(&q);
    json_t *j = parse("{\"pattern\":\"rgss\",\"format\":\"jitter-c\"}");
    proto_export_request r;
    assert_int_equal(proto_decode_export_request(j, NULL, &r, &e), AA_OK);
    assert_true(r.temporal);
    json_decref(j);
    j = parse("{\"pattern\":{\"preset\":\"rgss\"},\"format\":\"csv\"}");
    assert_int_equal(proto_decode_export_request(j, NULL, &r, &e), AA_OK);
    assert_false(r.temporal);
    assert_int_equal(r.writer, PROTO_EXPORT_POINTS);
    aa_pattern_free(&r.decoded);
    json_decref(j);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(enumerate_request),
        cmocka_unit_test(token_request),
        cmocka_unit_test(evaluate_request),
        cmocka_unit_test(export_request),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
