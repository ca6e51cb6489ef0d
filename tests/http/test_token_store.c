/* token_store: issue, check (also after reopening the file), list, revoke, forged tokens. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>

#include "token_store.h"

static char dir[64];

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/aalab-test-tokens-XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static char *issue(token_store *ts, long long uid, long long *id)
{
    json_t *out = NULL;
    assert_int_equal(token_store_issue(ts, uid, "lab", 100, &out, NULL), AA_OK);
    assert_int_equal(json_integer_value(json_object_get(out, "uid")), uid);
    *id = json_integer_value(json_object_get(out, "id"));
    char *t = strdup(json_string_value(json_object_get(out, "token")));
    json_decref(out);
    return t;
}

static void test_issue_check_revoke(void **state)
{
    (void)state;
    token_store *ts = token_store_open(dir, NULL);
    assert_non_null(ts);
    long long a_id, b_id, uid = -1, id = -1;
    char *a = issue(ts, 1000, &a_id), *b = issue(ts, 1001, &b_id);
    assert_int_not_equal(a_id, b_id);
    assert_int_equal(token_store_check(ts, a, &uid, &id), AA_OK);
    assert_int_equal(uid, 1000);
    assert_int_equal(id, a_id);

    /* The file is 0600 and holds no secret. */
    char path[128], hex[80];
    snprintf(path, sizeof path, "%s/tokens.db", dir);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0600);
    snprintf(hex, sizeof hex, "%s", strrchr(a, '_') + 1);
    FILE *f = fopen(path, "rb");
    char *buf = calloc(1, 1 << 20);
    size_t n = fread(buf, 1, (1 << 20) - 1, f);
    fclose(f);
    assert_null(memmem(buf, n, hex, strlen(hex)));
    free(buf);

    /* Forged and malformed tokens. */
    char forged[200];
    snprintf(forged, sizeof forged, "%s", a);
    char *last = forged + strlen(forged) - 1;
    *last = *last == '0' ? '1' : '0';
    assert_int_equal(token_store_check(ts, forged, &uid, &id), TOKEN_ENOENT);
    snprintf(forged, sizeof forged, "aalab_%lld_%s", b_id, strrchr(a, '_') + 1);
    assert_int_equal(token_store_check(ts, forged, &uid, &id), TOKEN_ENOENT); /* a's secret */
    /* The real token with its id zero-padded: not canonical, refused (issue 35, point 6). */
    const char *a_secret = strrchr(a, '_') + 1;
    for (int zeros = 1; zeros <= 3; zeros++) {
        snprintf(forged, sizeof forged, "aalab_%0*lld_%s",
                 (int)(zeros + snprintf(NULL, 0, "%lld", a_id)), a_id, a_secret);
        assert_int_equal(token_store_check(ts, forged, &uid, &id), TOKEN_ENOENT);
    }
    snprintf(forged, sizeof forged, "aalab_%lld_%s", a_id, a_secret);
    assert_int_equal(token_store_check(ts, forged, &uid, &id), AA_OK);
    const char *bad[] = {
        "",
        "aalab_",
        "aalab_1_",
        "Bearer x",
        "aalab_0_00",
        "aalab_-1_00",
        "aalab_1_0000000000000000000000000000000000000000000000000000000000000000"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        assert_int_equal(token_store_check(ts, bad[i], &uid, &id), TOKEN_ENOENT);
    for (char *p = strrchr(a, '_') + 1; *p; p++) /* upper case is not the secret */
        *p = (char)(*p >= 'a' && *p <= 'f' ? *p - 'a' + 'A' : *p);
    assert_int_equal(token_store_check(ts, a, &uid, &id), TOKEN_ENOENT);
    free(a);

    /* Lists never show the secret; revoke is the owner's or the admin's. */
    json_t *mine = token_store_list(ts, 1000), *all = token_store_list(ts, -1);
    assert_int_equal(json_array_size(mine), 1);
    assert_int_equal(json_array_size(all), 2);
    assert_null(json_object_get(json_array_get(all, 0), "token"));
    json_decref(mine);
    json_decref(all);
    assert_int_equal(token_store_revoke(ts, b_id, 1000, false), TOKEN_EFORBIDDEN);
    assert_int_equal(token_store_check(ts, b, &uid, &id), AA_OK);
    token_store_close(ts);

    /* Durable: reopened, b still works; revoked, it stops at once and for good. */
    ts = token_store_open(dir, NULL);
    assert_non_null(ts);
    assert_int_equal(token_store_check(ts, b, &uid, &id), AA_OK);
    assert_int_equal(uid, 1001);
    assert_int_equal(token_store_revoke(ts, b_id, 1001, false), AA_OK);
    assert_int_equal(token_store_check(ts, b, &uid, &id), TOKEN_ENOENT);
    assert_int_equal(token_store_revoke(ts, b_id, 0, true), TOKEN_ENOENT);
    token_store_close(ts);
    ts = token_store_open(dir, NULL);
    assert_int_equal(token_store_check(ts, b, &uid, &id), TOKEN_ENOENT);
    long long c_id;
    char *c = issue(ts, 1002, &c_id);
    assert_true(c_id > b_id); /* ids are never reused */
    assert_int_equal(token_store_revoke(ts, c_id, 0, true), AA_OK);
    token_store_close(ts);
    free(b);
    free(c);
}

/* --user-tokens: a uid holds at most that many live tokens; a revocation frees a place; other
 * uids are not affected (issue 35, point 7). */
static void test_per_user_cap(void **state)
{
    (void)state;
    token_store *ts = token_store_open(dir, NULL);
    assert_non_null(ts);
    json_t *out = NULL;
    aa_error err = {0};
    long long first = -1;
    for (int i = 0; i < 3; i++) {
        assert_int_equal(token_store_issue(ts, 1000, NULL, 3, &out, &err), AA_OK);
        if (i == 0)
            first = json_integer_value(json_object_get(out, "id"));
        json_decref(out);
    }
    assert_int_equal(token_store_count(ts, 1000), 3);
    assert_int_equal(token_store_issue(ts, 1000, NULL, 3, &out, &err), TOKEN_EQUOTA);
    assert_non_null(strstr(err.message, "--user-tokens"));
    assert_int_equal(token_store_issue(ts, 1001, NULL, 3, &out, &err), AA_OK); /* another uid */
    json_decref(out);
    assert_int_equal(token_store_revoke(ts, first, 1000, false), AA_OK);
    assert_int_equal(token_store_issue(ts, 1000, NULL, 3, &out, &err), AA_OK);
    json_decref(out);
    assert_int_equal(token_store_count(ts, 1000), 3);
    token_store_close(ts);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_issue_check_revoke, setup, teardown),
        cmocka_unit_test_setup_teardown(test_per_user_cap, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
