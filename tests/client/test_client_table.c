/* table: column widths, numeric right-alignment, "-" for missing cells, key/value listing. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "capture.h"
#include "table.h"

static void aligns_columns(void **state)
{
    const char *headers[] = {"name", "e2"};
    table *t = table_new(2, headers);
    assert_non_null(t);
    const char *r1[] = {"quincunx", "0.518"};
    const char *r2[] = {"rgss", "12.5"};
    assert_int_equal(table_add_row(t, r1), 0);
    assert_int_equal(table_add_row(t, r2), 0);
    assert_int_equal(table_rows(t), 2);
    capture c;
    table_print(t, capture_begin(&c));
    /* text left-aligned and padded, numbers right-aligned, two spaces between columns */
    assert_string_equal(capture_end(&c), "name         e2\n"
                                         "quincunx  0.518\n"
                                         "rgss       12.5\n");
    capture_free(&c);
    table_free(t);
}

static void missing_cells_and_no_trailing_blanks(void **state)
{
    const char *headers[] = {"id", "state"};
    table *t = table_new(2, headers);
    const char *r1[] = {NULL, "running"};
    const char *r2[] = {"12", NULL};
    table_add_row(t, r1);
    table_add_row(t, r2);
    capture c;
    table_print(t, capture_begin(&c));
    assert_string_equal(capture_end(&c), "id  state\n"
                                         " -  running\n"
                                         "12  -\n");
    capture_free(&c);
    table_free(t);
}

static void empty_trailing_cells(void **state)
{
    const char *headers[] = {"a", "b", "c"};
    table *t = table_new(3, headers);
    const char *r1[] = {"x", "", ""};
    const char *r2[] = {"y", "", "z"};
    table_add_row(t, r1);
    table_add_row(t, r2);
    capture c;
    table_print(t, capture_begin(&c));
    assert_string_equal(capture_end(&c), "a  b  c\n"
                                         "x\n"
                                         "y     z\n");
    capture_free(&c);
    table_free(t);
}

static void many_rows_grow(void **state)
{
    const char *headers[] = {"n"};
    table *t = table_new(1, headers);
    char buf[16];
    for (int i = 0; i < 1000; i++) {
        snprintf(buf, sizeof buf, "%d", i);
        const char *row[] = {buf};
        assert_int_equal(table_add_row(t, row), 0);
    }
    assert_int_equal(table_rows(t), 1000);
    capture c;
    table_print(t, capture_begin(&c));
    const char *text = capture_end(&c);
    assert_non_null(strstr(text, "\n999\n"));
    assert_non_null(strstr(text, "\n  0\n"));
    capture_free(&c);
    table_free(t);
}

static void header_only(void **state)
{
    const char *headers[] = {"a", "bb"};
    table *t = table_new(2, headers);
    capture c;
    table_print(t, capture_begin(&c));
    assert_string_equal(capture_end(&c), "a  bb\n");
    capture_free(&c);
    table_free(t);
    assert_null(table_new(0, headers));
}

static void key_values(void **state)
{
    const char *keys[] = {"version", "uptime_s"};
    const char *values[] = {"0.1.0", NULL};
    capture c;
    print_key_values(capture_begin(&c), keys, values, 2);
    assert_string_equal(capture_end(&c), "version   0.1.0\n"
                                         "uptime_s  -\n");
    capture_free(&c);
}

static void csv_quoting(void **state)
{
    const char *headers[] = {"name", "label", "e2"};
    table *t = table_new(3, headers);
    const char *r1[] = {"plain", "a, b", "0.5"};
    const char *r2[] = {"say \"hi\"", "two\nlines", NULL};
    const char *r3[] = {"-", "cr\rhere", "-"};
    assert_int_equal(table_add_row(t, r1), 0);
    assert_int_equal(table_add_row(t, r2), 0);
    assert_int_equal(table_add_row(t, r3), 0);
    capture c;
    table_print_csv(t, capture_begin(&c));
    /* RFC 4180: CRLF records; fields with , " CR LF quoted, quotes doubled; no value is empty */
    assert_string_equal(capture_end(&c), "name,label,e2\r\n"
                                         "plain,\"a, b\",0.5\r\n"
                                         "\"say \"\"hi\"\"\",\"two\nlines\",\r\n"
                                         ",\"cr\rhere\",\r\n");
    capture_free(&c);
    table_write(t, capture_begin(&c), false);
    assert_non_null(strstr(capture_end(&c), "name      label"));
    capture_free(&c);
    table_free(t);
}

static void csv_key_values(void **state)
{
    const char *keys[] = {"family", "E2"};
    const char *values[] = {"P(4,1+,2)", "-"};
    capture c;
    print_key_values_csv(capture_begin(&c), keys, values, 2);
    assert_string_equal(capture_end(&c), "key,value\r\nfamily,\"P(4,1+,2)\"\r\nE2,\r\n");
    capture_free(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(aligns_columns),
        cmocka_unit_test(missing_cells_and_no_trailing_blanks),
        cmocka_unit_test(empty_trailing_cells),
        cmocka_unit_test(many_rows_grow),
        cmocka_unit_test(header_only),
        cmocka_unit_test(key_values),
        cmocka_unit_test(csv_quoting),
        cmocka_unit_test(csv_key_values),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
