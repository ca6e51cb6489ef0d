/* The default dashboard directory: the source tree's web/ for a program run from its build tree
 * (this test is one), the installed share/aalab/web otherwise (checked on the installed package
 * by tests/package/package_stage.sh, whose daemon gets no --web-dir). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "config.h"
#include "install_paths.h"

static void test_build_tree_serves_source_web(void **state)
{
    (void)state;
    assert_string_equal(install_default_web_dir(), TEST_SOURCE_WEB_DIR);
    aalab_config c;
    config_defaults(&c);
    assert_string_equal(c.web_dir, TEST_SOURCE_WEB_DIR);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_build_tree_serves_source_web),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
