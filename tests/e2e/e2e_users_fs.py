#!/usr/bin/env python3
"""The daemon's directories and files against another user, with real Unix users
(tests/e2e/unix_users.py); issue 35, points 3 and 4:

- bob plants a symlink jobs.db in a state directory he can write: a root daemon refuses to start,
  naming the directory, and the victim file's mode is unchanged; a symlink jobs.db left in a
  directory that is now root's 0700 is refused by name too;
- a tokens.db of bob's (his rows, his hash) in a directory he can write (sticky, as /tmp), or
  left in a trusted directory, is refused: his token would otherwise act as alice;
- a socket directory writable by others, or owned by bob, is refused and no socket appears;
- an existing jobs.db of ours with mode 0644 is narrowed to 0600, with a message;
- in the systemd layout (state directory 0750 of the daemon's account, UMask 0027, the daemon's
  group the team's), a private render's tile files are 0600 in a 0700 tiles directory and bob
  cannot read alice's tile from the state directory.

Usage: e2e_users_fs.py AALABD   (needs root and useradd; exit 77 = skipped)"""

import glob
import grp
import os
import sqlite3
import stat
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from unix_users import CHILD_PYTHON, LabUsers, _UserDaemon  # noqa: E402

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


def mode(path):
    return stat.S_IMODE(os.lstat(path).st_mode)


def run_root_daemon(binary, state, sock, wait=6.0):
    """aalabd as root on state and sock; (exit code or None if it kept running, its output)."""
    p = subprocess.Popen([binary, "--state-dir", state, "--socket", sock, "--workers", "1"],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    try:
        out = p.communicate(timeout=wait)[0]
        return p.returncode, out.decode("utf-8", "replace")
    except subprocess.TimeoutExpired:
        p.terminate()
        out = p.communicate(timeout=20)[0]
        return None, out.decode("utf-8", "replace")


def fresh(users, name, owner_uid=0, owner_gid=0, dir_mode=0o700):
    path = tempfile.mkdtemp(prefix=name + "-", dir=users.root)
    os.chown(path, owner_uid, owner_gid)
    os.chmod(path, dir_mode)
    return path


def victim_file(users):
    path = os.path.join(users.root, "victim-%d" % time.monotonic_ns())
    with open(path, "w") as f:
        f.write("root's secret\n")
    os.chmod(path, 0o640)
    return path


def planted_symlinks(users, binary):
    bob = users.bob
    run = fresh(users, "run", dir_mode=0o755)
    sock = os.path.join(run, "aalabd.sock")

    # A state directory bob can write (root's, 0777): he links jobs.db to a root file.
    victim = victim_file(users)
    state = fresh(users, "state-open", dir_mode=0o777)
    p = bob.run(["/bin/ln", "-s", victim, os.path.join(state, "jobs.db")])
    check(p.returncode == 0, "bob plants jobs.db -> %s in a directory he can write" % victim)
    rc, out = run_root_daemon(binary, state, sock)
    check(rc not in (0, None) and state in out and "0777" in out,
          "the root daemon refuses the state directory bob can write, naming it (exit %s: %s)"
          % (rc, out.strip()[-200:]))
    check(mode(victim) == 0o640, "the victim file keeps mode 0640 (now %04o)" % mode(victim))
    check(not os.path.exists(sock), "... and no socket was created")

    # The same link, left in a directory that is now root's 0700 (planted before it was fixed).
    victim = victim_file(users)
    state = fresh(users, "state-link")
    os.symlink(victim, os.path.join(state, "jobs.db"))
    rc, out = run_root_daemon(binary, state, sock)
    jobs_db = os.path.join(state, "jobs.db")
    check(rc not in (0, None) and jobs_db in out and "symlink" in out,
          "a symlink jobs.db is refused by name (exit %s: %s)" % (rc, out.strip()[-200:]))
    check(mode(victim) == 0o640, "the victim file keeps mode 0640 (now %04o)" % mode(victim))

    # A symlink tokens.db likewise.
    victim = victim_file(users)
    state = fresh(users, "state-toklink")
    os.symlink(victim, os.path.join(state, "tokens.db"))
    rc, out = run_root_daemon(binary, state, sock)
    check(rc not in (0, None) and os.path.join(state, "tokens.db") in out,
          "a symlink tokens.db is refused by name (exit %s: %s)" % (rc, out.strip()[-200:]))
    check(mode(victim) == 0o640, "the victim file keeps mode 0640 (now %04o)" % mode(victim))


BOB_TOKENS = r"""
import sqlite3, sys
db = sqlite3.connect(sys.argv[1])
db.execute("CREATE TABLE tokens(id INTEGER PRIMARY KEY AUTOINCREMENT, uid INTEGER NOT NULL,"
           " label TEXT NOT NULL DEFAULT '', created INTEGER NOT NULL, hash BLOB NOT NULL)")
db.execute("INSERT INTO tokens(uid, label, created, hash) VALUES (?, 'planted', 0, ?)",
           (int(sys.argv[2]), b"\x11" * 32))
db.commit()
"""


def planted_tokens(users, binary):
    bob, alice = users.bob, users.alice
    run = fresh(users, "run", dir_mode=0o755)
    sock = os.path.join(run, "aalabd.sock")
    # Sticky and world-writable, as /tmp: bob may add files, not remove root's.
    state = fresh(users, "state-sticky", dir_mode=0o1777)
    tokens = os.path.join(state, "tokens.db")
    p = bob.run([CHILD_PYTHON, "-c", BOB_TOKENS, tokens, str(alice.uid)])
    check(p.returncode == 0 and os.stat(tokens).st_uid == bob.uid,
          "bob plants a tokens.db with a row for alice's uid (%s)" % p.stderr.strip()[-200:])
    rc, out = run_root_daemon(binary, state, sock)
    check(rc not in (0, None) and state in out,
          "a state directory others can write (sticky 1777) is refused (exit %s: %s)"
          % (rc, out.strip()[-200:]))

    # Left behind in a directory that is root's 0700 now: refused as bob's file.
    state2 = fresh(users, "state-tokens")
    os.rename(tokens, os.path.join(state2, "tokens.db"))
    rc, out = run_root_daemon(binary, state2, sock)
    check(rc not in (0, None) and os.path.join(state2, "tokens.db") in out and
          ("uid %d" % bob.uid) in out,
          "a tokens.db owned by bob is refused, naming it and his uid (exit %s: %s)"
          % (rc, out.strip()[-200:]))
    rows = sqlite3.connect(os.path.join(state2, "tokens.db")).execute(
        "SELECT count(*) FROM tokens").fetchone()[0]
    check(rows == 1, "... and left as it was (%d row)" % rows)


def socket_dirs(users, binary):
    bob = users.bob
    state = fresh(users, "state")
    run = fresh(users, "run-open", dir_mode=0o777)
    sock = os.path.join(run, "aalabd.sock")
    rc, out = run_root_daemon(binary, state, sock)
    check(rc not in (0, None) and run in out and "socket directory" in out,
          "a socket directory others can write is refused, naming it (exit %s: %s)"
          % (rc, out.strip()[-200:]))
    check(not os.path.exists(sock), "... and no socket appears in it")

    run = fresh(users, "run-bob", bob.uid, bob.gid, 0o755)
    sock = os.path.join(run, "aalabd.sock")
    rc, out = run_root_daemon(binary, state, sock)
    check(rc not in (0, None) and run in out and ("uid %d" % bob.uid) in out,
          "a socket directory owned by bob is refused (exit %s: %s)" % (rc, out.strip()[-200:]))
    check(not os.path.exists(sock), "... and no socket appears in it")

    # Below a directory bob owns, even a directory of root's 0755 could be swapped by him.
    above = fresh(users, "above-bob", bob.uid, bob.gid, 0o755)
    run = os.path.join(above, "run")
    os.mkdir(run, 0o755)
    sock = os.path.join(run, "aalabd.sock")
    rc, out = run_root_daemon(binary, state, sock)
    check(rc not in (0, None) and above in out,
          "a socket directory below one of bob's is refused, naming it (exit %s: %s)"
          % (rc, out.strip()[-200:]))


def db_mode_fixed(users, binary):
    state = fresh(users, "state-wide")
    run = fresh(users, "run", dir_mode=0o755)
    sock = os.path.join(run, "aalabd.sock")
    jobs_db = os.path.join(state, "jobs.db")
    sqlite3.connect(jobs_db).close()
    os.chmod(jobs_db, 0o644)
    rc, out = run_root_daemon(binary, state, sock, wait=3.0)
    check(rc is None, "a jobs.db of ours with mode 0644 is used (exit %s: %s)"
          % (rc, out.strip()[-300:]))
    check(mode(jobs_db) == 0o600 and "0644" in out and "0600" in out,
          "... narrowed to 0600 with a message (mode %04o)" % mode(jobs_db))


def systemd_tiles(users, binary):
    """The unit's layout: StateDirectoryMode=0750, UMask=0027, the daemon's group the team's."""
    alice, bob = users.alice, users.bob
    team = grp.getgrnam(users.group).gr_gid
    base = fresh(users, "sysd", dir_mode=0o755)
    state = os.path.join(base, "state")
    run = os.path.join(base, "run")
    os.mkdir(state)
    os.mkdir(run)
    for d, m in ((state, 0o750), (run, 0o755)):
        os.chown(d, users.daemon.uid, team)
        os.chmod(d, m)
    d = _UserDaemon(binary, users.daemon, workers=1, tcp=False, state_dir=state,
                    extra_args=["--socket-group", users.group], root=base)
    d.socket_path = os.path.join(run, "aalabd.sock")
    env = {"PATH": "/usr/bin:/bin", "LANG": "C.UTF-8"}
    for k in ("ASAN_OPTIONS", "UBSAN_OPTIONS", "TSAN_OPTIONS", "LSAN_OPTIONS"):
        if k in os.environ:
            env[k] = os.environ[k]
    d.start_with(30, env=env, user=users.daemon.uid, group=team, extra_groups=[],
                 cwd="/", umask=0o027)
    users.daemons.append(d)
    pattern = {"kernels": [[[-0.25, -0.25, 0.25], [0.25, -0.25, 0.25], [-0.25, 0.25, 0.25],
                            [0.25, 0.25, 0.25]]]}
    r = alice.request(d, "POST", "/v1/render", {"pattern": pattern, "size": [16, 16],
                                                "visibility": "private"})
    check(r.status == 200, "alice renders privately (%d %s)" % (r.status, r.body[:200]))
    tiles = os.path.join(state, "tiles")
    files = sorted(glob.glob(os.path.join(tiles, "*")))
    check(len(files) >= 2, "the render wrote tile files (%d)" % len(files))
    wide = ["%s %04o" % (os.path.basename(f), mode(f)) for f in files if mode(f) != 0o600]
    check(not wide, "every tile file is 0600 under UMask 0027 (%s)" % (wide or "all 0600"))
    check(mode(tiles) == 0o700, "the tiles directory is 0700 (%04o)" % mode(tiles))
    png = [f for f in files if f.endswith(".png")]
    if png:
        p = bob.run([CHILD_PYTHON, "-c", "import sys; open(sys.argv[1], 'rb').read()", png[0]])
        check(p.returncode != 0 and "Permission denied" in p.stderr,
              "bob (in the daemon's group) cannot read alice's tile from the state directory")
    check(d.stop() == 0, "the daemon stops cleanly")

    # A tiles directory and a tile of an older daemon (0750, 0640) are narrowed at the next start.
    os.chmod(tiles, 0o750)
    for f in files:
        os.chmod(f, 0o640)
    d.start_with(30, env=env, user=users.daemon.uid, group=team, extra_groups=[],
                 cwd="/", umask=0o027)
    check(mode(tiles) == 0o700, "an existing 0750 tiles directory is narrowed to 0700")
    wide = [os.path.basename(f) for f in png if mode(f) != 0o600]
    check(not wide, "existing 0640 tiles are narrowed to 0600 (%s)" % (wide or "all 0600"))
    check(d.stop() == 0, "the daemon stops cleanly again")


def main():
    binary = os.path.abspath(sys.argv[1])
    with LabUsers() as users:
        planted_symlinks(users, binary)
        planted_tokens(users, binary)
        socket_dirs(users, binary)
        db_mode_fixed(users, binary)
        systemd_tiles(users, binary)
    print("%d checks, %d failed" % (checks, len(failures)))
    for f in failures:
        print("  FAILED: %s" % f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
