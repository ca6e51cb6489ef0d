/* conn_admission: per-uid and total connection counts at accept (AF_UNIX pairs: SO_PEERCRED
 * gives this test's uid), counts given back at release, per-token counts on TCP by header,
 * and the loopback rule for TCP peers. */
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <netinet/in.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmocka.h>

#include "conn_admission.h"

typedef struct pair {
    int a, b;
} pair;

static pair unix_pair(void)
{
    int sv[2];
    assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
    return (pair){sv[0], sv[1]};
}

static conn_admit_result admit(conn_admission *ca, int fd, conn_peer *peer)
{
    struct sockaddr sa = {.sa_family = AF_UNIX};
    return conn_admission_admit(ca, fd, &sa, sizeof sa, peer);
}

/* Releases the admitted end of each pair and closes both ends. */
static void release_and_close(conn_admission *ca, pair *p, int n)
{
    for (int i = 0; i < n; i++) {
        conn_admission_release(ca, p[i].a);
        close(p[i].a);
        close(p[i].b);
    }
}

static void test_user_limit_and_release(void **state)
{
    (void)state;
    conn_admission *ca = conn_admission_create(true, 10, 2, 2);
    assert_non_null(ca);
    pair p[3] = {unix_pair(), unix_pair(), unix_pair()};
    conn_peer peer;
    assert_int_equal(admit(ca, p[0].a, &peer), ADMIT_OK);
    assert_true(peer.uid_known);
    assert_int_equal(peer.uid, getuid());
    assert_int_equal(admit(ca, p[1].a, &peer), ADMIT_OK);
    assert_int_equal(admit(ca, p[2].a, &peer), ADMIT_USER_LIMIT);
    assert_int_equal(conn_admission_open(ca), 2);
    conn_peer found;
    assert_true(conn_admission_peer(ca, p[1].a, &found));
    assert_int_equal(found.uid, getuid());
    assert_false(conn_admission_peer(ca, p[2].a, &found));
    conn_admission_release(ca, p[0].a);
    conn_admission_release(ca, p[0].a); /* twice: no effect */
    assert_int_equal(conn_admission_open(ca), 1);
    assert_int_equal(admit(ca, p[2].a, &peer), ADMIT_OK);
    release_and_close(ca, p, 3);
    assert_int_equal(conn_admission_open(ca), 0);
    conn_admission_destroy(ca);
}

static void test_total_limit(void **state)
{
    (void)state;
    conn_admission *ca = conn_admission_create(true, 2, 10, 10);
    pair p[3] = {unix_pair(), unix_pair(), unix_pair()};
    conn_peer peer;
    assert_int_equal(admit(ca, p[0].a, &peer), ADMIT_OK);
    assert_int_equal(admit(ca, p[1].a, &peer), ADMIT_OK);
    assert_int_equal(admit(ca, p[2].a, &peer), ADMIT_TOTAL_LIMIT);
    release_and_close(ca, p, 3);
    conn_admission_destroy(ca);
}

static void test_token_limit(void **state)
{
    (void)state;
    conn_admission *ca = conn_admission_create(true, 10, 10, 1);
    pair p[3] = {unix_pair(), unix_pair(), unix_pair()};
    conn_peer peer;
    for (int i = 0; i < 3; i++)
        assert_int_equal(admit(ca, p[i].a, &peer), ADMIT_OK);
    assert_true(conn_admission_token(ca, p[0].a, 1));
    assert_true(conn_admission_token(ca, p[0].a, 1)); /* counted once */
    assert_false(conn_admission_token(ca, p[1].a, 1));
    assert_true(conn_admission_token(ca, p[1].a, 2));
    assert_true(conn_admission_token(ca, p[2].a, -1)); /* no valid token: not counted */
    conn_admission_release(ca, p[0].a);
    assert_true(conn_admission_token(ca, p[2].a, 1));
    release_and_close(ca, p, 3);
    conn_admission_destroy(ca);
}

static void test_tcp_refuses_non_loopback(void **state)
{
    (void)state;
    conn_admission *ca = conn_admission_create(false, 10, 10, 10);
    pair p = unix_pair();
    struct sockaddr_in in = {.sin_family = AF_INET};
    inet_pton(AF_INET, "10.0.0.1", &in.sin_addr);
    conn_peer peer;
    assert_int_equal(conn_admission_admit(ca, p.a, (struct sockaddr *)&in, sizeof in, &peer),
                     ADMIT_NOT_LOOPBACK);
    struct sockaddr_in6 in6 = {.sin6_family = AF_INET6};
    inet_pton(AF_INET6, "::ffff:192.168.1.1", &in6.sin6_addr);
    assert_int_equal(conn_admission_admit(ca, p.a, (struct sockaddr *)&in6, sizeof in6, &peer),
                     ADMIT_NOT_LOOPBACK);
    assert_int_equal(conn_admission_open(ca), 0);
    close(p.a);
    close(p.b);
    conn_admission_destroy(ca);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_user_limit_and_release),
        cmocka_unit_test(test_total_limit),
        cmocka_unit_test(test_token_limit),
        cmocka_unit_test(test_tcp_refuses_non_loopback),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
