"""Helpers for the end-to-end tests: start aalabd on a temporary socket and state directory and
talk to it with curl (over the Unix socket, or TCP loopback). Every answer is checked against its
JSON Schema (response_check.py)."""

import json
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time

import response_check


SANITIZER_MARKERS = ("ERROR: AddressSanitizer", "ERROR: LeakSanitizer", "runtime error:",
                     "WARNING: ThreadSanitizer")


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


class Reply:
    def __init__(self, status, headers, body):
        self.status = status
        self.headers = headers
        self.body = body

    def json(self):
        return json.loads(self.body)

    def __repr__(self):
        return "Reply(%d, %r)" % (self.status, self.body[:300])


class Daemon:
    def __init__(self, binary, root=None, tcp=True, web_dir=None, extra=()):
        self.binary = binary
        self.root = root or tempfile.mkdtemp(prefix="aalab-e2e-")
        self.sock = os.path.join(self.root, "run", "aalabd.sock")
        self.state = os.path.join(self.root, "state")
        self.port = free_port() if tcp else None
        self.web_dir = web_dir
        self.extra = list(extra)
        self.proc = None
        self.log_path = os.path.join(self.root, "aalabd.log")
        self.token = None
        self.check_responses = True

    def start(self):
        args = [self.binary, "--socket", self.sock, "--state-dir", self.state,
                "--enable-test-kinds"]
        if self.port:
            args += ["--tcp", "127.0.0.1:%d" % self.port]
        if self.web_dir:
            args += ["--web-dir", self.web_dir]
        args += self.extra
        env = dict(os.environ)
        for k in ("LISTEN_FDS", "LISTEN_PID", "NOTIFY_SOCKET"):
            env.pop(k, None)
        self.log = open(self.log_path, "ab")
        self.proc = subprocess.Popen(args, stdout=self.log, stderr=subprocess.STDOUT, env=env)
        deadline = time.time() + 20
        while time.time() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError("aalabd exited %d:\n%s" % (self.proc.returncode, self.log_text()))
            if os.path.exists(self.sock):
                try:
                    if self.get("/v1/health").status == 200:
                        # A token for TCP requests, issued to us over the Unix socket.
                        r = self.post("/v1/tokens", {"label": "e2e"})
                        if r.status != 201:
                            raise RuntimeError("POST /v1/tokens: %r" % r)
                        self.token = r.json()["token"]
                        return self
                except Exception:
                    pass
            time.sleep(0.05)
        raise RuntimeError("aalabd did not start:\n" + self.log_text())

    def log_text(self):
        with open(self.log_path, "rb") as f:
            return f.read().decode("utf-8", "replace")

    def stop(self, sig=signal.SIGTERM, timeout=30):
        if self.proc and self.proc.poll() is None:
            self.proc.send_signal(sig)
            self.proc.wait(timeout)
        if self.proc:
            self.log.close()
        rc = self.proc.returncode if self.proc else 0
        self.proc = None
        return rc

    def cleanup(self):
        self.stop()
        text = self.log_text() if os.path.exists(self.log_path) else ""
        shutil.rmtree(self.root, ignore_errors=True)
        for marker in SANITIZER_MARKERS:
            if marker in text:
                raise AssertionError("sanitizer report in the daemon log:\n" + text)

    def curl(self, method, path, body=None, headers=None, tcp=False, raw_body=None, ctype=True):
        args = ["curl", "-sS", "-X", method, "-D", "-", "--max-time", "60"]
        if tcp:
            url = "http://127.0.0.1:%d%s" % (self.port, path)
        else:
            args += ["--unix-socket", self.sock]
            url = "http://aalab" + path
        for k, v in (headers or {}).items():
            args += ["-H", "%s: %s" % (k, v)]
        data = raw_body if raw_body is not None else (json.dumps(body) if body is not None else None)
        if data is not None:
            if ctype:
                args += ["-H", "Content-Type: application/json"]
            args += ["--data-binary", "@-"]
        args += ["--path-as-is", url]
        p = subprocess.run(args, input=data.encode() if isinstance(data, str) else data,
                           capture_output=True, timeout=90)
        if p.returncode != 0:
            raise RuntimeError("curl failed (%d): %s" % (p.returncode, p.stderr.decode()))
        out = p.stdout
        # -D - prints every header block (e.g. 100 Continue); the last one is the answer.
        status, headers = 0, {}
        while out.startswith(b"HTTP/"):
            head, _, out = out.partition(b"\r\n\r\n")
            lines = head.split(b"\r\n")
            status = int(lines[0].split()[1])
            headers = {}
            for line in lines[1:]:
                k, _, v = line.partition(b":")
                headers[k.strip().lower().decode()] = v.strip().decode()
        if self.check_responses:
            response_check.check(method, path, status, headers, out)
        return Reply(status, headers, out.decode("utf-8", "replace"))

    def get(self, path, **kw):
        return self.curl("GET", path, **kw)

    def post(self, path, body=None, **kw):
        return self.curl("POST", path, body=body, **kw)

    def delete(self, path, **kw):
        return self.curl("DELETE", path, **kw)

    def wait_job(self, job_id, states=("done", "failed", "cancelled", "interrupted"), timeout=30):
        deadline = time.time() + timeout
        while time.time() < deadline:
            r = self.get("/v1/jobs/%d" % job_id)
            assert r.status == 200, r
            j = r.json()
            if j["state"] in states:
                return j
            time.sleep(0.05)
        raise AssertionError("job %d did not reach %s: %s" % (job_id, states, j))


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def expect_error(r, status, field=None):
    check(r.status == status, "expected %d, got %r" % (status, r))
    e = r.json()["error"]
    check(set(e) == {"code", "message", "field"}, "error object shape: %r" % e)
    if field is not None:
        check(e["field"] == field, "expected field %r, got %r" % (field, e["field"]))
    return e
