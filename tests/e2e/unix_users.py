"""Real Unix users for the sharing tests: a daemon account, a socket group with two members
(alice, bob) and one local user outside it (eve), created with useradd as root and removed at
exit. The daemon runs as the daemon account; requests are made by child processes that run as
the user in question, so SO_PEERCRED, file modes and loopback peer lookups see real, distinct
uids. Standard library only.

    with LabUsers() as users:
        d = users.start_daemon(aalabd, extra_args=["--job-slice", "2"])
        r = users.alice.request(d, "POST", "/v1/jobs", {"kind": "sleep", "seconds": 1})
        tok = users.alice.new_token(d)           # over the Unix socket
        users.eve.request(d, "GET", "/v1/jobs", via="tcp")   # 401: no token

Skips the calling test (exit 77) when not root or without useradd."""

import base64
import grp
import json
import os
import pwd
import secrets
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import aalabd_harness  # noqa: E402
import response_check  # noqa: E402
from aalabd_harness import Daemon, parse_response  # noqa: E402

# Every answer the multi-user tests get is checked against its schema, also through the harness.
aalabd_harness.RESPONSE_HOOK = response_check.check

SKIP = 77
# Children run as other users, who cannot read a Python installed under /root (pyenv): the
# system interpreter, which every account can run.
CHILD_PYTHON = "/usr/bin/python3" if os.access("/usr/bin/python3", os.X_OK) else sys.executable

# The child that makes one request as the user: raw HTTP/1.1 over the Unix socket or TCP.
_REQUEST_CHILD = r"""
import base64, json, socket, sys
a = json.loads(sys.argv[1])
if a["via"] == "tcp":
    s = socket.create_connection(("127.0.0.1", a["port"]), timeout=a["timeout"])
else:
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    s.settimeout(a["timeout"])
    s.connect(a["socket"])
body = base64.b64decode(a["body"]) if a["body"] is not None else b""
head = "%s %s HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n" % (a["method"], a["path"])
for k, v in a["headers"].items():
    head += "%s: %s\r\n" % (k, v)
if a["body"] is not None:
    head += "Content-Type: application/json\r\nContent-Length: %d\r\n" % len(body)
s.sendall(head.encode() + b"\r\n" + body)
raw = b""
while True:
    try:
        chunk = s.recv(65536)
    except socket.timeout:
        break
    if not chunk:
        break
    raw += chunk
print(base64.b64encode(raw).decode())
"""


class User:
    def __init__(self, name, groups=()):
        self.name = name
        self.groups = list(groups)
        pw = pwd.getpwnam(name)
        self.uid = pw.pw_uid
        self.gid = pw.pw_gid
        self.home = pw.pw_dir

    def _popen_kw(self):
        extra = [grp.getgrnam(g).gr_gid for g in self.groups]
        env = {"PATH": "/usr/bin:/bin", "HOME": self.home, "USER": self.name, "LANG": "C.UTF-8"}
        return dict(user=self.uid, group=self.gid, extra_groups=extra, env=env, cwd="/")

    def run(self, argv, timeout=60, input=None, env=None):
        """Runs argv as this user; returns subprocess.CompletedProcess (text output)."""
        kw = self._popen_kw()
        if env:
            kw["env"] = dict(kw["env"], **env)
        return subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                              timeout=timeout, input=input, **kw)

    def spawn(self, code, args=(), env=None):
        """Starts `python3 -c code args...` as this user (for floods); returns the Popen."""
        kw = self._popen_kw()
        if env:
            kw["env"] = dict(kw["env"], **env)
        return subprocess.Popen([CHILD_PYTHON, "-c", code] + [str(a) for a in args],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)

    def request(self, daemon, method, path, body=None, token=None, via="unix", headers=None,
                timeout=30.0, raw_body=None):
        """One HTTP request made by a process of this user; returns a harness Response.
        Raises OSError if the connection was refused or reset before an answer."""
        hdrs = dict(headers or {})
        if token:
            hdrs["Authorization"] = "Bearer " + token
        data = raw_body if raw_body is not None else (
            json.dumps(body).encode() if body is not None else None)
        arg = {"via": via, "port": daemon.port, "socket": daemon.socket_path, "method": method,
               "path": path, "headers": hdrs, "timeout": timeout,
               "body": base64.b64encode(data).decode() if data is not None else None}
        p = self.run([CHILD_PYTHON, "-c", _REQUEST_CHILD, json.dumps(arg)], timeout=timeout + 10)
        if p.returncode != 0:
            raise OSError("request as %s failed: %s" % (self.name, p.stderr.strip()[-400:]))
        raw = base64.b64decode(p.stdout.strip() or "")
        if not raw:
            raise OSError("request as %s: connection closed without an answer" % self.name)
        resp = parse_response(raw)
        response_check.check(method, path, resp.status, resp.headers, resp.body)
        return resp

    def new_token(self, daemon, label="test"):
        """A bearer token issued to this user over the Unix socket (POST /v1/tokens)."""
        r = self.request(daemon, "POST", "/v1/tokens", {"label": label})
        if r.status not in (200, 201):
            raise RuntimeError("token for %s: %d %s" % (self.name, r.status, r.body[:300]))
        return r.json()["token"]


def _run(argv):
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)


class LabUsers:
    """Creates aalabt<suffix>{d,a,b,e} and the group aalabt<suffix>g; removes them at exit."""

    def __init__(self, prefix="aalabt"):
        if os.geteuid() != 0 or not shutil.which("useradd"):
            print("SKIP: the multi-user tests need root and useradd")
            sys.exit(SKIP)
        self.prefix = "%s%s" % (prefix, secrets.token_hex(2))
        self.group = self.prefix + "g"
        self.names = {"daemon": self.prefix + "d", "alice": self.prefix + "a",
                      "bob": self.prefix + "b", "eve": self.prefix + "e"}
        self.daemons = []
        self.root = None

    def __enter__(self):
        _run(["groupadd", self.group])
        created = []
        try:
            for role, name in self.names.items():
                groups = [self.group] if role in ("daemon", "alice", "bob") else []
                cmd = ["useradd", "--no-create-home", "--home-dir", "/nonexistent",
                       "--shell", "/usr/sbin/nologin", "--user-group"]
                if groups:
                    cmd += ["--groups", ",".join(groups)]
                _run(cmd + [name])
                created.append(name)
                setattr(self, role, User(name, groups))
        except Exception:
            self._remove(created)
            raise
        # A directory every user can traverse, owned by the daemon account below it.
        self.root = tempfile.mkdtemp(prefix="aalab-users-")
        os.chmod(self.root, 0o755)
        return self

    def start_daemon(self, binary, extra_args=(), tcp=True, workers=2, test_kinds=True,
                     timeout=30.0):
        """aalabd as the daemon account, socket group = the team group, in a fresh directory
        (socket dir 0750 root:team... the daemon's own; state 0700 daemon)."""
        base = tempfile.mkdtemp(prefix="d", dir=self.root)
        os.chmod(base, 0o755)
        run_dir = os.path.join(base, "run")
        state = os.path.join(base, "state")
        os.makedirs(run_dir)
        os.makedirs(state)
        os.chown(run_dir, self.daemon.uid, grp.getgrnam(self.group).gr_gid)
        os.chmod(run_dir, 0o2750)
        os.chown(state, self.daemon.uid, self.daemon.gid)
        os.chmod(state, 0o700)
        args = ["--socket-group", self.group] + list(extra_args)
        d = _UserDaemon(os.path.abspath(binary), self.daemon, workers=workers, tcp=tcp, state_dir=state,
                        extra_args=args, root=base, test_kinds=test_kinds)
        d.socket_path = os.path.join(run_dir, "aalabd.sock")
        d.start(timeout=timeout)
        self.daemons.append(d)
        return d

    def __exit__(self, *exc):
        problems = []
        for d in self.daemons:
            try:
                rc = d.stop()
                if rc not in (0, None):
                    problems.append("aalabd exited %s at SIGTERM" % rc)
            except Exception as e:  # keep removing the users
                problems.append("daemon stop: %s" % e)
            reports = d.sanitizer_reports()
            if reports:
                problems.append("sanitizer report in the daemon log (%s):\n%s" %
                                (", ".join(reports), d.log_text()[-6000:]))
        self._remove(list(self.names.values()))
        if self.root and not os.environ.get("AALAB_KEEP_TEST_DIRS"):
            shutil.rmtree(self.root, True)
        if problems and exc[0] is None:
            raise RuntimeError("; ".join(problems))
        return False

    def _remove(self, names):
        for n in names:
            subprocess.run(["pkill", "-KILL", "-u", n], stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
        time.sleep(0.05)
        for n in names:
            subprocess.run(["userdel", n], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        subprocess.run(["groupdel", self.group], stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)


class _UserDaemon(Daemon):
    """The harness Daemon, started as another account."""

    def __init__(self, binary, account, test_kinds=True, **kw):
        super().__init__(binary, **kw)
        self.account = account
        self.test_kinds = test_kinds

    def args(self):
        a = super().args()
        if not self.test_kinds:
            a = [x for x in a if x != "--enable-test-kinds"]
        return a

    def start(self, timeout=30.0):
        # The harness opens the log as root; the daemon writes it through the inherited fd.
        env = {"PATH": "/usr/bin:/bin", "LANG": "C.UTF-8"}
        for k in ("ASAN_OPTIONS", "UBSAN_OPTIONS", "TSAN_OPTIONS", "LSAN_OPTIONS"):
            if k in os.environ:
                env[k] = os.environ[k]
        return self.start_with(timeout, env=env, user=self.account.uid, group=self.account.gid,
                               extra_groups=[grp.getgrnam(g).gr_gid for g in self.account.groups],
                               cwd="/")


def percentile(values, p):
    """The p-th percentile (0..100) of values, nearest rank."""
    v = sorted(values)
    if not v:
        return float("nan")
    k = max(0, min(len(v) - 1, int(round(p / 100.0 * len(v) + 0.5)) - 1))
    return v[k]
