/* A listener on a TCP socket bound to 0.0.0.0 (as a careless socket unit would pass it) serves
 * loopback peers only: a connection from this host's own non-loopback address (a peer address
 * outside 127.0.0.0/8) is closed unanswered and logged in one line, while 127.0.0.1 is served.
 * Needs a non-loopback IPv4 address on this host; without one the test says so and fails. */
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmocka.h>

#include "api_fixture.h"
#include "mhd_adapter.h"

/* The listener's log: written by its accept thread, read after the listener has stopped. */
static char logged[1024];

static void capture(const char *line)
{
    snprintf(logged + strlen(logged), sizeof logged - strlen(logged), "%s\n", line);
}

static bool non_loopback_ipv4(struct in_addr *out)
{
    struct ifaddrs *ifs, *i;
    bool found = false;
    if (getifaddrs(&ifs))
        return false;
    for (i = ifs; i && !found; i = i->ifa_next) {
        if (i->ifa_addr && i->ifa_addr->sa_family == AF_INET) {
            struct in_addr a = ((struct sockaddr_in *)i->ifa_addr)->sin_addr;
            if ((ntohl(a.s_addr) >> 24) != 127) {
                *out = a;
                found = true;
            }
        }
    }
    freeifaddrs(ifs);
    return found;
}

/* One GET over a fresh connection from source address src to dst:port; the answer's bytes. */
static size_t exchange(struct in_addr src, struct in_addr dst, int port, char *buf, size_t cap)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    assert_true(fd >= 0);
    struct sockaddr_in me = {.sin_family = AF_INET, .sin_addr = src};
    assert_int_equal(bind(fd, (struct sockaddr *)&me, sizeof me), 0);
    struct sockaddr_in to = {.sin_family = AF_INET, .sin_addr = dst, .sin_port = htons(port)};
    assert_int_equal(connect(fd, (struct sockaddr *)&to, sizeof to), 0);
    struct timeval tv = {.tv_sec = 10};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    const char req[] = "GET /v1/health HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n";
    send(fd, req, sizeof req - 1, MSG_NOSIGNAL);
    size_t n = 0;
    for (;;) {
        ssize_t r = recv(fd, buf + n, cap - 1 - n, 0);
        if (r <= 0)
            break;
        n += (size_t)r;
    }
    buf[n] = 0;
    close(fd);
    return n;
}

static void test_only_loopback_peers_served(void **state)
{
    (void)state;
    struct in_addr outside, lo = {.s_addr = htonl(INADDR_LOOPBACK)};
    if (!non_loopback_ipv4(&outside))
        fail_msg("this host has no non-loopback IPv4 address to connect from");
    api_fixture *f = api_fixture_open("peers", NULL);

    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in any = {.sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_ANY)};
    socklen_t len = sizeof any;
    assert_int_equal(bind(fd, (struct sockaddr *)&any, sizeof any), 0);
    assert_int_equal(listen(fd, 16), 0);
    assert_int_equal(getsockname(fd, (struct sockaddr *)&any, &len), 0);
    int port = ntohs(any.sin_port);
    char msg[256];
    http_listener *l =
        http_listener_start(f->ctx, &f->cfg, fd, false, NULL, capture, msg, sizeof msg);
    assert_non_null(l);

    char buf[8192];
    assert_int_equal(exchange(outside, outside, port, buf, sizeof buf), 0);
    size_t n = exchange(lo, lo, port, buf, sizeof buf);
    assert_true(n > 0);
    /* Served: the API answers (and, over TCP without a token, refuses with its JSON 401). */
    assert_non_null(strstr(buf, "HTTP/1.1 401"));
    assert_non_null(strstr(buf, "\"unauthorized\""));

    http_listener_quiesce(l);
    http_listener_stop(l);
    char ip[INET_ADDRSTRLEN];
    inet_ntop(AF_INET, &outside, ip, sizeof ip);
    char expect[128];
    snprintf(expect, sizeof expect, "refused a TCP connection from %s: not a loopback address\n",
             ip);
    assert_string_equal(logged, expect); /* one line, for the one refused connection */
    assert_int_equal(api_fixture_close(f), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_only_loopback_peers_served),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
