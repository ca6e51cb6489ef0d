/* request_line_check: what the accept thread answers itself (400/505 in JSON) and what it hands
 * to libmicrohttpd, including the tolerances libmicrohttpd has (empty lines first, runs of
 * blanks, HTTP/1.x minor versions). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

#include "request_line.h"

static request_line_verdict check(const char *s)
{
    return request_line_check(s, strlen(s));
}

static void test_served(void **state)
{
    (void)state;
    assert_int_equal(check("GET / HTTP/1.1\r\n"), REQUEST_LINE_OK);
    assert_int_equal(check("POST /v1/evaluate HTTP/1.0\r\nHost: x\r\n\r\n{}"), REQUEST_LINE_OK);
    assert_int_equal(check("GET /v1/health HTTP/1.2\r\n"), REQUEST_LINE_OK);
    assert_int_equal(check("GET  /v1/health   HTTP/1.1\r\n"), REQUEST_LINE_OK);
    assert_int_equal(check("\r\n\r\nGET / HTTP/1.1\r\n"), REQUEST_LINE_OK);
    assert_int_equal(check("GET / HTTP/1.1\n"), REQUEST_LINE_OK);
    assert_int_equal(check("GET /a b HTTP/1.1\r\n"), REQUEST_LINE_OK); /* MHD's to judge */
    assert_int_equal(check("BREW /pot HTTP/1.1\r\n"), REQUEST_LINE_OK);
}

static void test_incomplete(void **state)
{
    (void)state;
    assert_int_equal(check(""), REQUEST_LINE_INCOMPLETE);
    assert_int_equal(check("GET / HTTP/1.1"), REQUEST_LINE_INCOMPLETE);
    assert_int_equal(check("\r\n"), REQUEST_LINE_INCOMPLETE);
    assert_int_equal(check("PRI * HTTP/2"), REQUEST_LINE_INCOMPLETE);
}

static void test_bad_version(void **state)
{
    (void)state;
    assert_int_equal(check("GET / HTTP/9.9\r\n"), REQUEST_LINE_BAD_VERSION);
    assert_int_equal(check("PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n"), REQUEST_LINE_BAD_VERSION);
    assert_int_equal(check("GET / HTTP/0.9\r\n"), REQUEST_LINE_BAD_VERSION);
    assert_int_equal(check("GET / HTTP/3.0\r\n"), REQUEST_LINE_BAD_VERSION);
}

static void test_bad_request(void **state)
{
    (void)state;
    assert_int_equal(check("GARBAGE\r\n\r\n"), REQUEST_LINE_BAD);
    assert_int_equal(check("GET /v1/health\r\n"), REQUEST_LINE_BAD); /* HTTP/0.9 */
    assert_int_equal(check("GET / FTP/1.1\r\n"), REQUEST_LINE_BAD);
    assert_int_equal(check("GET / HTTP/1.10\r\n"), REQUEST_LINE_BAD);
    assert_int_equal(check("GET / HTTP/x.1\r\n"), REQUEST_LINE_BAD);
    assert_int_equal(check("G(T / HTTP/1.1\r\n"), REQUEST_LINE_BAD);
    assert_int_equal(check("\x16\x03\x01\x02\x01 a b\n"), REQUEST_LINE_BAD); /* TLS */
    assert_int_equal(check("   \r\n"), REQUEST_LINE_BAD);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_served),
        cmocka_unit_test(test_incomplete),
        cmocka_unit_test(test_bad_version),
        cmocka_unit_test(test_bad_request),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
