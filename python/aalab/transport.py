"""HTTP/1.1 over the daemon's Unix socket with the standard library only (``http.client``).

Socket discovery is the C client's (client/socket_path.c): an explicit path, else
``$AALAB_SOCKET``, else ``$XDG_RUNTIME_DIR/aalab/aalabd.sock`` if a socket is there (a per-user
daemon), else — without ``$XDG_RUNTIME_DIR`` — ``/tmp/aalab-UID/aalabd.sock`` if that directory
is the user's own (aalabd's fallback), else ``/run/aalab/aalabd.sock`` (the system daemon).

Each request opens its own connection (a Unix socket connect costs microseconds), so a
:class:`Transport` holds no connection state and may be shared between threads.
"""

from __future__ import annotations

import http.client
import json
import os
import socket
import stat
import time
from typing import Any, Dict, List, Mapping, Optional, Tuple
from urllib.parse import quote, urlencode

from .errors import AalabError, DaemonUnreachable

SYSTEM_SOCKET = "/run/aalab/aalabd.sock"
TMP_DIR = "/tmp"  # where aalabd puts /tmp/aalab-UID without $XDG_RUNTIME_DIR


def _is_socket(path: str) -> bool:
    try:
        return stat.S_ISSOCK(os.stat(path).st_mode)
    except OSError:
        return False


def resolve_socket(explicit: Optional[str] = None) -> Tuple[str, List[str]]:
    """The socket path to use and the candidates considered (for error messages), in the
    C client's order (module docstring)."""
    if explicit:
        return os.fspath(explicit), ["%s (socket=)" % explicit]
    env = os.environ.get("AALAB_SOCKET")
    if env:
        return env, ["%s ($AALAB_SOCKET)" % env]
    runtime = os.environ.get("XDG_RUNTIME_DIR")
    if runtime:
        path = os.path.join(runtime, "aalab", "aalabd.sock")
        if _is_socket(path):
            return path, [path]
        return SYSTEM_SOCKET, [path, SYSTEM_SOCKET]
    # aalabd's last resort without root and $XDG_RUNTIME_DIR; trusted only if the directory is
    # ours, so that another user cannot plant a socket there.
    uid = os.geteuid()
    d = os.path.join(TMP_DIR, "aalab-%d" % uid)
    path = os.path.join(d, "aalabd.sock")
    try:
        st = os.lstat(d)
        if stat.S_ISDIR(st.st_mode) and st.st_uid == uid and _is_socket(path):
            return path, [path]
    except OSError:
        pass
    return SYSTEM_SOCKET, [path, SYSTEM_SOCKET]


class _UnixConnection(http.client.HTTPConnection):
    def __init__(self, path: str, timeout: float) -> None:
        super().__init__("aalab", timeout=timeout)  # the host name is ignored on the socket
        self._path = path

    def connect(self) -> None:
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            s.settimeout(self.timeout)
            s.connect(self._path)
        except BaseException:
            s.close()
            raise
        self.sock = s


class Response:
    """A raw answer: status, headers (lower-case names) and body bytes."""

    def __init__(self, status: int, headers: Dict[str, str], body: bytes) -> None:
        self.status = status
        self.headers = headers
        self.body = body

    def json(self) -> Any:
        try:
            return json.loads(self.body.decode("utf-8"))
        except (UnicodeDecodeError, ValueError) as e:
            raise AalabError("protocol", "the daemon's answer is not JSON (%s): %.200r"
                             % (e, self.body), "", self.status) from None


def path_with_query(path: str, query: Optional[Mapping[str, Any]] = None) -> str:
    """``path`` with the non-None entries of ``query`` URL-encoded."""
    q = {k: v for k, v in (query or {}).items() if v is not None}
    return path + ("?" + urlencode(q) if q else "")


def quote_segment(s: Any) -> str:
    return quote(str(s), safe="")


class Transport:
    """Requests to one daemon socket.

    Args:
        socket_path: the socket, or None for the discovery of :func:`resolve_socket`.
        timeout: seconds to wait for the connection and for each read of an answer.
        retries: how often to retry an answer 429 or 503 that carries ``Retry-After``
            (per-user evaluate/render limits, a full queue), waiting as told (at most 10 s).
    """

    def __init__(self, socket_path: Optional[str] = None, timeout: float = 60.0,
                 retries: int = 3) -> None:
        self.socket_path, self._tried = resolve_socket(socket_path)
        if timeout is None or not timeout > 0:
            raise ValueError("timeout must be a positive number of seconds")
        self.timeout = float(timeout)
        self.retries = int(retries)

    def request(self, method: str, path: str, body: Any = None,
                timeout: Optional[float] = None) -> Response:
        """One request; retries 429/503 with Retry-After; raises :class:`DaemonUnreachable`
        when nothing answers, :class:`AalabError` (code ``timeout``) on a timeout."""
        payload = None
        headers = {"Accept": "application/json"}
        if body is not None:
            payload = json.dumps(body, allow_nan=False).encode("utf-8")
            headers["Content-Type"] = "application/json"
        attempt = 0
        while True:
            resp = self._once(method, path, payload, headers, timeout or self.timeout)
            retry_after = resp.headers.get("retry-after")
            if resp.status in (429, 503) and retry_after and attempt < self.retries:
                try:
                    wait = float(retry_after)
                except ValueError:
                    wait = 1.0
                if 0 <= wait <= 10:
                    attempt += 1
                    time.sleep(wait)
                    continue
            return resp

    def _once(self, method: str, path: str, payload: Optional[bytes], headers: Dict[str, str],
              timeout: float) -> Response:
        conn = _UnixConnection(self.socket_path, timeout)
        try:
            try:
                conn.request(method, path, body=payload, headers=headers)
            except (FileNotFoundError, ConnectionRefusedError, PermissionError) as e:
                raise DaemonUnreachable(
                    "unreachable",
                    "cannot connect to aalabd (%s); tried %s. Start a daemon (aalabd, or "
                    "systemctl start aalabd.socket for the shared one) or pass socket= / set "
                    "$AALAB_SOCKET" % (e.strerror or e, ", ".join(self._tried))) from None
            except OSError as e:
                if isinstance(e, socket.timeout):
                    raise AalabError("timeout", "no connection to %s within %.0f s"
                                     % (self.socket_path, timeout)) from None
                raise DaemonUnreachable("unreachable", "cannot talk to aalabd on %s: %s"
                                        % (self.socket_path, e)) from None
            try:
                r = conn.getresponse()
                body = r.read()
            except socket.timeout:
                raise AalabError("timeout", "%s %s: no answer within %.0f s (Client(timeout=...))"
                                 % (method, path.split("?")[0], timeout)) from None
            except (http.client.HTTPException, OSError) as e:
                raise AalabError("protocol", "%s %s: the connection failed: %s"
                                 % (method, path.split("?")[0], e)) from None
            return Response(r.status, {k.lower(): v for k, v in r.getheaders()}, body)
        finally:
            conn.close()
