"""Fixtures of the Python package's tests: one aalabd on a temporary socket and state directory
for the whole session (tests/aalabd_harness.py), and clients that validate every answer against
the JSON Schemas the package ships (proto/schemas).

The daemon is $AALAB_DAEMON, else the first of build/{ci,dev,release}/server/aalabd; without
one the daemon tests skip (scripts/test.sh sets AALAB_DAEMON, so CI never skips)."""

import os
import sys

import pytest

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
sys.path.insert(0, os.path.join(REPO, "tests"))

import aalabd_harness  # noqa: E402

import aalab  # noqa: E402


def daemon_binary():
    env = os.environ.get("AALAB_DAEMON")
    if env:
        if not os.access(env, os.X_OK):
            raise RuntimeError("AALAB_DAEMON=%s is not an executable" % env)
        return env
    for d in ("ci", "dev", "release"):
        p = os.path.join(REPO, "build", d, "server", "aalabd")
        if os.access(p, os.X_OK):
            return p
    return None


@pytest.fixture(scope="session")
def daemon():
    binary = daemon_binary()
    if binary is None:
        pytest.skip("no aalabd built (set AALAB_DAEMON or build build/dev)")
    d = aalabd_harness.Daemon(binary, workers=2, tcp=False)
    d.start()
    yield d
    rc = d.stop()
    assert rc == 0, "aalabd exited %r:\n%s" % (rc, d.log_text())
    assert not d.sanitizer_reports(), d.log_text()


@pytest.fixture
def client(daemon):
    """A client that checks every answer against its schema."""
    return aalab.Client(daemon.socket_path, validate=True, timeout=60)


@pytest.fixture(scope="session")
def opt_job(daemon):
    """A short, reproducible P(4,1+,2) optimisation shared by the job tests."""
    c = aalab.Client(daemon.socket_path, validate=True)
    return c.optimize(family="P(4,1+,2)", seeds=2, max_iterations=60, rng_seed=3,
                      label="pytest P(4,1+,2)").wait(progress=False, timeout=120)
