"""End-to-end: persistence across restarts (SIGTERM and kill -9), re-queueing of unfinished jobs,
SQLite integrity, queue bound and per-user quota (429 + Retry-After), one daemon per socket."""

import os
import signal
import sqlite3
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from e2e_lib import Daemon, check, expect_error  # noqa: E402


def submit(d, seconds, **extra):
    body = {"kind": "sleep", "seconds": seconds}
    body.update(extra)
    r = d.post("/v1/jobs", body)
    check(r.status == 202, r)
    return r.json()["id"]


def integrity_ok(state):
    db = sqlite3.connect(os.path.join(state, "jobs.db"))
    try:
        return db.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
    finally:
        db.close()


def test_restart(binary):
    d = Daemon(binary, tcp=False, extra=["--workers", "1"]).start()
    try:
        done = submit(d, 0.1, pattern={"preset": "quincunx"})
        before = d.wait_job(done)
        check(before["state"] == "done", before)
        running = submit(d, 60)
        d.wait_job(running, states=("running",))
        queued = submit(d, 0.2)

        # a second daemon on the same socket refuses to start and touches nothing
        p = subprocess.run([binary, "--socket", d.sock, "--state-dir", d.state + "2"],
                           capture_output=True, timeout=20)
        check(p.returncode != 0 and b"another daemon" in p.stderr, p)
        p = subprocess.run([binary, "--socket", d.sock + "2", "--state-dir", d.state],
                           capture_output=True, timeout=20)
        check(p.returncode != 0 and b"in use" in p.stderr, p)
        check(d.get("/v1/health").status == 200, "first daemon unaffected")

        # graceful stop: the running job is checkpointed as queued
        check(d.stop() == 0, "SIGTERM exit status")
        check(integrity_ok(d.state), "integrity after SIGTERM")
        d.start()
        after = d.get("/v1/jobs/%d" % done).json()
        for k in ("state", "result", "best", "trace", "finished", "spec"):
            check(after[k] == before[k], "finished job unchanged after restart: " + k)
        j = d.get("/v1/jobs/%d" % running).json()
        check(j["state"] in ("queued", "running") and "re-queued" in j.get("reason", ""), j)
        # the job queued behind it runs after the restart
        r = d.delete("/v1/jobs/%d" % running)
        check(r.status == 202, r)
        check(d.wait_job(running)["state"] == "cancelled", "cancel after restart")
        check(d.wait_job(queued)["state"] == "done", "queued job ran after restart")

        # kill -9 with one job running and some queued: nothing finished is lost
        running2 = submit(d, 60)
        d.wait_job(running2, states=("running",))
        waiting = [submit(d, 0.05) for _ in range(5)]
        d.stop(sig=signal.SIGKILL)
        check(integrity_ok(d.state), "integrity after kill -9")
        d.start()
        after = d.get("/v1/jobs/%d" % done).json()
        check(after["result"] == before["result"] and after["state"] == "done", after)
        j = d.get("/v1/jobs/%d" % running2).json()
        check(j["state"] in ("queued", "running") and "re-queued" in j.get("reason", ""), j)
        d.delete("/v1/jobs/%d" % running2)
        for w in waiting:
            check(d.wait_job(w)["state"] == "done", "queued job survived kill -9")
        # a job running at three abnormal exits is not re-queued a fourth time
        crashing = submit(d, 60)
        for attempt in range(3):
            d.wait_job(crashing, states=("running",))
            d.stop(sig=signal.SIGKILL)
            d.start()
        j = d.get("/v1/jobs/%d" % crashing).json()
        check(j["state"] == "interrupted" and "abnormally 3 times" in j.get("reason", ""), j)

        # health's counts by state may lag by up to 0.25 s (cached)
        deadline = time.time() + 5
        while True:
            h = d.get("/v1/health").json()
            if h["jobs"]["done"] >= 7 or time.time() > deadline:
                break
            time.sleep(0.05)
        check(h["jobs"]["done"] >= 7, h)
    except BaseException:
        print(d.log_text())
        raise
    finally:
        d.cleanup()


def test_limits(binary):
    d = Daemon(binary, tcp=False,
               extra=["--workers", "1", "--queue-size", "2", "--user-quota", "3"]).start()
    try:
        a = submit(d, 60)
        d.wait_job(a, states=("running",))
        b = submit(d, 60)
        c = submit(d, 60)
        r = d.post("/v1/jobs", {"kind": "sleep", "seconds": 60})
        e = expect_error(r, 429)
        check(e["code"] == "queue_full" and int(r.headers["retry-after"]) > 0, r.headers)
        d.delete("/v1/jobs/%d" % c)
        check(d.get("/v1/jobs/%d" % c).json()["state"] == "cancelled", "queued cancel at once")
        c = submit(d, 60)  # 3 active: quota reached
        d.delete("/v1/jobs/%d" % b)
        r = d.post("/v1/jobs", {"kind": "sleep", "seconds": 60})
        check(r.status == 202, r)  # b freed a slot
        r = d.post("/v1/jobs", {"kind": "sleep", "seconds": 60})
        e = expect_error(r, 429)
        check(e["code"] in ("too_many_requests", "queue_full") and "retry-after" in r.headers, r)
        for j in d.get("/v1/jobs").json()["jobs"]:
            if j["state"] in ("queued", "running"):
                d.delete("/v1/jobs/%d" % j["id"])
        # evaluate stays available while the pool is busy
        check(d.post("/v1/evaluate", {"pattern": {"preset": "rgss"}}).status == 200, "evaluate")
    except BaseException:
        print(d.log_text())
        raise
    finally:
        d.cleanup()


def main():
    binary = sys.argv[1]
    test_restart(binary)
    test_limits(binary)
    print("e2e_restart: ok")


if __name__ == "__main__":
    main()
