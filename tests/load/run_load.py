#!/usr/bin/env python3
"""Load and overload against a real aalabd, from second processes (aalab_load over the Unix
socket, wrk over TCP loopback).

  --quick (ctest "load_smoke", ~20 s): 3 s of evaluate load over the Unix socket and over TCP,
          RSS before/after; job flood past the queue bound -> 429 + Retry-After, every answer
          within 5 s; an idle and a slow (byte-by-byte) connection are closed by the daemon.
  --full  (benchmark, run by hand): one million evaluate requests over the Unix socket with 2
          connections, RSS before/after (growth must stay under 5 %), then 30 s of wrk over TCP.

Usage: run_load.py --aalabd PATH --load PATH/aalab_load (--quick | --full) [--requests N]
"""

import argparse
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import aalabd_harness as H  # noqa: E402

EVAL_BODY = ('{"pattern":{"kernels":[[[-0.125,-0.375,0.25],[0.375,-0.125,0.25],'
             '[0.125,0.375,0.25],[-0.375,0.125,0.25]]]}}')


class Failure(Exception):
    pass


def expect(cond, msg):
    if not cond:
        raise Failure(msg)


def run_load(load, d, transport, extra):
    target = ["--unix", d.socket_path] if transport == "unix" else ["--tcp", "127.0.0.1:%d" % d.port]
    out = subprocess.run([load] + target + extra, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         timeout=3600)
    line = out.stdout.decode().strip().splitlines()[-1] if out.stdout.strip() else "{}"
    res = json.loads(line)
    res["exit"] = out.returncode
    return res


def run_wrk(d, seconds, connections=2, threads=1):
    if not shutil.which("wrk"):
        return None
    tmp = tempfile.mkdtemp(prefix="aalab-wrk-")
    lua = os.path.join(tmp, "post.lua")
    with open(lua, "w") as f:
        f.write('wrk.method = "POST"\nwrk.body = %s\nwrk.headers["Content-Type"] = "application/json"\n'
                % json.dumps(EVAL_BODY))
        if d.token:  # the TCP listener wants a bearer token on every API request
            f.write('wrk.headers["Authorization"] = "Bearer %s"\n' % d.token)
        f.write("done = function(summary, latency, requests)\n"
                "  io.write(string.format('WRKJSON {\"requests\":%d,\"seconds\":%.3f,\"p50_us\":%.1f,"
                "\"p99_us\":%.1f,\"errors\":%d,\"non2xx\":%d}\\n', summary.requests, summary.duration/1e6,"
                " latency:percentile(50), latency:percentile(99), summary.errors.connect + summary.errors.read"
                " + summary.errors.write + summary.errors.timeout, summary.errors.status))\nend\n")
    out = subprocess.run(["wrk", "-t%d" % threads, "-c%d" % connections, "-d%ds" % seconds, "--timeout", "5s",
                          "-s", lua, "http://127.0.0.1:%d/v1/evaluate" % d.port],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=seconds + 60)
    shutil.rmtree(tmp, ignore_errors=True)
    for line in out.stdout.decode().splitlines():
        if line.startswith("WRKJSON "):
            r = json.loads(line[8:])
            r["req_per_s"] = r["requests"] / r["seconds"] if r["seconds"] else 0
            r["transport"] = "tcp (wrk)"
            return r
    raise Failure("wrk produced no summary:\n%s" % out.stdout.decode())


def fmt(r):
    return ("%s: %d requests in %.1f s = %.0f req/s, p50 %.0f us, p99 %.0f us, errors %d" %
            (r["transport"], r["requests"], r["seconds"], r["req_per_s"], r["p50_us"], r["p99_us"],
             r.get("errors", 0) + r.get("non2xx", 0)))


def overload(d):
    """Floods the job queue with long sleep jobs until 429; every answer must come quickly."""
    ids = []
    got429 = None
    worst = 0.0
    for i in range(2000):
        t0 = time.time()
        r = d.request("POST", "/v1/jobs", {"kind": "sleep", "seconds": 60}, timeout=5)
        worst = max(worst, time.time() - t0)
        if r.status == 202:
            ids.append(r.json()["id"])
            continue
        expect(r.status == 429, "job flood: answer %d %r" % (r.status, r.body[:200]))
        got429 = r
        break
    expect(got429 is not None, "2000 long jobs accepted without 429: no queue bound?")
    ra = got429.headers.get("retry-after")
    expect(ra is not None and ra.isdigit() and int(ra) > 0, "429 without a valid Retry-After: %r" % ra)
    expect(got429.json()["error"]["code"], "429 without an error code")
    # More submissions keep being refused promptly, and evaluate still works meanwhile.
    for _ in range(20):
        t0 = time.time()
        r = d.request("POST", "/v1/jobs", {"kind": "sleep", "seconds": 60}, timeout=5)
        worst = max(worst, time.time() - t0)
        expect(r.status == 429, "past the bound: %d" % r.status)
    expect(H.check_valid_evaluate(d) is None, "evaluate failed while the queue was full")
    for jid in ids:
        d.request("DELETE", "/v1/jobs/%s" % jid)
    print("overload: %d jobs accepted, then 429 with Retry-After: %s s; slowest answer %.0f ms"
          % (len(ids), ra, worst * 1000))


def idle_and_slow(d, limit, check_slow=True):
    """An idle connection and a slow one (a byte every second) must be closed by the daemon."""
    t0 = time.time()
    idle = d.open_conn("unix", timeout=limit)
    slow = d.open_conn("unix", timeout=limit)
    req = b"GET /v1/health HTTP/1.1\r\nHost: localhost\r\n"
    closed = {}
    slow_i = 0
    idle.setblocking(False)
    slow.setblocking(False)
    # Wait for the connections checked here; the slow one may close first (both expire after
    # the first-line timeout), so a count of closed connections would stop the wait too early.
    want = ("idle", "slow") if check_slow else ("idle",)
    while time.time() - t0 < limit and not all(name in closed for name in want):
        for name, s in (("idle", idle), ("slow", slow)):
            if name in closed:
                continue
            try:
                data = s.recv(4096)
                if data == b"":
                    closed[name] = time.time() - t0
            except BlockingIOError:
                pass
            except OSError:
                closed[name] = time.time() - t0
        if "slow" not in closed and slow_i < len(req):
            try:
                slow.send(req[slow_i:slow_i + 1])
                slow_i += 1
            except OSError:
                closed["slow"] = time.time() - t0
        time.sleep(1.0)
    idle.close()
    slow.close()
    expect("idle" in closed, "an idle connection was still open after %d s" % limit)
    print("idle connection closed after %.0f s" % closed["idle"])
    if check_slow:
        expect("slow" in closed, "a slow connection (1 byte/s, slowloris) was still open after %d s"
               % limit)
        print("slow connection (1 byte/s) closed after %.0f s" % closed["slow"])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--aalabd", required=True)
    ap.add_argument("--load", required=True)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--full", action="store_true")
    ap.add_argument("--slowloris", action="store_true",
                    help="only the idle and 1-byte-per-second connections (ctest load_slowloris)")
    ap.add_argument("--requests", type=int, default=1000000)
    ap.add_argument("--connections", type=int, default=2)
    ap.add_argument("--wrk-seconds", type=int, default=30)
    ap.add_argument("--timeout-limit", type=int, default=15,
                    help="seconds within which idle/slow connections must be closed")
    ap.add_argument("--daemon-arg", action="append", default=[],
                    help="extra aalabd flag (repeatable), e.g. --daemon-arg=--connection-timeout=5")
    a = ap.parse_args()
    extra = list(a.daemon_arg)
    if a.quick or a.slowloris:
        # A small queue bound (and a per-user quota above it, so that the bound is what refuses)
        # and a short inactivity timeout keep the smoke test short.
        extra += ["--queue-size", "16", "--user-quota", "1000", "--connection-timeout", "3"]
    d = H.Daemon(a.aalabd, workers=2, extra_args=extra).start()
    try:
        if a.slowloris:
            idle_and_slow(d, a.timeout_limit, check_slow=True)
            d.stop()
            return 0
        # Warm-up, so that RSS "before" includes the steady-state allocations.
        run_load(a.load, d, "unix", ["--connections", "2", "--requests", "20000", "--body", EVAL_BODY])
        time.sleep(0.3)
        rss0 = d.rss_kb()
        if a.full:
            r = run_load(a.load, d, "unix", ["--connections", str(a.connections), "--requests",
                                              str(a.requests), "--body", EVAL_BODY])
            time.sleep(0.5)
            rss1 = d.rss_kb()
            print(fmt(r))
            growth = (rss1 - rss0) / rss0 * 100
            print("RSS before %d kB, after %d requests %d kB (%+.2f %%)" % (rss0, r["requests"], rss1, growth))
            expect(r["exit"] == 0 and r["errors"] == 0, "load errors: %r" % r)
            w = run_wrk(d, a.wrk_seconds)
            if w:
                print(fmt(w))
                expect(w["errors"] == 0 and w["non2xx"] == 0, "wrk errors: %r" % w)
            rss2 = d.rss_kb()
            print("RSS after wrk: %d kB" % rss2)
            expect(growth < 5.0, "RSS grew %.2f %% over %d requests" % (growth, r["requests"]))
        else:
            r = run_load(a.load, d, "unix", ["--connections", "2", "--seconds", "3", "--body", EVAL_BODY])
            print(fmt(r))
            expect(r["exit"] == 0 and r["errors"] == 0 and r["requests"] > 0, "load errors: %r" % r)
            w = run_wrk(d, 3)
            if w:
                print(fmt(w))
                expect(w["errors"] == 0 and w["non2xx"] == 0 and w["requests"] > 0, "wrk errors: %r" % w)
            print("RSS before %d kB, after %d kB" % (rss0, d.rss_kb()))
            overload(d)
            idle_and_slow(d, a.timeout_limit, check_slow=False)
        expect(d.alive(), "aalabd died")
        rc = d.stop()
        expect(rc == 0, "aalabd exit status %r" % rc)
        expect(not d.sanitizer_reports(), "sanitizer report:\n%s" % d.log_text())
    except Failure as e:
        print("FAIL: %s" % e)
        if d.alive():
            d.stop()
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
