#!/usr/bin/env python3
"""Access on a shared daemon, with real Unix users (tests/e2e/unix_users.py): a daemon account,
alice and bob in the socket group, eve outside it. Shows each access rule refused:

- over TCP every API request needs a token, reads included; eve (no socket access, so no token)
  reads nothing of the API but gets the dashboard page;
- tokens are per user, issued on the Unix socket only, revoked at once; a TCP caller is the
  token's uid without root's powers, even with a token issued to root;
- a private job is 404 to bob on both listeners (job, list, export, {"job": ID} references),
  readable by alice and by root on the socket; so is a private render's tile;
- bob cannot cancel alice's job on either listener;
- a token stops working when its owner leaves the socket group;
- a per-user daemon refuses a fallback directory /tmp/aalab-UID that is not its own or not 0700.

Usage: e2e_users_access.py AALABD   (needs root and useradd; exit 77 = skipped)"""

import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from unix_users import LabUsers  # noqa: E402

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


def status(r):
    return r.status


def eve_outside(users, d):
    # Eve cannot reach the socket at all (0660, group of the team; run dir 2750).
    try:
        r = users.eve.request(d, "GET", "/v1/health", timeout=5)
        check(r.status >= 400, "eve on the Unix socket is refused (%d)" % r.status)
    except OSError:
        check(True, "eve cannot connect to the Unix socket")
    for path in ("/v1/health", "/v1/jobs", "/v1/presets", "/v1/jobs/1", "/v1/patterns/1/export",
                 "/v1/tiles/0123456789abcdef0123456789abcdef.png", "/v1/tokens"):
        r = users.eve.request(d, "GET", path, via="tcp")
        check(r.status == 401, "eve over TCP without a token: GET %s -> 401 (%d)" % (path, r.status))
    r = users.eve.request(d, "POST", "/v1/tokens", {"label": "eve"}, via="tcp")
    check(r.status == 401, "eve cannot get a token over TCP (%d)" % r.status)
    r = users.eve.request(d, "GET", "/", via="tcp")
    check(r.status == 200 and b"<" in r.body, "eve over TCP gets the dashboard page (%d)" % r.status)


def wait_done(users, d, job_id, who):
    for _ in range(200):
        r = who.request(d, "GET", "/v1/jobs/%d" % job_id)
        if r.status == 200 and r.json()["state"] in ("done", "failed", "cancelled"):
            return r.json()
        time.sleep(0.1)
    raise AssertionError("job %d never finished" % job_id)


def jobs_and_tiles(users, d):
    alice, bob = users.alice, users.bob
    tok = {u.name: u.new_token(d, label="e2e") for u in (alice, bob)}
    ta, tb = tok[alice.name], tok[bob.name]
    root_tok = d.request("POST", "/v1/tokens", {"label": "root"}).json()["token"]

    r = alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 0, "visibility": "private",
                                              "pattern": {"preset": "quincunx"}})
    check(r.status == 202 and r.json().get("visibility") == "private", "alice submits a private job")
    priv = r.json()["id"]
    job = wait_done(users, d, priv, alice)
    check(job["owner_uid"] == alice.uid, "the job is owned by alice's uid")
    r = alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 0, "visibility": "world"})
    check(r.status == 400 and r.error_field() == "visibility", "visibility must be team or private")

    jp, ep = "/v1/jobs/%d" % priv, "/v1/patterns/%d/export" % priv
    for path in (jp, ep):
        check(status(bob.request(d, "GET", path)) == 404, "bob on the socket: %s -> 404" % path)
        check(status(bob.request(d, "GET", path, via="tcp", token=tb)) == 404,
              "bob over TCP: %s -> 404" % path)
        check(status(alice.request(d, "GET", path)) == 200, "alice on the socket: %s -> 200" % path)
        check(status(alice.request(d, "GET", path, via="tcp", token=ta)) == 200,
              "alice over TCP: %s -> 200" % path)
        check(status(d.request("GET", path)) == 200, "root on the socket: %s -> 200" % path)
        check(status(d.request("GET", path, via="tcp",
                               headers={"Authorization": "Bearer " + root_tok})) == 404,
              "root's token over TCP is not root: %s -> 404" % path)
    ids = [j["id"] for j in bob.request(d, "GET", "/v1/jobs").json()["jobs"]]
    check(priv not in ids, "bob's job list leaves the private job out")
    ids = [j["id"] for j in alice.request(d, "GET", "/v1/jobs", via="tcp", token=ta).json()["jobs"]]
    check(priv in ids, "alice's job list (TCP) has it")

    ref = {"pattern": {"job": priv}}
    r = bob.request(d, "POST", "/v1/evaluate", ref)
    check(r.status == 400 and r.error_field() == "pattern.job",
          "bob's {\"job\": ID} reference to it in evaluate: 400 pattern.job (%d)" % r.status)
    r = bob.request(d, "POST", "/v1/jobs", dict(ref, kind="sleep", seconds=0), via="tcp", token=tb)
    check(r.status == 400 and r.error_field() == "pattern.job", "... and in a job spec (TCP)")
    r = bob.request(d, "POST", "/v1/render", dict(ref, size=[16, 16]))
    check(r.status == 400 and r.error_field() == "pattern.job", "... and in a render")
    r = alice.request(d, "POST", "/v1/evaluate", ref, via="tcp", token=ta)
    check(r.status == 200, "alice's own reference evaluates (%d)" % r.status)

    # A private render: its tiles are alice's (and root's).
    r = alice.request(d, "POST", "/v1/render", {"pattern": {"job": priv}, "size": [16, 16],
                                                "visibility": "private"})
    check(r.status == 200, "alice renders privately (%d)" % r.status)
    url = r.json()["tiles"]["difference"]["url"]
    check(status(bob.request(d, "GET", url)) == 404, "bob on the socket: private tile -> 404")
    check(status(bob.request(d, "GET", url, via="tcp", token=tb)) == 404,
          "bob over TCP: private tile -> 404")
    check(status(users.eve.request(d, "GET", url, via="tcp")) == 401, "eve: private tile -> 401")
    r = alice.request(d, "GET", url, via="tcp", token=ta)
    check(r.status == 200 and r.body[:4] == b"\x89PNG", "alice over TCP gets her tile")
    check(status(d.request("GET", url)) == 200, "root on the socket gets it")
    r = bob.request(d, "POST", "/v1/render", {"pattern": {"preset": "rgss"}, "size": [16, 16]})
    team_url = r.json()["tiles"]["pattern"]["url"]
    check(status(alice.request(d, "GET", team_url, via="tcp", token=ta)) == 200,
          "a team render's tile is the team's")

    # Cancelling: only the owner (or root on the socket).
    r = alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 60})
    team_job = r.json()["id"]
    r = alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 60,
                                              "visibility": "private"})
    priv_job = r.json()["id"]
    tj, pj = "/v1/jobs/%d" % team_job, "/v1/jobs/%d" % priv_job
    check(status(bob.request(d, "GET", tj)) == 200, "bob reads alice's team job")
    check(status(bob.request(d, "DELETE", tj)) == 403, "bob cannot cancel it on the socket (403)")
    check(status(bob.request(d, "DELETE", tj, via="tcp", token=tb)) == 403,
          "bob cannot cancel it over TCP (403)")
    check(status(d.request("DELETE", tj, via="tcp",
                           headers={"Authorization": "Bearer " + root_tok})) == 403,
          "root's token over TCP cannot cancel it either (403)")
    check(status(bob.request(d, "DELETE", pj)) == 404, "alice's private job: bob's cancel -> 404")
    check(status(alice.request(d, "DELETE", tj, via="tcp", token=ta)) == 202,
          "alice cancels her job over TCP")
    check(status(d.request("DELETE", pj)) == 202, "root on the socket cancels the private one")

    # Tokens: issued on the socket only, listed without secrets, revoked at once.
    r = bob.request(d, "POST", "/v1/tokens", {}, via="tcp", token=tb)
    check(r.status == 403, "no token issued over TCP, even to a token holder (%d)" % r.status)
    mine = alice.request(d, "GET", "/v1/tokens").json()["tokens"]
    check(all(t["uid"] == alice.uid and "token" not in t for t in mine) and mine,
          "alice lists her own tokens, without secrets")
    everyone = d.request("GET", "/v1/tokens").json()["tokens"]
    check({alice.uid, bob.uid, 0} <= {t["uid"] for t in everyone}, "root lists everyone's")
    tid = mine[0]["id"]
    check(status(bob.request(d, "DELETE", "/v1/tokens/%d" % tid)) == 403,
          "bob cannot revoke alice's token")
    check(status(alice.request(d, "GET", "/v1/health", via="tcp", token=ta)) == 200,
          "alice's token works before the revocation")
    check(status(alice.request(d, "DELETE", "/v1/tokens/%d" % tid)) == 200, "alice revokes it")
    check(status(alice.request(d, "GET", "/v1/health", via="tcp", token=ta)) == 401,
          "the revoked token is refused at once")

    # A token counts only while its owner is in the socket group.
    check(status(bob.request(d, "GET", "/v1/health", via="tcp", token=tb)) == 200,
          "bob's token works while he is in the group")
    subprocess.run(["gpasswd", "-d", bob.name, users.group], check=True, capture_output=True)
    time.sleep(2.5)  # the daemon caches membership for 2 s
    check(status(bob.request(d, "GET", "/v1/jobs", via="tcp", token=tb)) == 401,
          "bob removed from the socket group: his token is refused (401)")
    subprocess.run(["gpasswd", "-a", bob.name, users.group], check=True, capture_output=True)


def fallback_dir(users, binary):
    """A per-user aalabd (no XDG_RUNTIME_DIR, no --socket) must own /tmp/aalab-UID, mode 0700."""
    alice, bob = users.alice, users.bob
    fallback = "/tmp/aalab-%d" % alice.uid
    state = os.path.join(users.root, "alice-state")
    os.makedirs(state)
    os.chown(state, alice.uid, alice.gid)
    os.chmod(state, 0o700)
    argv = [binary, "--state-dir", state, "--workers", "1"]

    def run_alice(timeout=10):
        return alice.run(argv, timeout=timeout)

    try:
        shutil.rmtree(fallback, True)
        # Bob got there first: he would own alice's socket and receive her requests.
        os.mkdir(fallback)
        os.chown(fallback, bob.uid, bob.gid)
        os.chmod(fallback, 0o777)
        p = run_alice()
        check(p.returncode != 0 and "belongs to uid %d" % bob.uid in p.stderr,
              "alice's daemon refuses /tmp/aalab-UID owned by bob (exit %d: %s)"
              % (p.returncode, p.stderr.strip()[:160]))
        check(not os.path.exists(os.path.join(fallback, "aalabd.sock")), "... and plants no socket")
        # Her own directory, but open to others.
        os.chown(fallback, alice.uid, alice.gid)
        os.chmod(fallback, 0o755)
        p = run_alice()
        check(p.returncode != 0 and "0755" in p.stderr and "0700" in p.stderr,
              "alice's daemon refuses her /tmp/aalab-UID with mode 0755 (%s)" % p.stderr.strip()[:160])
        # Missing: created 0700 and used.
        shutil.rmtree(fallback, True)
        kw = alice._popen_kw()
        proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, **kw)
        sock = os.path.join(fallback, "aalabd.sock")
        for _ in range(200):
            if os.path.exists(sock) or proc.poll() is not None:
                break
            time.sleep(0.05)
        st = os.lstat(fallback) if os.path.exists(fallback) else None
        check(st is not None and st.st_uid == alice.uid and (st.st_mode & 0o7777) == 0o700,
              "a missing /tmp/aalab-UID is created 0700 and owned by alice")
        check(os.path.exists(sock), "... and the daemon listens there")
        proc.terminate()
        out = proc.communicate(timeout=20)[0].decode("utf-8", "replace")
        check(proc.returncode == 0, "... and stops cleanly (%s)" % out.strip()[-200:])
    finally:
        shutil.rmtree(fallback, True)


def main():
    binary = os.path.abspath(sys.argv[1])
    src = os.path.dirname(os.path.dirname(HERE))
    with LabUsers() as users:
        web = os.path.join(users.root, "web")
        shutil.copytree(os.path.join(src, "web"), web)
        for base, dirs, files in os.walk(web):
            for n in dirs + files:
                os.chmod(os.path.join(base, n), 0o755 if n in dirs else 0o644)
        d = users.start_daemon(binary, extra_args=["--web-dir", web])
        eve_outside(users, d)
        jobs_and_tiles(users, d)
        check(d.stop() == 0, "the daemon stops cleanly on SIGTERM")
        reports = d.sanitizer_reports()  # after exit: LeakSanitizer reports then
        check(not reports, "no sanitizer reports in the daemon log %s" % reports)
        fallback_dir(users, binary)
    print("%d checks, %d failed" % (checks, len(failures)))
    for f in failures:
        print("  FAILED: %s" % f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
