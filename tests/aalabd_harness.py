"""Shared test harness for the hardening tests: start aalabd on a temporary Unix socket and state
directory, and speak HTTP/1.1 to it over the Unix socket or TCP loopback with raw sockets (so that
malformed, oversized and half-sent requests can be expressed). Standard library only."""

import atexit
import json
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time

# Called as RESPONSE_HOOK(method, path, status, headers, body) with every answer of
# Daemon.request; the e2e tests set it to validate answers against their JSON Schemas.
RESPONSE_HOOK = None

SANITIZER_MARKERS = ("ERROR: AddressSanitizer", "ERROR: LeakSanitizer", "runtime error:",
                     "WARNING: ThreadSanitizer", "SUMMARY: UndefinedBehaviorSanitizer")


class Response:
    def __init__(self, status, headers, body):
        self.status = status
        self.headers = headers  # lower-case name -> value (last one wins)
        self.body = body

    def json(self):
        return json.loads(self.body.decode("utf-8"))

    def error_field(self):
        """The error object's field, None if absent; raises if the body is not an error."""
        err = self.json()["error"]
        return err.get("field")


def built_with_asan(binary):
    """True if the daemon was built with AddressSanitizer (its quarantine makes RSS meaningless
    as a leak measure; LeakSanitizer at exit is the check then): libasan linked dynamically
    (gcc) or the runtime linked in statically (clang)."""
    out = subprocess.run(["ldd", binary], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    if b"libasan" in out.stdout:
        return True
    with open(binary, "rb") as f:
        return b"AddressSanitizer" in f.read()


def free_tcp_port():
    s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def _decode_chunked(data):
    out = bytearray()
    while True:
        line, _, rest = data.partition(b"\r\n")
        size = int(line.split(b";")[0].strip() or b"0", 16)
        if size == 0:
            return bytes(out)
        out += rest[:size]
        data = rest[size + 2:]


def parse_response(raw):
    head, sep, body = raw.partition(b"\r\n\r\n")
    if not sep:
        raise ValueError("incomplete response (%d bytes)" % len(raw))
    lines = head.split(b"\r\n")
    parts = lines[0].split(b" ", 2)
    status = int(parts[1])
    headers = {}
    for line in lines[1:]:
        k, _, v = line.partition(b":")
        headers[k.strip().lower().decode("latin-1")] = v.strip().decode("latin-1")
    if headers.get("transfer-encoding", "").lower() == "chunked":
        body = _decode_chunked(body)
    elif "content-length" in headers:
        body = body[:int(headers["content-length"])]
    return Response(status, headers, body)


class Daemon:
    """aalabd on a temp socket/state dir (and a TCP loopback port and a web dir)."""

    def __init__(self, binary, workers=2, tcp=True, web_dir=None, state_dir=None, extra_args=(),
                 root=None):
        self.binary = binary
        if root is None:
            root = tempfile.mkdtemp(prefix="aalab-test-")
            # Removed when the test script ends (AALAB_KEEP_TEST_DIRS=1 keeps it for debugging).
            if not os.environ.get("AALAB_KEEP_TEST_DIRS"):
                atexit.register(shutil.rmtree, root, True)
        self.root = root
        self.socket_path = os.path.join(self.root, "aalabd.sock")
        self.state_dir = state_dir or os.path.join(self.root, "state")
        os.makedirs(self.state_dir, exist_ok=True)
        self.web_dir = web_dir
        self.port = free_tcp_port() if tcp else None
        self.workers = workers
        self.extra_args = list(extra_args)
        self.proc = None
        self.log_path = os.path.join(self.root, "aalabd.log")
        self.log = None
        self.token = None

    def args(self):
        a = [self.binary, "--socket", self.socket_path, "--state-dir", self.state_dir,
             "--workers", str(self.workers), "--enable-test-kinds"]
        if self.port:
            a += ["--tcp", "127.0.0.1:%d" % self.port]
        if self.web_dir:
            a += ["--web-dir", self.web_dir]
        return a + self.extra_args

    def start(self, timeout=20.0):
        env = dict(os.environ)
        env.pop("LISTEN_FDS", None)
        env.pop("NOTIFY_SOCKET", None)
        return self.start_with(timeout, env=env)

    def start_with(self, timeout, **popen_kw):
        """Starts the daemon with these Popen arguments (env, user, ...) and waits until it
        answers GET /v1/health; then issues the harness's token."""
        self.log = open(self.log_path, "ab")
        self.proc = subprocess.Popen(self.args(), stdout=self.log, stderr=subprocess.STDOUT,
                                     **popen_kw)
        deadline = time.time() + timeout
        while time.time() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError("aalabd exited with %s during start-up:\n%s" %
                                   (self.proc.returncode, self.log_text()))
            if os.path.exists(self.socket_path):
                try:
                    r = self.request("GET", "/v1/health", timeout=2)
                    if r.status == 200:
                        self.token = self.issue_token()
                        return self
                except OSError:
                    pass
            time.sleep(0.05)
        raise RuntimeError("aalabd did not become healthy in %.0f s:\n%s" % (timeout, self.log_text()))

    def issue_token(self, label="harness"):
        """A bearer token for TCP requests, issued to this process over the Unix socket
        (POST /v1/tokens); None if the daemon does not issue tokens."""
        r = self.request("POST", "/v1/tokens", {"label": label}, timeout=5)
        return r.json()["token"] if r.status == 201 else None

    def alive(self):
        return self.proc is not None and self.proc.poll() is None

    def pid(self):
        return self.proc.pid

    def kill9(self):
        self.proc.send_signal(signal.SIGKILL)
        self.proc.wait(10)
        self.log.close()

    def stop(self, timeout=20.0):
        """SIGTERM and wait; returns the exit status (or raises on hang)."""
        if self.proc is None or self.proc.poll() is not None:
            return None if self.proc is None else self.proc.returncode
        self.proc.send_signal(signal.SIGTERM)
        try:
            rc = self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait(5)
            raise RuntimeError("aalabd did not exit within %.0f s of SIGTERM" % timeout)
        finally:
            self.log.close()
        return rc

    def log_text(self):
        try:
            with open(self.log_path, "rb") as f:
                return f.read().decode("utf-8", "replace")[-20000:]
        except OSError:
            return ""

    def sanitizer_reports(self):
        t = self.log_text()
        return [m for m in SANITIZER_MARKERS if m in t]

    def rss_kb(self):
        with open("/proc/%d/status" % self.proc.pid) as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
        return -1

    def open_conn(self, via="unix", timeout=10.0):
        if via == "tcp":
            s = socket.create_connection(("127.0.0.1", self.port), timeout=timeout)
        else:
            s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            s.settimeout(timeout)
            s.connect(self.socket_path)
        return s

    def request(self, method, path, body=None, headers=None, via="unix", timeout=10.0,
                chunked=False):
        """One request on a fresh connection (Connection: close); returns a Response."""
        if isinstance(body, str):
            body = body.encode("utf-8")
        if isinstance(body, (dict, list)):
            body = json.dumps(body).encode("utf-8")
        h = {"Host": "localhost" if via == "unix" else "127.0.0.1:%d" % self.port}
        if body is not None and "Content-Type" not in (headers or {}) and headers is None:
            h["Content-Type"] = "application/json"
        h.update(headers or {})
        h["Connection"] = "close"
        if body is not None:
            if chunked:
                h["Transfer-Encoding"] = "chunked"
            else:
                h["Content-Length"] = str(len(body))
        head = "%s %s HTTP/1.1\r\n" % (method, path)
        head += "".join("%s: %s\r\n" % kv for kv in h.items()) + "\r\n"
        payload = head.encode("latin-1")
        if body is not None:
            if chunked:
                parts = [b"%x\r\n%s\r\n" % (len(body[i:i + 65536]), body[i:i + 65536])
                         for i in range(0, len(body), 65536)]
                payload += b"".join(parts) + b"0\r\n\r\n"
            else:
                payload += body
        resp = self.send_raw(payload, via=via, timeout=timeout)
        if RESPONSE_HOOK:
            RESPONSE_HOOK(method, path, resp.status, resp.headers, resp.body)
        return resp

    def send_raw(self, payload, via="unix", timeout=10.0):
        s = self.open_conn(via, timeout)
        try:
            try:
                s.sendall(payload)
            except (BrokenPipeError, ConnectionResetError):
                pass  # the server may answer (413) and close before reading everything
            return parse_response(recv_all(s, timeout))
        finally:
            s.close()


def recv_all(s, timeout):
    deadline = time.time() + timeout
    chunks = []
    while True:
        s.settimeout(max(0.01, deadline - time.time()))
        try:
            c = s.recv(65536)
        except socket.timeout:
            raise TimeoutError("no complete response within %.0f s" % timeout)
        except ConnectionResetError:
            break
        if not c:
            break
        chunks.append(c)
    return b"".join(chunks)


VALID_EVALUATE = {"pattern": {"preset": "rgss"}}
RGSS_E2 = 0.439  # Laine & Aila Table 2 (3 digits)


def check_valid_evaluate(d):
    """A valid evaluate must still succeed; returns an error string or None."""
    try:
        r = d.request("POST", "/v1/evaluate", VALID_EVALUATE)
    except Exception as e:  # noqa: BLE001 - any failure is a test failure
        return "valid evaluate failed: %r" % e
    if r.status != 200:
        return "valid evaluate answered %d: %r" % (r.status, r.body[:200])
    try:
        e2 = r.json()["e2"]
    except Exception as e:  # noqa: BLE001
        return "valid evaluate body unusable: %r" % e
    if abs(e2 - RGSS_E2) > 1e-3:
        return "valid evaluate gave e2=%r, expected %.3f" % (e2, RGSS_E2)
    return None
