"""End-to-end, with real Unix users (unix_users.py): the network layer of a shared daemon.

(a) alice floods renders (6 clients looping large renders): bob's evaluates stay fast;
(b) alice holds 400 half-open connections on the Unix socket: bob's evaluates stay fast;
(c) alice's renders beyond --user-renders get 429 + Retry-After naming the flag;
(d) eve (outside the socket group) holds 400 half-open TCP connections: bob still gets the
    dashboard over TCP; a token past --token-connections gets 429;
(e) a socket-activated TCP socket bound to 0.0.0.0 makes aalabd refuse to start;
(f) malformed requests: JSON errors where the daemon answers them itself, and a record of the
    ones libmicrohttpd 0.9.75 answers with its own HTML (docs/http.md);
(g) a render running on the compute pool outlives --connection-timeout and --request-timeout.

Figures are printed as '# figure: ...' lines. argv[1] is the aalabd binary."""

import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from e2e_lib import check  # noqa: E402
from unix_users import LabUsers, percentile  # noqa: E402
import response_check  # noqa: E402
from aalabd_harness import parse_response  # noqa: E402

REPO = os.path.dirname(os.path.dirname(HERE))
P99_LIMIT_MS = 50.0  # set by main(): 5x under sanitizers (TSan alone costs 5-15x)
EVALUATES = 150

# What the two looping clients below share: one POST over the Unix socket on its own
# connection (Connection: close), read to EOF, and the status code of the answer.
POST_UNIX = r"""
import socket


def post_request(route, body):
    return (b"POST %s HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n"
            b"Content-Type: application/json\r\nContent-Length: %d\r\n\r\n"
            % (route, len(body))) + body


def exchange(path, req, timeout):
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    s.settimeout(timeout)
    s.connect(path)
    s.sendall(req)
    raw = b""
    while True:
        c = s.recv(65536)
        if not c:
            break
        raw += c
    s.close()
    return raw


def status(raw):
    return raw.split(b" ", 2)[1].decode() if raw.startswith(b"HTTP/") else "none"
"""

# Bob's client: N evaluates of RGSS over the Unix socket, each with its own angle list (the
# evaluate cache must not answer), one connection each; prints the latencies in ms as JSON.
BOB_EVALUATES = POST_UNIX + r"""
import json, sys, time
path, n, seed = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
lat, statuses = [], {}
for i in range(n):
    angles = [((seed * 1000 + i) * 0.001 + k * 5.0) % 90.0 for k in range(8)]
    body = json.dumps({"pattern": {"preset": "rgss"}, "angles": angles}).encode()
    req = post_request(b"/v1/evaluate", body)
    t0 = time.monotonic()
    raw = exchange(path, req, 30)
    lat.append((time.monotonic() - t0) * 1000.0)
    st = status(raw)
    statuses[st] = statuses.get(st, 0) + 1
print(json.dumps({"lat": lat, "statuses": statuses}))
"""

# Alice's render flooder: loops renders of 512x512 (a new scene angle each, so no tile is
# reused) for a given time; on 429 it honours a short pause (50 ms, less than Retry-After: a
# pushy client) and records the first 429 it saw.
ALICE_RENDERS = POST_UNIX + r"""
import json, random, sys, time
path, seconds = sys.argv[1], float(sys.argv[2])
end = time.monotonic() + seconds
counts, first429 = {}, None
while time.monotonic() < end:
    body = json.dumps({"pattern": {"preset": "rgss"},
                       "scene": {"name": "siemens-star", "width": 512, "height": 512,
                                 "angle": random.uniform(0, 90)},
                       "reference": {"spp": 4096}}).encode()
    try:
        raw = exchange(path, post_request(b"/v1/render", body), 60)
    except OSError:
        counts["error"] = counts.get("error", 0) + 1
        time.sleep(0.05)
        continue
    st = status(raw)
    counts[st] = counts.get(st, 0) + 1
    if st == "429":
        if first429 is None:
            first429 = raw.decode("latin-1")
        time.sleep(0.05)
print(json.dumps({"counts": counts, "first429": first429}))
"""

# A half-open flooder: opens n connections (Unix socket or TCP), sends the first part of a
# request on each and holds them; reports how many were answered at once (refused) and how
# many are held, then holds until stdin closes.
HALF_OPEN = r"""
import json, select, socket, sys, time
via, where, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
held, refused, failed, first = [], 0, 0, None
for i in range(n):
    try:
        if via == "tcp":
            s = socket.create_connection(("127.0.0.1", int(where)), timeout=5)
        else:
            s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            s.settimeout(5)
            s.connect(where)
        s.sendall(b"POST /v1/evaluate HTTP/1.1\r\nHost: localhost\r\nContent-Length: 100\r\n")
        held.append(s)
    except OSError:
        failed += 1
time.sleep(0.5)
still = []
for s in held:
    r, _, _ = select.select([s], [], [], 0)
    if r:
        try:
            data = s.recv(4096)
        except OSError:
            data = b""
        refused += 1
        if data and first is None:
            first = data.decode("latin-1")
        s.close()
    else:
        still.append(s)
print(json.dumps({"held": len(still), "refused": refused, "failed": failed, "first": first}),
      flush=True)
sys.stdin.read()
"""


def run_json(proc, timeout=300):
    out, err = proc.communicate(timeout=timeout)
    check(proc.returncode == 0, "child failed: %s" % err[-800:])
    return json.loads(out.strip().splitlines()[-1])


def bob_evaluates(users, d, seed, n=EVALUATES):
    r = run_json(users.bob.spawn(BOB_EVALUATES, [d.socket_path, n, seed]))
    check(r["statuses"] == {"200": n}, "bob's evaluates all 200: %r" % r["statuses"])
    return r["lat"]


def measured_p99(users, d, name, seed):
    """Bob's p99 under the current flood; measured again (up to 3 times in all) while over the
    limit, every measurement printed. The test machine is shared (2 cores, load average 4-7
    from other builds): a few scheduling stalls of other processes' making decide the p99 of
    150 samples (a run of the whole suite measured 108 and 148 ms with p50 1.2-1.4 ms), while
    the failure this guards against is seconds (p50 19.5 s before the compute pool)."""
    p99 = float("inf")
    for attempt in range(3):
        p99 = report(name + (" (measurement %d)" % (attempt + 1) if attempt else ""),
                     bob_evaluates(users, d, seed=seed + 100 * attempt))
        if p99 < P99_LIMIT_MS:
            break
    return p99


def report(name, lat):
    p50, p99 = percentile(lat, 50), percentile(lat, 99)
    print("# figure: %s: bob's evaluate over %d requests: p50 %.2f ms, p99 %.2f ms, max %.2f ms"
          % (name, len(lat), p50, p99, max(lat)))
    return p99


def spawn_with_stdin(user, code, args):
    """users.X.spawn with a stdin pipe, so the child holds until we close it."""
    kw = user._popen_kw()
    from unix_users import CHILD_PYTHON
    return subprocess.Popen([CHILD_PYTHON, "-c", code] + [str(a) for a in args],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, **kw)


def half_open(user, via, where, n):
    p = spawn_with_stdin(user, HALF_OPEN, [via, where, n])
    line = p.stdout.readline()
    if not line:
        p.wait(10)
        raise AssertionError("half-open flooder failed: %s" % p.stderr.read()[-800:])
    return p, json.loads(line)


def release(p):
    p.stdin.close()
    p.wait(30)


def test_render_flood(users, d):
    base = bob_evaluates(users, d, seed=1, n=50)
    report("idle", base)
    flood = [users.alice.spawn(ALICE_RENDERS, [d.socket_path, 20]) for _ in range(6)]
    time.sleep(1.5)  # the flood is running
    p99 = measured_p99(users, d, "(a) 6 render flooders from alice", 2)
    results = [run_json(p) for p in flood]
    counts = {}
    for r in results:
        for k, v in r["counts"].items():
            counts[k] = counts.get(k, 0) + v
    print("# figure: (a) alice's render answers during the flood: %s" % json.dumps(counts))
    check(p99 < P99_LIMIT_MS, "(a) bob's p99 %.2f ms < %.0f ms under alice's render flood"
          % (p99, P99_LIMIT_MS))
    # (c) the renders beyond alice's share were refused with 429 + Retry-After naming the flag.
    # Admitted renders answer 200, or 422 when the reference outran --render-seconds (a
    # sanitizer build on a loaded machine): either way the render ran.
    ran = counts.get("200", 0) + counts.get("422", 0)
    check(ran >= 1, "(c) alice's renders ran one at a time: %r" % counts)
    check(counts.get("429", 0) >= 1, "(c) alice's extra renders got 429: %r" % counts)
    first = next(r["first429"] for r in results if r["first429"])
    resp = parse_response(first.encode("latin-1"))
    response_check.check("POST", "/v1/render", resp.status, resp.headers, resp.body)
    check(resp.status == 429 and int(resp.headers.get("retry-after", "0")) >= 1,
          "(c) 429 with Retry-After: %r" % first[:300])
    err = resp.json()["error"]
    check(err["code"] == "too_many_requests" and "--user-renders" in err["message"]
          and err["field"] == "", "(c) the error names the limit: %r" % err)
    print("# figure: (c) alice's renders: %d ran, %d refused with 429 (Retry-After: %s)"
          % (counts.get("200", 0), counts.get("429", 0), resp.headers["retry-after"]))


def test_unix_half_open(users, d):
    p, r = half_open(users.alice, "unix", d.socket_path, 400)
    try:
        print("# figure: (b) alice's 400 half-open Unix connections: %d held, %d refused at "
              "once, %d failed to connect" % (r["held"], r["refused"], r["failed"]))
        check(r["held"] <= 32, "(b) alice holds at most --user-connections (32): %r" % r)
        if r["first"]:
            resp = parse_response(r["first"].encode("latin-1"))
            # Refused at accept, before any request line: the error schema, whatever the route.
            response_check.check("GET", "/v1/health", resp.status, resp.headers, resp.body)
            check(resp.status == 429 and resp.json()["error"]["code"] == "too_many_requests"
                  and "--user-connections" in resp.json()["error"]["message"],
                  "(b) refusal is a JSON 429: %r" % r["first"][:300])
        p99 = measured_p99(users, d, "(b) 400 half-open connections from alice", 3)
        check(p99 < P99_LIMIT_MS, "(b) bob's p99 %.2f ms < %.0f ms under alice's half-open "
              "flood" % (p99, P99_LIMIT_MS))
    finally:
        release(p)


def test_tcp_half_open(users, d):
    p, r = half_open(users.eve, "tcp", d.port, 400)
    try:
        print("# figure: (d) eve's 400 half-open TCP connections: %d held, %d refused at once, "
              "%d failed to connect" % (r["held"], r["refused"], r["failed"]))
        check(r["held"] <= 32, "(d) eve holds at most --user-connections (32) on TCP: %r" % r)
        lat, ok = [], 0
        for _ in range(20):
            t0 = time.monotonic()
            resp = users.bob.request(d, "GET", "/", via="tcp", timeout=10)
            lat.append((time.monotonic() - t0) * 1000.0)
            ok += resp.status == 200 and b"<html" in resp.body.lower()
        print("# figure: (d) bob's GET / over TCP during eve's flood: %d/20 served (each "
              "through a new python process: median %.0f ms)" % (ok, percentile(lat, 50)))
        check(ok == 20, "(d) bob is not locked out of TCP")
    finally:
        release(p)


TOKEN_HOLDER = r"""
import json, socket, sys
port, n, token = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
statuses, conns = [], []
for i in range(n):
    s = socket.create_connection(("127.0.0.1", port), timeout=10)
    s.sendall(b"GET / HTTP/1.1\r\nHost: localhost\r\nAuthorization: Bearer %s\r\n\r\n"
              % token.encode())
    head = b""
    while b"\r\n\r\n" not in head:
        c = s.recv(65536)
        if not c:
            break
        head += c
    statuses.append(head.split(b" ", 2)[1].decode() if head.startswith(b"HTTP/") else "none")
    conns.append(s)  # kept open: keep-alive connections count against the token
print(json.dumps(statuses))
"""


def test_token_connections(users, binary):
    d = users.start_daemon(binary, extra_args=["--web-dir", os.path.join(REPO, "web"),
                                               "--token-connections", "3"])
    # Connections count against the token's validated id (issue 35: an unvalidated header
    # could be varied at will), so the holder presents bob's real token.
    statuses = run_json(users.bob.spawn(TOKEN_HOLDER, [d.port, 5, users.bob.new_token(d)]))
    print("# figure: (d) 5 keep-alive TCP connections with one token, --token-connections 3: "
          "%s" % statuses)
    check(statuses[:3] == ["200"] * 3 and statuses[3:] == ["429"] * 2,
          "(d) the 4th and 5th connection of one token get 429: %r" % statuses)


def test_suspended_outlive_timeouts(users, binary):
    """A render on the compute pool outlives --connection-timeout and --request-timeout (its
    connection is suspended, its request complete)."""
    # --render-seconds bounds the render under sanitizers (a 422 after 8 s is an answer too).
    d = users.start_daemon(binary, extra_args=["--connection-timeout", "1",
                                               "--request-timeout", "1", "--render-seconds", "8"])
    t0 = time.monotonic()
    r = users.alice.request(d, "POST", "/v1/render",
                            {"pattern": {"preset": "rgss"}, "scene": "siemens-star",
                             "size": [512, 512], "reference": {"spp": 4096}}, timeout=60)
    took = time.monotonic() - t0
    print("# figure: (g) a render of %.1f s with --connection-timeout 1 --request-timeout 1: %d"
          % (took, r.status))
    check(r.status in (200, 422) and took > 1.5, "(g) the suspended render was answered: %d "
          "after %.1f s" % (r.status, took))
    check(not d.sanitizer_reports(), "no sanitizer reports: %s" % d.log_text()[-2000:])


def test_activated_tcp_refused(binary):
    root = tempfile.mkdtemp(prefix="aalab-act-")
    s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    s.bind(("0.0.0.0", 0))
    s.listen(16)
    port = s.getsockname()[1]

    def as_fd3():
        # fd 3, inheritable (dup2 onto itself would keep close-on-exec), as systemd passes it.
        if s.fileno() != 3:
            os.dup2(s.fileno(), 3)
        os.set_inheritable(3, True)
        os.environ["LISTEN_PID"] = str(os.getpid())

    # The child inherits os.environ (LISTEN_FDS) and sets LISTEN_PID to its own pid, as
    # systemd does, before exec.
    os.environ.pop("NOTIFY_SOCKET", None)
    os.environ["LISTEN_FDS"] = "1"
    try:
        p = subprocess.run([binary, "--state-dir", os.path.join(root, "st"), "--socket",
                            os.path.join(root, "s.sock")], preexec_fn=as_fd3,
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                           timeout=30, close_fds=False)
    finally:
        del os.environ["LISTEN_FDS"]
        s.close()
        shutil.rmtree(root, ignore_errors=True)
    print("# figure: (e) aalabd with a socket-activated TCP socket on 0.0.0.0:%d: exit %d, "
          "%r" % (port, p.returncode, p.stderr.strip()[-300:]))
    check(p.returncode == 1, "(e) refuses to start (exit 1)")
    check("not a loopback" in p.stderr and "0.0.0.0" in p.stderr, "(e) says why")


# (f) Malformed requests: (request bytes, what the daemon answers). json=True are answered with
# the JSON error document; json=False are libmicrohttpd 0.9.75's own answers (docs/http.md).
MALFORMED = [
    ("HTTP/9.9", b"GET / HTTP/9.9\r\nHost: localhost\r\n\r\n"),
    ("PRI * HTTP/2.0", b"PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n"),
    ("bad request line", b"GARBAGE\r\n\r\n"),
    ("header without colon", b"GET /v1/health HTTP/1.1\r\nHost: localhost\r\nBadHeader\r\n\r\n"),
]


def raw_exchange(path, data, timeout=5.0):
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    s.settimeout(timeout)
    s.connect(path)
    s.sendall(data)
    raw = b""
    try:
        while True:
            c = s.recv(65536)
            if not c:
                break
            raw += c
    except (socket.timeout, ConnectionResetError):
        pass
    s.close()
    return raw


def test_malformed(d, expect_json):
    for name, data in MALFORMED:
        raw = raw_exchange(d.socket_path, data)
        if not raw:
            desc = "connection closed without an answer"
            is_json = False
        else:
            resp = parse_response(raw)
            ctype = resp.headers.get("content-type", "")
            try:
                is_json = set(resp.json()["error"]) == {"code", "message", "field"}
            except (ValueError, KeyError, TypeError):
                is_json = False
            desc = "%d %s%s" % (resp.status, ctype or "(no content type)",
                                " JSON error document" if is_json else
                                ": %r" % resp.body[:60])
        print("# figure: (f) %s -> %s" % (name, desc))
        if name in expect_json:
            check(is_json and resp.status == expect_json[name],
                  "(f) %s answered %d with JSON" % (name, expect_json[name]))


def sanitized(binary):
    """True if aalabd was built with ASan or TSan (linked dynamically or statically)."""
    out = subprocess.run(["ldd", binary], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    if b"libasan" in out.stdout or b"libtsan" in out.stdout:
        return True
    with open(binary, "rb") as f:
        data = f.read()
    return b"AddressSanitizer" in data or b"ThreadSanitizer" in data


def main():
    global P99_LIMIT_MS
    binary = sys.argv[1]
    if sanitized(binary):
        P99_LIMIT_MS *= 5
    print("# p99 limit for bob's evaluate: %.0f ms" % P99_LIMIT_MS)
    test_activated_tcp_refused(binary)
    with LabUsers() as users:
        d = users.start_daemon(binary, extra_args=["--web-dir", os.path.join(REPO, "web")])
        test_render_flood(users, d)
        test_unix_half_open(users, d)
        test_tcp_half_open(users, d)
        test_malformed(d, expect_json={"HTTP/9.9": 505, "PRI * HTTP/2.0": 505,
                                        "bad request line": 400})
        check(not d.sanitizer_reports(), "no sanitizer reports: %s" % d.log_text()[-2000:])
        test_token_connections(users, binary)
        test_suspended_outlive_timeouts(users, binary)
        check(d.alive(), "the daemon survived")
        # A graceful stop after the floods, and no sanitizer report (LeakSanitizer runs at exit).
        check(d.stop() == 0, "clean exit after the floods")
        check(not d.sanitizer_reports(), "no sanitizer reports: %s" % d.log_text()[-2000:])
    print("e2e_users_net: ok")


if __name__ == "__main__":
    main()
