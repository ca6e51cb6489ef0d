/* peer_identity: the loopback rule on addresses, SO_PEERCRED on an AF_UNIX pair, and the owner
 * uid of the connecting socket of a loopback TCP connection made here (sock_diag), IPv4 and
 * IPv6. The test's own uid is the answer every lookup must give. */
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmocka.h>

#include "peer_identity.h"

static bool loopback4(const char *ip)
{
    struct sockaddr_in in = {.sin_family = AF_INET, .sin_port = htons(80)};
    assert_int_equal(inet_pton(AF_INET, ip, &in.sin_addr), 1);
    return peer_addr_is_loopback((struct sockaddr *)&in, sizeof in);
}

static bool loopback6(const char *ip)
{
    struct sockaddr_in6 in6 = {.sin6_family = AF_INET6, .sin6_port = htons(80)};
    assert_int_equal(inet_pton(AF_INET6, ip, &in6.sin6_addr), 1);
    return peer_addr_is_loopback((struct sockaddr *)&in6, sizeof in6);
}

static void test_loopback_rule(void **state)
{
    (void)state;
    assert_true(loopback4("127.0.0.1"));
    assert_true(loopback4("127.255.0.9"));
    assert_true(loopback6("::1"));
    assert_true(loopback6("::ffff:127.0.0.1"));
    assert_false(loopback4("10.0.0.1"));
    assert_false(loopback4("192.168.1.1"));
    assert_false(loopback4("0.0.0.0"));
    assert_false(loopback4("128.0.0.1"));
    assert_false(loopback6("::ffff:10.0.0.1"));
    assert_false(loopback6("::"));
    assert_false(loopback6("fe80::1"));
    assert_false(loopback6("::2"));
    struct sockaddr_in shortaddr = {.sin_family = AF_INET};
    inet_pton(AF_INET, "127.0.0.1", &shortaddr.sin_addr);
    assert_false(peer_addr_is_loopback((struct sockaddr *)&shortaddr, 4));
    struct sockaddr unix_addr = {.sa_family = AF_UNIX};
    assert_false(peer_addr_is_loopback(&unix_addr, sizeof unix_addr));
    assert_false(peer_addr_is_loopback(NULL, 0));
}

static void test_unix_peer_uid(void **state)
{
    (void)state;
    int sv[2];
    assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
    uid_t uid = (uid_t)-1;
    assert_int_equal(peer_unix_uid(sv[0], &uid), 0);
    assert_int_equal(uid, getuid());
    close(sv[0]);
    close(sv[1]);
    assert_int_equal(peer_unix_uid(-1, &uid), -1);
}

/* A connected loopback pair: *server is the accepted end. False if family is unavailable. */
static bool tcp_pair(int family, int *client, int *server)
{
    struct sockaddr_storage ss;
    memset(&ss, 0, sizeof ss);
    socklen_t len;
    if (family == AF_INET) {
        struct sockaddr_in *in = (struct sockaddr_in *)&ss;
        in->sin_family = AF_INET;
        in->sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        len = sizeof *in;
    } else {
        struct sockaddr_in6 *in6 = (struct sockaddr_in6 *)&ss;
        in6->sin6_family = AF_INET6;
        in6->sin6_addr = in6addr_loopback;
        len = sizeof *in6;
    }
    int l = socket(family, SOCK_STREAM, 0);
    if (l < 0 || bind(l, (struct sockaddr *)&ss, len)) {
        if (l >= 0)
            close(l);
        return false;
    }
    assert_int_equal(listen(l, 4), 0);
    assert_int_equal(getsockname(l, (struct sockaddr *)&ss, &len), 0);
    *client = socket(family, SOCK_STREAM, 0);
    assert_true(*client >= 0);
    assert_int_equal(connect(*client, (struct sockaddr *)&ss, len), 0);
    *server = accept(l, NULL, NULL);
    assert_true(*server >= 0);
    close(l);
    return true;
}

static void check_tcp_uid(int family)
{
    int c, s;
    if (!tcp_pair(family, &c, &s)) {
        print_message("no %s loopback here: skipped\n", family == AF_INET ? "IPv4" : "IPv6");
        return;
    }
    uid_t uid = (uid_t)-1;
    int rc = peer_tcp_uid(s, &uid);
    if (rc)
        print_message("peer_tcp_uid: %s\n", strerror(errno));
    assert_int_equal(rc, 0);
    assert_int_equal(uid, getuid());
    /* The client end asks about the server's accepted socket: same uid, found the same way. */
    uid = (uid_t)-1;
    assert_int_equal(peer_tcp_uid(c, &uid), 0);
    assert_int_equal(uid, getuid());
    close(c);
    /* A closed peer leaves nothing to find (or a socket in FIN state, still ours). */
    close(s);
}

static void test_tcp_peer_uid_ipv4(void **state)
{
    (void)state;
    check_tcp_uid(AF_INET);
}

static void test_tcp_peer_uid_ipv6(void **state)
{
    (void)state;
    check_tcp_uid(AF_INET6);
}

static void test_tcp_uid_of_non_tcp_fails(void **state)
{
    (void)state;
    int sv[2];
    assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
    uid_t uid;
    assert_int_equal(peer_tcp_uid(sv[0], &uid), -1);
    close(sv[0]);
    close(sv[1]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_loopback_rule),
        cmocka_unit_test(test_unix_peer_uid),
        cmocka_unit_test(test_tcp_peer_uid_ipv4),
        cmocka_unit_test(test_tcp_peer_uid_ipv6),
        cmocka_unit_test(test_tcp_uid_of_non_tcp_fails),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
