"""The job store on a shared daemon, with real Unix users:

1. alice's flood of 1.9 MB specs ends refused with 403 quota_exceeded while jobs.db stays
   within her quota plus a stated overhead, and bob can still submit;
2. a spec above --max-spec-bytes is refused with 413 before parsing;
3. purge (DELETE ?purge=1) by the owner works, by bob of alice's job is 403, by root works;
   a running job is 409; PATCH pinned by the owner works, by bob is 403;
4. retention: with a tiny --keep-days a pinned job survives the sweep, an unpinned one goes;
5. GET /v1/jobs with 10,000 stored jobs: p50/p99 over the Unix socket (< 50 ms p99), and a
   job lookup while another user loops on the listing;
6. the progress write rate of 2 running jobs with a 1.9 MB pattern (bytes/s written by the
   daemon); AALAB_BASELINE_AALABD=path also measures that binary for comparison.

argv[1] = aalabd. Needs root and useradd (else exit 77)."""

import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.dirname(HERE))
from aalabd_harness import built_with_asan  # noqa: E402
from unix_users import LabUsers, percentile  # noqa: E402

MIB = 1 << 20
QUOTA = 16 * MIB  # room for 2-3 of the ~1.9 MB flood specs (each reserves ~4 MB)
# jobs.db beyond the stored bytes: page slack of the overflow chains, indexes, the schema.
DB_OVERHEAD = 2 * MIB
FAILURES = []

# Children run as the user in question and build big bodies themselves (argv is limited to
# 128 KiB per argument): raw HTTP/1.1 over the Unix socket.
CHILD = r"""
import json, socket, sys, time
sock, action, arg = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])

def req(method, path, body=None):
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    s.settimeout(120)
    s.connect(sock)
    head = "%s %s HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n" % (method, path)
    if body is not None:
        head += "Content-Type: application/json\r\nContent-Length: %d\r\n" % len(body)
    s.sendall(head.encode() + b"\r\n" + (body or b""))
    raw = b""
    while True:
        c = s.recv(1 << 20)
        if not c:
            break
        raw += c
    s.close()
    h, _, b = raw.partition(b"\r\n\r\n")
    return int(h.split(b" ")[1]), b

if action == "flood":
    body = open(arg["file"], "rb").read()
    out = {"accepted": [], "statuses": [], "last": None}
    for i in range(arg["attempts"]):
        st, b = req("POST", "/v1/jobs", body)
        out["statuses"].append(st)
        if st == 202:
            out["accepted"].append(json.loads(b)["id"])
        elif st == 429:
            time.sleep(0.3)
        else:
            out["last"] = json.loads(b)
            if st == 403:
                break
    print(json.dumps(out))
elif action == "timing":
    lat = []
    for i in range(arg["n"]):
        t = time.perf_counter()
        st, b = req("GET", arg["path"])
        lat.append(time.perf_counter() - t)
        assert st == 200, (st, b[:200])
    print(json.dumps({"latencies": lat, "bytes": len(b)}))
elif action == "loop":
    t_end = time.time() + arg["seconds"]
    n = 0
    while time.time() < t_end:
        req("GET", arg["path"])
        n += 1
    print(json.dumps({"requests": n}))
"""


def check(cond, what):
    print("%s: %s" % ("ok" if cond else "FAIL", what))
    if not cond:
        FAILURES.append(what)


def run_child(user, d, action, arg, timeout=600):
    p = user.spawn(CHILD, [d.socket_path, action, json.dumps(arg)])
    out, err = p.communicate(timeout=timeout)
    if p.returncode != 0:
        raise RuntimeError("%s child as %s failed: %s" % (action, user.name, err[-2000:]))
    return json.loads(out)


def big_pattern_spec(seconds):
    """A sleep spec of about 1.9 MB: 16 kernels of 4096 samples with weights 1/4096 (exact in
    binary, so the daemon's re-encoded best and result have the same size)."""
    coords = [-0.375, -0.125, 0.125, 0.375]
    w = 1.0 / 4096
    kernels = [[[coords[(k + i) % 4], coords[(i // 4) % 4], w] for i in range(4096)]
               for k in range(16)]
    return json.dumps({"kind": "sleep", "seconds": seconds, "pattern": {"kernels": kernels}},
                      separators=(",", ":")).encode()


def write_file(users, name, data):
    path = os.path.join(users.root, name)
    with open(path, "wb") as f:
        f.write(data)
    os.chmod(path, 0o644)
    return path


def db_size(d, with_wal=True):
    total = 0
    for suffix in ("", "-wal") if with_wal else ("",):
        try:
            total += os.path.getsize(os.path.join(d.state_dir, "jobs.db" + suffix))
        except OSError:
            pass
    return total


def wait_state(d, job_id, states, timeout=120):
    """Polls the list (cheap), not the job (megabytes when its pattern is big)."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        r = d.request("GET", "/v1/jobs?limit=500", timeout=30)
        for j in r.json()["jobs"] if r.status == 200 else []:
            if j["id"] == job_id and j["state"] in states:
                return j
        time.sleep(0.1)
    raise RuntimeError("job %d did not reach %s" % (job_id, states))


def part_quota_and_purge(users, binary):
    d = users.start_daemon(binary, extra_args=["--user-store-bytes", str(QUOTA),
                                               "--queue-size", "64"])
    body = big_pattern_spec(0)
    print("# flood spec: %d bytes; quota %d bytes" % (len(body), QUOTA))
    check(1_800_000 <= len(body) <= 2 * MIB, "the flood spec is about 1.9 MB (%d)" % len(body))
    spec_file = write_file(users, "flood.json", body)
    res = run_child(users.alice, d, "flood", {"file": spec_file, "attempts": 60})
    last = res["last"] or {}
    print("# alice: %d accepted, statuses %s" % (len(res["accepted"]), res["statuses"]))
    print("# refusal: %s" % json.dumps(last)[:400])
    check(res["statuses"][-1] == 403 and last.get("error", {}).get("code") == "quota_exceeded",
          "the flood ends refused with 403 quota_exceeded")
    check(str(QUOTA) in last.get("error", {}).get("message", ""),
          "the refusal names the limit")
    for job_id in res["accepted"]:
        wait_state(d, job_id, ("done", "failed"))
    usage = users.alice.request(d, "GET", "/v1/usage").json()
    size = db_size(d, with_wal=False)
    size_wal = db_size(d)
    print("# alice usage %d of %d bytes; jobs.db %d bytes, with WAL %d bytes"
          % (usage["store_bytes"], usage["store_limit"], size, size_wal))
    check(usage["store_limit"] == QUOTA and 0 < usage["store_bytes"] <= QUOTA,
          "GET /v1/usage: alice within her quota")
    check(size <= QUOTA + DB_OVERHEAD,
          "jobs.db (%d) <= quota + %d bytes of overhead" % (size, DB_OVERHEAD))
    # From alice's list, as alice: each job is ~10 MB in full (spec, best and result), seconds
    # apiece under the sanitizers.
    listed = {j["id"]: j["state"]
              for j in users.alice.request(d, "GET", "/v1/jobs?limit=500").json()["jobs"]}
    # The first two finish done. A later one may fail when its output (best and result, each
    # about twice the spec as re-encoded) would take alice over her quota (job_store_write.c's
    # over_quota; the third of three, at 16 MiB): why is printed, not checked.
    check(len(res["accepted"]) >= 2, "at least two flood jobs accepted under the quota")
    states = [listed.get(i) for i in res["accepted"][:2]]
    for i in res["accepted"]:
        if listed.get(i) != "done":  # only then its megabytes are fetched
            print("# job %d %s: %s" % (i, listed.get(i), json.dumps(
                users.alice.request(d, "GET", "/v1/jobs/%d" % i, timeout=120).json().get("error"))))
    check(all(s == "done" for s in states), "accepted flood jobs finished done: %s" % states)
    r = users.bob.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 0})
    check(r.status == 202, "bob can still submit (%d)" % r.status)
    bob_job = r.json()["id"]

    # 413 above --max-spec-bytes (default 2 MiB), before parsing: not even JSON.
    r = d.request("POST", "/v1/jobs", b"x" * (2 * MIB + 1))
    check(r.status == 413 and r.json()["error"]["field"] == "",
          "a spec above --max-spec-bytes is 413 (%d)" % r.status)

    # Envelope keys.
    r = users.alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 0,
                                                    "visibility": "secret"})
    check(r.status == 400 and r.json()["error"]["field"] == "visibility",
          "visibility must be team or private")
    r = users.alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 0,
                                                    "priority": 11})
    check(r.status == 400 and r.json()["error"]["field"] == "priority", "priority -10..10")

    # Purge: bob cannot, alice can; root can purge anyone's.
    a1 = res["accepted"][0]
    before = users.alice.request(d, "GET", "/v1/usage").json()["store_bytes"]
    r = users.bob.request(d, "DELETE", "/v1/jobs/%d?purge=1" % a1)
    check(r.status == 403, "bob purging alice's job is 403 (%d)" % r.status)
    r = users.bob.request(d, "PATCH", "/v1/jobs/%d" % a1, {"pinned": True})
    check(r.status == 403, "bob pinning alice's job is 403 (%d)" % r.status)
    r = users.alice.request(d, "PATCH", "/v1/jobs/%d" % a1, {"pinned": True})
    check(r.status == 200 and r.json()["pinned"] is True, "alice pins her job")
    r = users.alice.request(d, "DELETE", "/v1/jobs/%d?purge=1" % a1)
    check(r.status == 200, "alice purges her job (%d)" % r.status)
    check(users.alice.request(d, "GET", "/v1/jobs/%d" % a1).status == 404, "purged: 404")
    after = users.alice.request(d, "GET", "/v1/usage").json()["store_bytes"]
    print("# alice usage %d -> %d bytes after one purge" % (before, after))
    check(after < before - 5 * MIB, "a purge gives the bytes back")
    r = d.request("DELETE", "/v1/jobs/%d?purge=1" % res["accepted"][1])
    check(r.status == 200, "root purges alice's job (%d)" % r.status)
    wait_state(d, bob_job, ("done",))
    r = d.request("DELETE", "/v1/jobs/%d?purge=1" % bob_job)
    check(r.status == 200, "root purges bob's job (%d)" % r.status)
    r = users.alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 30})
    check(r.status == 202, "alice submits again after purging (%d)" % r.status)
    running = r.json()["id"]
    wait_state(d, running, ("running",))
    r = users.alice.request(d, "DELETE", "/v1/jobs/%d?purge=1" % running)
    check(r.status == 409, "purging a running job is 409 (%d)" % r.status)
    users.alice.request(d, "DELETE", "/v1/jobs/%d" % running)
    wait_state(d, running, ("cancelled",))
    r = users.alice.request(d, "DELETE", "/v1/jobs/%d?purge=1" % running)
    check(r.status == 200, "purged once cancelled (%d)" % r.status)
    d.stop()
    size = db_size(d)
    print("# jobs.db after stop (checkpointed): %d bytes" % size)
    check(size <= QUOTA + DB_OVERHEAD, "jobs.db after stop <= quota + overhead")


def part_retention(users, binary):
    keep_days = 0.0001  # 8.64 s, the smallest --keep-days; the sweep runs every 2.16 s
    d = users.start_daemon(binary, extra_args=["--keep-days", str(keep_days)])
    pinned = users.alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 0,
                                                         "pinned": True}).json()["id"]
    plain = users.alice.request(d, "POST", "/v1/jobs", {"kind": "sleep",
                                                        "seconds": 0}).json()["id"]
    patched = users.alice.request(d, "POST", "/v1/jobs", {"kind": "sleep",
                                                          "seconds": 0}).json()["id"]
    for i in (pinned, plain, patched):
        wait_state(d, i, ("done",))
    r = users.alice.request(d, "PATCH", "/v1/jobs/%d" % patched, {"pinned": True})
    check(r.status == 200, "PATCH pinned (%d)" % r.status)
    t0 = time.time()
    while time.time() - t0 < 30 and d.request("GET", "/v1/jobs/%d" % plain).status == 200:
        time.sleep(0.25)
    gone = time.time() - t0
    print("# the unpinned job was deleted %.1f s after it finished (keep %.2f s)"
          % (gone, keep_days * 86400))
    check(d.request("GET", "/v1/jobs/%d" % plain).status == 404, "unpinned old job deleted")
    check(d.request("GET", "/v1/jobs/%d" % pinned).status == 200, "pinned job survives")
    check(d.request("GET", "/v1/jobs/%d" % patched).status == 200, "PATCH-pinned job survives")
    d.stop()


PREFILL = r"""
import json, random, sqlite3, sys, time
db = sqlite3.connect(sys.argv[1])
t0 = time.time() - 7200  # recent: retention (90 days) keeps them
uids = json.loads(sys.argv[2])
n = int(sys.argv[3])
rng = random.Random(1)
rows = []
for i in range(n):
    pat = {"family": "P(1,1,8)", "cost_spp": 8.0, "form": "kernels",
           "kernels": [[[rng.uniform(-.5, .5), rng.uniform(-.5, .5), 0.125] for _ in range(8)]]}
    e2 = rng.uniform(0.2, 0.7)
    best = json.dumps({"pattern": pat, "e2": e2})
    spec = json.dumps({"kind": "optimize", "family": "P(1,1,8)", "seeds": 4})
    if i % 1000 == 0:  # a few very large rows: the list must not read them
        best = json.dumps({"pattern": pat, "e2": e2, "pad": "x" * 1000000})
    uid = uids[i % len(uids)]
    vis = "private" if i % 50 == 0 else "team"
    rows.append(("optimize", uid, "done", 1.0, spec, best, "[]", best, t0 + i * 0.1, t0 + i * 0.1,
                 t0 + i * 0.1 + 0.05, e2, "P(1,1,8)", vis, len(spec) + 2 * len(best) + 2))
db.executemany("INSERT INTO jobs(kind, owner_uid, state, progress, spec, best, trace, result, "
               "created, started, finished, best_e2, family, visibility, bytes) "
               "VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)", rows)
db.commit()
db.close()
"""


def part_list_and_write_rate(users, binary):
    d = users.start_daemon(binary)
    d.stop()
    db = os.path.join(d.state_dir, "jobs.db")
    uids = [users.alice.uid, users.bob.uid, users.eve.uid]
    p = users.daemon.run(["/usr/bin/python3", "-c", PREFILL, db, json.dumps(uids), "10000"],
                         timeout=600)
    check(p.returncode == 0, "pre-filled 10,000 jobs (%s)" % p.stderr[-300:])
    print("# jobs.db with 10,000 jobs: %d bytes" % db_size(d))
    d.start()
    sanitized = built_with_asan(binary) or "tsan" in binary.lower() or \
        os.environ.get("AALAB_SANITIZED") == "1"
    bound = 0.5 if sanitized else 0.050
    # Up to three measurements while over the bound, as e2e_users_net does: other ctest jobs
    # share the 2 cores, and one busy second decides a p99 of 200 requests.
    for attempt in range(3):
        res = run_child(users.alice, d, "timing", {"path": "/v1/jobs", "n": 200})
        lat = res["latencies"]
        p50, p99 = percentile(lat, 50), percentile(lat, 99)
        print("# GET /v1/jobs (500 of 10,000 jobs, %d bytes): p50 %.1f ms, p99 %.1f ms"
              " (measurement %d)" % (res["bytes"], p50 * 1e3, p99 * 1e3, attempt + 1))
        if p99 < bound:
            break
    check(p99 < bound, "GET /v1/jobs p99 %.1f ms < %.0f ms" % (p99 * 1e3, bound * 1e3))
    res = run_child(users.alice, d, "timing", {"path": "/v1/jobs?limit=20&state=done", "n": 100})
    print("# GET /v1/jobs?limit=20&state=done: p50 %.1f ms, p99 %.1f ms"
          % (percentile(res["latencies"], 50) * 1e3, percentile(res["latencies"], 99) * 1e3))
    # One user looping on the list does not hold up another user's lookup.
    loop = users.bob.spawn(CHILD, [d.socket_path, "loop",
                                   json.dumps({"path": "/v1/jobs", "seconds": 6})])
    time.sleep(0.5)
    res = run_child(users.alice, d, "timing", {"path": "/v1/jobs/5000", "n": 100})
    out, _ = loop.communicate(timeout=60)
    lp99 = percentile(res["latencies"], 99)
    print("# GET /v1/jobs/5000 while bob loops on the list (%s): p50 %.1f ms, p99 %.1f ms"
          % (out.strip(), percentile(res["latencies"], 50) * 1e3, lp99 * 1e3))
    check(lp99 < 10 * bound, "lookup p99 during a listing loop %.1f ms" % (lp99 * 1e3))
    d.stop()
    write_rate(users, binary, "this build")
    base = os.environ.get("AALAB_BASELINE_AALABD")
    if base:
        write_rate(users, base, "baseline " + base, check_bound=False)


def io_bytes(pid):
    with open("/proc/%d/io" % pid) as f:
        v = dict(line.split(": ") for line in f.read().splitlines())
    return int(v["wchar"]), int(v["write_bytes"])


def write_rate(users, binary, label, check_bound=True):
    """Bytes written by the daemon per second while 2 sleep jobs with a 1.9 MB pattern run."""
    d = users.start_daemon(binary, workers=2)
    body = big_pattern_spec(40)
    ids = [d.request("POST", "/v1/jobs", body, timeout=60).json()["id"] for _ in range(2)]
    for i in ids:
        wait_state(d, i, ("running",))
    time.sleep(1)
    w0, b0 = io_bytes(d.proc.pid)
    t0 = time.time()
    time.sleep(10)  # two of the 5 s progress periods of each job
    w1, b1 = io_bytes(d.proc.pid)
    dt = time.time() - t0
    for i in ids:
        d.request("DELETE", "/v1/jobs/%d" % i)
    rate, disk = (w1 - w0) / dt, (b1 - b0) / dt
    print("# progress write rate, %s: %.0f bytes/s written (wchar), %.0f bytes/s to disk "
          "(write_bytes), 2 running jobs with a %d-byte pattern spec"
          % (label, rate, disk, len(body)))
    if check_bound:
        # One best (~2 MB) per job per 5 s, through the WAL and its checkpoint: ~4 MB/s at most.
        check(rate < 4 * MIB, "progress writes %.0f bytes/s < 4 MiB/s" % rate)
    d.stop()


def main():
    binary = os.path.abspath(sys.argv[1])
    with LabUsers() as users:
        part_quota_and_purge(users, binary)
        part_retention(users, binary)
        part_list_and_write_rate(users, binary)
        for d in users.daemons:
            reports = d.sanitizer_reports()
            check(not reports, "no sanitizer reports in %s" % d.log_path)
    if FAILURES:
        print("%d failure(s)" % len(FAILURES))
        return 1
    print("all passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
