#!/usr/bin/env python3
"""Runs the bad-input catalogue (cases.jsonl, one case per line) end to end against a real aalabd
started on a temporary Unix socket, state directory, TCP loopback port and web directory.

For every case: send the request, check the status, that an error answer is
{"error":{"code","message","field"}} JSON with the expected field, optional extra checks; then
check that the daemon is still alive and that a valid evaluate still succeeds.

Case keys: name, method, path, headers, body (text) | body_json | body_hex | gen (generated body) |
raw (hand-built request: content_length lie, header_bytes, header_count, path_bytes), via
("unix" default, "tcp"), setup ("done_job", "cancelled_job", "pattern_job", "optimize_job": "{job}" in the path
is replaced by its id), status (int or list), field (string, null = absent or empty, list of
acceptable values, "*" = not checked, e.g. for answers libmicrohttpd produces itself),
check ({"e2_finite": true}, {"state": "done"}, {"content_type_prefix": ...}), forbid_body
(strings that must not appear in the answer).

Usage: run_bad_inputs.py --aalabd BUILD/server/aalabd [--cases cases.jsonl] [--only SUBSTR] [-v]
"""

import argparse
import json
import math
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import aalabd_harness as H  # noqa: E402


def gen_body(g):
    kind = g["kind"]
    if kind == "nest":
        d = g["depth"]
        return ('{"pattern":' + "[" * d + "]" * d + "}").encode()
    if kind == "kernels":
        # n samples per kernel on a 64-column grid inside [-0.5, 0.5)^2, weights 1/n (exact
        # when n is a power of two; otherwise the sum is within rounding of 1).
        n, k = g["samples"], g["kernels"]
        cols = 64
        rows = (n + cols - 1) // cols
        samples = ",".join("[%r,%r,%r]" % ((i % cols) / cols - 0.5, (i // cols) / rows - 0.5, 1.0 / n)
                           for i in range(n))
        ker = "[" + samples + "]"
        return ('{"pattern":{"kernels":[' + ",".join([ker] * k) + "]}}").encode()
    if kind == "mirrored":
        n = g["samples"]
        side = int(math.ceil(math.sqrt(n)))
        s = ",".join("[%r,%r,%r]" % ((i % side) / side - 0.49, (i // side) / side - 0.49, 1.0 / n)
                     for i in range(n))
        return ('{"pattern":{"mirrored":[' + s + "]}}").encode()
    if kind == "angles":
        n = g["angles"]
        a = ",".join("%.17g" % (180.0 * i / n) for i in range(n))
        return ('{"pattern":{"preset":"rgss"},"angles":[' + a + "]}").encode()
    if kind == "knots":
        n = g["knots"]
        k = ",".join("[%.17g,1]" % (179.0 * i / n) for i in range(n))
        return ('{"pattern":{"preset":"rgss"},"acuity":{"knots":[' + k + "]}}").encode()
    if kind == "spaces":
        return b'{"pattern":{"preset":"rgss"}' + b" " * g["bytes"] + b"}"
    if kind == "long_preset":
        return ('{"pattern":{"preset":"' + "a" * g["bytes"] + '"}}').encode()
    raise ValueError("unknown generator %r" % kind)


def case_body(c):
    if "body" in c:
        return c["body"].encode("utf-8")
    if "body_json" in c:
        return json.dumps(c["body_json"]).encode("utf-8")
    if "body_hex" in c:
        return bytes.fromhex(c["body_hex"])
    if "gen" in c:
        return gen_body(c["gen"])
    return None


def raw_request(d, c, via):
    r = c["raw"]
    host = "localhost" if via == "unix" else "127.0.0.1:%d" % d.port
    path = c["path"] + ("a" * r["path_bytes"] if "path_bytes" in r else "")
    head = "%s %s HTTP/1.1\r\nHost: %s\r\nConnection: close\r\n" % (c["method"], path, host)
    for k, v in c.get("headers", {}).items():
        head += "%s: %s\r\n" % (k, v)
    if "header_bytes" in r:
        head += "X-Big: %s\r\n" % ("a" * r["header_bytes"])
    for i in range(r.get("header_count", 0)):
        head += "X-H%d: v\r\n" % i
    body = b""
    if "content_length" in r:
        head += "Content-Length: %d\r\n" % r["content_length"]
        body = r.get("send", "").encode()
    payload = (head + "\r\n").encode("latin-1") + body
    # The lying Content-Length never completes: the server must answer without waiting for it.
    return d.send_raw(payload, via=via, timeout=15)


def wait_job(d, job_id, states, timeout=30):
    deadline = time.time() + timeout
    while time.time() < deadline:
        r = d.request("GET", "/v1/jobs/%s" % job_id)
        if r.status == 200 and r.json().get("state") in states:
            return r.json()
        time.sleep(0.05)
    raise RuntimeError("job %s did not reach %s" % (job_id, states))


def setup_job(d, what, cache):
    if what in cache:
        return cache[what]
    if what == "done_job":
        spec = {"kind": "sleep", "seconds": 0}
    elif what == "cancelled_job":
        spec = {"kind": "sleep", "seconds": 60}
    elif what == "pattern_job":  # a finished job with a best pattern
        spec = {"kind": "sleep", "seconds": 0, "pattern": {"preset": "rgss"}}
    elif what == "optimize_job":
        spec = {"kind": "optimize", "family": "P(4,1+,1.25)", "seeds": 1, "max_seconds": 1, "rng_seed": 1}
    else:
        raise ValueError(what)
    r = d.request("POST", "/v1/jobs", spec)
    if r.status != 202:
        raise RuntimeError("setup %s: POST /v1/jobs answered %d %r" % (what, r.status, r.body[:300]))
    jid = r.json()["id"]
    if what == "cancelled_job":
        r = d.request("DELETE", "/v1/jobs/%s" % jid)
        if r.status not in (200, 202, 204):
            raise RuntimeError("setup: cancel answered %d" % r.status)
        wait_job(d, jid, ("cancelled",))
    else:
        wait_job(d, jid, ("done",), timeout=60)
    cache[what] = jid
    return jid


def field_ok(expected, got):
    if expected == "*":
        return True
    if got == "":
        got = None
    exp = expected if isinstance(expected, list) else [expected]
    return got in exp


def run_case(d, c, cache):
    via = c.get("via", "unix")
    path = c["path"]
    if "setup" in c:
        path = path.replace("{job}", str(setup_job(d, c["setup"], cache)))
    if "raw" in c:
        resp = raw_request(d, c, via)
    else:
        body = case_body(c)
        headers = c.get("headers")
        chunked = bool(c.get("gen", {}).get("chunked"))
        resp = d.request(c["method"], path, body=body, headers=headers, via=via, timeout=30,
                         chunked=chunked)
    problems = []
    statuses = c["status"] if isinstance(c["status"], list) else [c["status"]]
    if resp.status not in statuses:
        problems.append("status %d, expected %s" % (resp.status, statuses))
    if resp.status >= 500:
        problems.append("server error")
    acao = resp.headers.get("access-control-allow-origin")
    if acao == "*":
        problems.append("wildcard CORS header")
    for f in c.get("forbid_body") or []:
        if f.encode() in resp.body:
            problems.append("answer contains %r" % f)
    if resp.status >= 400 and c["field"] != "*":
        ct = resp.headers.get("content-type", "")
        if not ct.startswith("application/json"):
            problems.append("error content-type %r" % ct)
        try:
            err = resp.json()["error"]
            if not isinstance(err.get("code"), str) or not err["code"]:
                problems.append("error.code missing")
            if not isinstance(err.get("message"), str) or not err["message"]:
                problems.append("error.message missing")
            if not field_ok(c["field"], err.get("field")):
                problems.append("field %r, expected %r" % (err.get("field"), c["field"]))
        except Exception as e:  # noqa: BLE001
            problems.append("error body not {\"error\":{...}} JSON: %r (%r)" % (e, resp.body[:200]))
    chk = c.get("check") or {}
    if resp.status < 300 and chk:
        try:
            j = resp.json() if "content_type_prefix" not in chk else None
            e2 = j.get("e2") if j else None
            if chk.get("e2_finite") and not (isinstance(e2, (int, float)) and math.isfinite(e2) and e2 >= 0):
                problems.append("e2 not a finite number >= 0: %r" % e2)
            if "state" in chk and j.get("state") != chk["state"]:
                problems.append("state %r, expected %r" % (j.get("state"), chk["state"]))
            if "content_type_prefix" in chk and not resp.headers.get("content-type", "").startswith(chk["content_type_prefix"]):
                problems.append("content-type %r" % resp.headers.get("content-type"))
        except Exception as e:  # noqa: BLE001
            problems.append("success body unusable: %r" % e)
    return resp, problems


def make_web_dir(root):
    web = os.path.join(root, "web")
    os.makedirs(web, exist_ok=True)
    with open(os.path.join(web, "index.html"), "w") as f:
        f.write("<!doctype html><title>aalab test</title>\n")
    with open(os.path.join(root, "secret.txt"), "w") as f:
        f.write("SECRET-MARKER outside the web dir\n")
    os.symlink(os.path.join(root, "secret.txt"), os.path.join(web, "escape.txt"))
    return web


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--aalabd", required=True)
    ap.add_argument("--cases", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "cases.jsonl"))
    ap.add_argument("--only", default=None)
    ap.add_argument("-v", "--verbose", action="store_true")
    a = ap.parse_args()
    with open(a.cases) as f:
        cases = [json.loads(line) for line in f if line.strip()]
    if a.only:
        cases = [c for c in cases if a.only in c["name"]]
    d = H.Daemon(a.aalabd)
    d.web_dir = make_web_dir(d.root)
    d.start()
    print("aalabd pid %d, socket %s, tcp %d, %d cases" % (d.pid(), d.socket_path, d.port, len(cases)))
    failed = []
    cache = {}
    t0 = time.time()
    for c in cases:
        try:
            resp, problems = run_case(d, c, cache)
            got = "%d %s" % (resp.status, resp.body[:160].decode("utf-8", "replace"))
        except Exception as e:  # noqa: BLE001
            problems, got = ["request failed: %r" % e], "-"
        if not d.alive():
            problems.append("aalabd died (exit %s)" % d.proc.returncode)
        else:
            after = H.check_valid_evaluate(d)
            if after:
                problems.append(after)
        if problems:
            failed.append(c["name"])
            print("FAIL %-40s %s\n     got: %s" % (c["name"], "; ".join(problems), got.replace("\n", " ")))
        elif a.verbose:
            print("ok   %-40s %s" % (c["name"], got.replace("\n", " ")[:120]))
        if not d.alive():
            print(d.log_text())
            break
    rc = d.stop() if d.alive() else d.proc.returncode
    san = d.sanitizer_reports()
    print("%d cases in %.1f s, %d failed; aalabd exit status %s"
          % (len(cases), time.time() - t0, len(failed), rc))
    if san:
        print("sanitizer reports in the daemon log: %s\n%s" % (san, d.log_text()))
    if rc != 0:
        print("aalabd did not exit cleanly on SIGTERM")
    if failed:
        print("failed: " + " ".join(failed))
    return 1 if failed or san or rc != 0 else 0


if __name__ == "__main__":
    sys.exit(main())
