#!/usr/bin/env python3
"""A full disk under the job store, with real Unix users (tests/e2e/unix_users.py); issue 35,
point 8. The state directory is a 20 MB tmpfs of the daemon's account, filled by root:

- while it is full, PATCH {"pinned": true} of an existing job, a submission and a purge answer
  503 JSON (code unavailable), never 404 or 409 "running";
- a job that ends while the disk stays full is not left "running": after its final write's
  retries it shows failed with error code unavailable, cancel says it has finished;
- once space returns it is stored so (failed, unavailable) and purge removes it;
- a job whose final write first fails but succeeds within the retries (space back after 2 s)
  ends done.

Usage: e2e_users_diskfull.py AALABD   (needs root, useradd and mount -t tmpfs; exit 77 =
skipped, with the reason)"""

import errno
import grp
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from unix_users import LabUsers, _UserDaemon  # noqa: E402

checks = 0
failures = []


def check(cond, what):
    global checks
    checks += 1
    if cond:
        print("ok   %s" % what)
    else:
        failures.append(what)
        print("FAIL %s" % what)


def fill(path):
    """Writes path until the file system says ENOSPC; returns the bytes written."""
    n = 0
    with open(path, "wb", buffering=0) as f:
        for chunk in (1 << 20, 4096, 512, 1):
            block = b"\0" * chunk
            while True:
                try:
                    f.write(block)
                    n += chunk
                except OSError as e:
                    if e.errno != errno.ENOSPC:
                        raise
                    break
    return n


def job(users, d, jid):
    r = users.alice.request(d, "GET", "/v1/jobs/%d" % jid)
    return r.json() if r.status == 200 else {"status": r.status}


def wait_state(users, d, jid, pred, timeout):
    end = time.time() + timeout
    j = {}
    while time.time() < end:
        j = job(users, d, jid)
        if pred(j):
            return j
        time.sleep(0.2)
    return j


def error_code(r):
    try:
        return r.json()["error"]["code"]
    except Exception:
        return None


def scenario(users, d, state):
    alice = users.alice
    filler = os.path.join(state, "filler")

    r = alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 0})
    first = r.json()["id"]
    wait_state(users, d, first, lambda j: j.get("state") == "done", 20)
    r = alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 3})
    check(r.status == 202, "alice submits a 3 s job (%d)" % r.status)
    jid = r.json()["id"]
    wait_state(users, d, jid, lambda j: j.get("state") == "running", 10)

    written = fill(filler)
    print("filled the tmpfs with %d bytes" % written)
    r = alice.request(d, "PATCH", "/v1/jobs/%d" % first, {"pinned": True})
    check(r.status == 503 and error_code(r) == "unavailable",
          "PATCH pinned while the disk is full: 503 unavailable, not 404 (%d %s)"
          % (r.status, r.body[:160]))
    r = alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 0})
    check(r.status == 503 and error_code(r) == "unavailable",
          "a submission while the disk is full: 503 unavailable (%d)" % r.status)

    # 3 s of sleep plus the final write's retries (about 6 s).
    t0 = time.time()
    j = wait_state(users, d, jid, lambda j: j.get("state") not in ("queued", "running"), 25)
    check(j.get("state") == "failed" and (j.get("error") or {}).get("code") == "unavailable",
          "the job ending on a full disk shows failed / unavailable after %.1f s, not running "
          "(%s)" % (time.time() - t0, {k: j.get(k) for k in ("state", "error", "finished")}))
    r = alice.request(d, "DELETE", "/v1/jobs/%d" % jid)
    check(r.status == 409, "cancel: it has finished (%d %s)" % (r.status, r.body[:120]))
    r = alice.request(d, "DELETE", "/v1/jobs/%d?purge=1" % jid)
    check(r.status == 503 and error_code(r) == "unavailable",
          "purge while the disk is full: 503 unavailable, not 409 running (%d %s)"
          % (r.status, r.body[:160]))

    os.unlink(filler)
    time.sleep(2.5)  # the unavailable record is retried every second
    j = job(users, d, jid)
    check(j.get("state") == "failed" and (j.get("error") or {}).get("code") == "unavailable"
          and j.get("finished") is not None,
          "space back: stored failed / unavailable with its end time (%s)"
          % {k: j.get(k) for k in ("state", "error", "finished")})
    check("stored as failed (unavailable)" in d.log_text(), "the log says so")
    r = alice.request(d, "DELETE", "/v1/jobs/%d?purge=1" % jid)
    check(r.status == 200, "... and alice purges it (%d %s)" % (r.status, r.body[:120]))
    check(job(users, d, jid).get("status") == 404, "... and it is gone")
    r = alice.request(d, "PATCH", "/v1/jobs/%d" % first, {"pinned": True})
    check(r.status == 200 and r.json().get("pinned") is True, "PATCH pinned works again")

    # Full for 2 s only: the final write's retries store the real outcome.
    r = alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 1})
    jid = r.json()["id"]
    wait_state(users, d, jid, lambda j: j.get("state") == "running", 10)
    fill(filler)
    time.sleep(2.5)
    os.unlink(filler)
    j = wait_state(users, d, jid, lambda j: j.get("state") not in ("queued", "running"), 15)
    check(j.get("state") == "done", "a job whose final write succeeds on a retry ends done (%s)"
          % {k: j.get(k) for k in ("state", "error")})


def main():
    binary = os.path.abspath(sys.argv[1])
    with LabUsers() as users:
        team = grp.getgrnam(users.group).gr_gid
        base = tempfile.mkdtemp(prefix="df", dir=users.root)
        os.chmod(base, 0o755)
        state, run = os.path.join(base, "state"), os.path.join(base, "run")
        os.mkdir(state)
        os.mkdir(run)
        os.chown(run, users.daemon.uid, team)
        os.chmod(run, 0o2750)
        p = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=20m,mode=0700,uid=%d,gid=%d"
                            % (users.daemon.uid, users.daemon.gid), "tmpfs", state],
                           capture_output=True, text=True)
        if p.returncode != 0:
            print("SKIP: mount -t tmpfs is not allowed here: %s" % p.stderr.strip())
            sys.exit(77)
        try:
            d = _UserDaemon(binary, users.daemon, workers=2, tcp=False, state_dir=state,
                            extra_args=["--socket-group", users.group], root=base)
            d.socket_path = os.path.join(run, "aalabd.sock")
            d.start()
            users.daemons.append(d)
            scenario(users, d, state)
            check(d.stop() == 0, "the daemon stops cleanly")
        finally:
            filler = os.path.join(state, "filler")
            if os.path.exists(filler):
                os.unlink(filler)
            if subprocess.run(["umount", state]).returncode != 0:
                subprocess.run(["umount", "-l", state])
    print("%d checks, %d failed" % (checks, len(failures)))
    for f in failures:
        print("  FAILED: %s" % f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
