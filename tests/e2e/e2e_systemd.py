"""End-to-end: socket activation (LISTEN_FDS via systemd-socket-activate) and sd_notify
readiness (READY=1 at start, STOPPING=1 at SIGTERM) on a NOTIFY_SOCKET of our own."""

import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from e2e_lib import check  # noqa: E402


def curl_health(sock):
    p = subprocess.run(["curl", "-sS", "--max-time", "5", "--unix-socket", sock,
                        "http://aalab/v1/health"], capture_output=True)
    return p.returncode == 0 and b'"status":"ok"' in p.stdout


def test_notify(binary, root):
    notify_path = os.path.join(root, "notify.sock")
    n = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    n.bind(notify_path)
    n.settimeout(20)
    env = dict(os.environ, NOTIFY_SOCKET=notify_path)
    env.pop("LISTEN_FDS", None)
    sock = os.path.join(root, "n.sock")
    p = subprocess.Popen([binary, "--socket", sock, "--state-dir", os.path.join(root, "st1")],
                         env=env, stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
    try:
        msg = n.recv(4096).decode()
        check("READY=1" in msg, "READY=1 sent: %r" % msg)
        check(curl_health(sock), "serving once READY")
        p.send_signal(signal.SIGTERM)
        msg = n.recv(4096).decode()
        check("STOPPING=1" in msg, "STOPPING=1 sent: %r" % msg)
        check(p.wait(20) == 0, "exit 0")
    finally:
        if p.poll() is None:
            p.kill()
        n.close()


def test_activation(binary, root):
    activate = shutil.which("systemd-socket-activate")
    if not activate:
        print("systemd-socket-activate not found: activation part skipped")
        return False
    sock = os.path.join(root, "act.sock")
    probe = socket.socket()
    probe.bind(("127.0.0.1", 0))
    port = probe.getsockname()[1]
    probe.close()
    p = subprocess.Popen([activate, "-l", sock, "-l", "127.0.0.1:%d" % port, binary,
                          "--state-dir", os.path.join(root, "st2")],
                         stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
    try:
        deadline = time.time() + 20
        while not os.path.exists(sock) and time.time() < deadline:
            time.sleep(0.05)
        check(curl_health(sock), "socket-activated daemon answers on the passed socket")
        check(curl_health(sock), "and keeps answering")
        # The activated TCP listener: named in /v1/health (aalab token prints the URL), and
        # every API request on it needs a token issued on the socket.
        h = subprocess.run(["curl", "-sS", "--unix-socket", sock, "http://aalab/v1/health"],
                           capture_output=True).stdout.decode()
        check('"dashboard":"http://127.0.0.1:%d/"' % port in h, "health names the TCP listener: %s" % h)
        tok = subprocess.run(["curl", "-sS", "--unix-socket", sock, "-d", "{}", "-H",
                              "Content-Type: application/json",
                              "http://aalab/v1/tokens"], capture_output=True).stdout.decode()
        token = tok.split('"token":"')[1].split('"')[0]

        def tcp_status(*extra):
            return subprocess.run(["curl", "-s", "-o", "/dev/null", "-w", "%{http_code}"] +
                                  list(extra) + ["http://127.0.0.1:%d/v1/health" % port],
                                  capture_output=True).stdout.decode()
        check(tcp_status() == "401", "activated TCP listener: no token, 401")
        check(tcp_status("-H", "Authorization: Bearer " + token) == "200",
              "activated TCP listener: with a token, 200")
        p.send_signal(signal.SIGTERM)
        check(p.wait(20) == 0, "exit 0")
    finally:
        if p.poll() is None:
            p.kill()
    return True


def main():
    binary = sys.argv[1]
    root = tempfile.mkdtemp(prefix="aalab-sd-")
    try:
        test_notify(binary, root)
        test_activation(binary, root)
    finally:
        shutil.rmtree(root, ignore_errors=True)
    print("e2e_systemd: ok")


if __name__ == "__main__":
    main()
