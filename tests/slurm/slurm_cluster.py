#!/usr/bin/env python3
"""A real one-node Slurm cluster for the tests and the cluster benchmark, started from Debian's
slurm-wlm and munge packages in a temporary directory and stopped after.

    with SlurmCluster() as c:          # or c = SlurmCluster(); c.start(); ...; c.stop()
        env = c.env()                  # os.environ + SLURM_CONF
        subprocess.run(["sbatch", ...], env=env)

As a command:

    tests/slurm/slurm_cluster.py start [--dir DIR]   # prints `export SLURM_CONF=...` lines
    tests/slurm/slurm_cluster.py env DIR             # the same lines for a running cluster
    tests/slurm/slurm_cluster.py stop DIR            # stops it and removes DIR

What it starts, all inside one temporary directory (nothing under /etc, /run or /var is used):
  - munged, as the user munge, with its own key, socket, pid, log and seed file;
  - slurmctld -i (ignore saved state) and slurmd, both in the foreground of their own session,
    with a generated slurm.conf for this host: its own free ports, AuthInfo=socket=<munge socket>,
    SlurmUser=root, proctrack/linuxproc, task/none, no accounting storage, select/cons_tres with
    CR_Core, NodeName=$(hostname -s) CPUs=$(nproc), one default partition "aalab".
It waits until sinfo shows the node idle. stop() cancels every job, `scontrol shutdown`, waits
for the daemons, ends whatever is left that belongs to this cluster (processes are found by their
ids: the daemons this module started, and any process whose environment, command line or open
files name the cluster's directory, i.e. slurmstepd and the job steps), and removes the directory.

Where the cluster cannot start (not root, a package missing, no user munge, a daemon that exits or
never reports the node idle) start() raises ClusterUnavailable with the reason; tests turn that
into a skip (exit code 77) with the reason printed, unless AALAB_REQUIRE_SLURM=1 asks for a
failure instead. Standard library only."""

import argparse
import glob
import json
import os
import pwd
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

SKIP = 77
COMMANDS = ("munged", "slurmctld", "slurmd", "sbatch", "squeue", "scontrol", "scancel", "sinfo")
PARTITION = "aalab"


class ClusterUnavailable(Exception):
    """The cluster cannot run on this machine; the message says why."""


def _free_ports(n):
    socks, ports = [], []
    for _ in range(n):
        s = socket.socket()
        s.bind(("", 0))
        socks.append(s)
        ports.append(s.getsockname()[1])
    for s in socks:
        s.close()
    return ports


def _which(cmd):
    # slurmctld, slurmd and munged live in /usr/sbin, which a non-login PATH may lack.
    path = os.environ.get("PATH", "") + ":/usr/sbin:/sbin"
    return shutil.which(cmd, path=path)


def _mem_mb():
    with open("/proc/meminfo") as f:
        for line in f:
            if line.startswith("MemTotal:"):
                return int(line.split()[1]) // 1024
    return 1024


def _tail(path, n=30):
    try:
        with open(path, "rb") as f:
            lines = f.read().decode("utf-8", "replace").splitlines()
        return "\n".join(lines[-n:])
    except OSError:
        return "(no %s)" % path


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    # A zombie child of ours counts as gone (reaped below when it is our child).
    try:
        with open("/proc/%d/stat" % pid) as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def _wait_gone(pids, timeout):
    deadline = time.time() + timeout
    while time.time() < deadline:
        for p in pids:
            try:
                os.waitpid(p, os.WNOHANG)
            except ChildProcessError:
                pass
        if not any(_alive(p) for p in pids):
            return True
        time.sleep(0.1)
    return False


def unavailable_reason():
    """Why this machine cannot run the test cluster, or None if it can try."""
    if os.geteuid() != 0:
        return "not root (slurmd and munged as user munge need root)"
    missing = [c for c in COMMANDS if not _which(c)]
    if missing:
        return ("missing %s (Debian packages slurm-wlm and munge; scripts/install-deps.sh "
                "installs them)" % " ".join(missing))
    try:
        pwd.getpwnam("munge")
    except KeyError:
        return "no user munge (the munge package creates it)"
    return None


class SlurmCluster:
    def __init__(self, root=None, min_job_age=30, kill_wait=5, owner=True):
        self.root = root
        # The process whose end makes this cluster stale (the next start stops it); None for a
        # cluster started from the command line, which lives until `stop`.
        self.owner = os.getpid() if owner else None
        self.min_job_age = min_job_age
        self.kill_wait = kill_wait
        self.pids = {}  # name -> pid of the daemons started here
        self.hostname = socket.gethostname().split(".")[0]
        self.cpus = os.cpu_count() or 1
        self.started = False

    # --- paths -----------------------------------------------------------------------------
    def path(self, *parts):
        return os.path.join(self.root, *parts)

    @property
    def conf(self):
        return self.path("slurm.conf")

    @property
    def munge_socket(self):
        return self.path("munge", "run", "munge.socket")

    def env(self, base=None):
        env = dict(os.environ if base is None else base)
        env["SLURM_CONF"] = self.conf
        env["PATH"] = env.get("PATH", "/usr/bin:/bin") + ":/usr/sbin:/sbin"
        return env

    # --- start -----------------------------------------------------------------------------
    def start(self, timeout=60):
        why = unavailable_reason()
        if why:
            raise ClusterUnavailable(why)
        reap_stale()
        if self.root is None:
            self.root = tempfile.mkdtemp(prefix="aalab-slurm-")
        os.makedirs(self.root, exist_ok=True)
        os.chmod(self.root, 0o755)  # munged (user munge) must reach its own subdirectory
        try:
            self._start(timeout)
        except BaseException:
            self.stop()
            raise
        self.started = True
        return self

    def _start(self, timeout):
        for d in ("state", "spool", "log", "run"):
            os.makedirs(self.path(d), mode=0o755, exist_ok=True)
        self._start_munge()
        self._write_conf()
        self._save_state()
        env = self.env()
        for name, args in (("slurmctld", ["slurmctld", "-D", "-i", "-f", self.conf]),
                           ("slurmd", ["slurmd", "-D", "-f", self.conf, "-N", self.hostname])):
            out = open(self.path("log", name + ".stdout"), "ab")
            p = subprocess.Popen([_which(args[0])] + args[1:], stdout=out, stderr=subprocess.STDOUT,
                                 stdin=subprocess.DEVNULL, env=env, start_new_session=True)
            out.close()
            self.pids[name] = p.pid
            self._save_state()
            if name == "slurmctld":
                self._wait(lambda: self._run(["scontrol", "ping"]).stdout.find("UP") >= 0,
                           timeout, "slurmctld does not answer `scontrol ping`", "slurmctld")
        self._wait(lambda: self.node_state() == "idle", timeout,
                   "the node never showed idle in sinfo (state %r)" % "?", "slurmd")

    def _start_munge(self):
        mu = pwd.getpwnam("munge")
        base = self.path("munge")
        os.makedirs(self.path("munge", "run"), exist_ok=True)
        os.makedirs(self.path("munge", "key"), exist_ok=True)
        for d, mode in ((base, 0o755), (self.path("munge", "run"), 0o755),
                        (self.path("munge", "key"), 0o700)):
            os.chmod(d, mode)
            os.chown(d, mu.pw_uid, mu.pw_gid)
        key = self.path("munge", "key", "munge.key")
        with open(key, "wb") as f:
            f.write(os.urandom(1024))
        os.chmod(key, 0o400)
        os.chown(key, mu.pw_uid, mu.pw_gid)
        args = [_which("munged"), "--foreground", "--socket=" + self.munge_socket,
                "--key-file=" + key, "--pid-file=" + self.path("munge", "run", "munged.pid"),
                "--log-file=" + self.path("munge", "run", "munged.log"),
                "--seed-file=" + self.path("munge", "run", "munged.seed"), "--num-threads=2"]
        out = open(self.path("log", "munged.stdout"), "ab")

        def as_munge():
            os.setgroups([])
            os.setgid(mu.pw_gid)
            os.setuid(mu.pw_uid)

        p = subprocess.Popen(args, stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                             preexec_fn=as_munge, start_new_session=True, cwd=base)
        out.close()
        self.pids["munged"] = p.pid
        self._save_state()
        self._wait(lambda: os.path.exists(self.munge_socket), 15,
                   "munged did not create its socket", "munged")

    def _write_conf(self):
        ctld_port, slurmd_port = _free_ports(2)
        mem = max(256, int(_mem_mb() * 0.8))
        lines = [
            "# Generated by tests/slurm/slurm_cluster.py: a one-node test cluster in " + self.root,
            "ClusterName=aalabtest",
            "SlurmctldHost=" + self.hostname,
            "SlurmctldPort=%d" % ctld_port,
            "SlurmdPort=%d" % slurmd_port,
            "AuthType=auth/munge",
            "AuthInfo=socket=" + self.munge_socket,
            "CredType=cred/munge",
            "SlurmUser=root",
            "SlurmdUser=root",
            "ProctrackType=proctrack/linuxproc",
            "TaskPlugin=task/none",
            "SchedulerType=sched/backfill",
            "SelectType=select/cons_tres",
            "SelectTypeParameters=CR_Core",
            "AccountingStorageType=accounting_storage/none",
            "JobAcctGatherType=jobacct_gather/none",
            "JobCompType=jobcomp/none",
            "MpiDefault=none",
            "ReturnToService=2",
            "MaxArraySize=10001",
            "MinJobAge=%d" % self.min_job_age,
            "KillWait=%d" % self.kill_wait,
            "StateSaveLocation=" + self.path("state"),
            "SlurmdSpoolDir=" + self.path("spool"),
            "SlurmctldPidFile=" + self.path("run", "slurmctld.pid"),
            "SlurmdPidFile=" + self.path("run", "slurmd.pid"),
            "SlurmctldLogFile=" + self.path("log", "slurmctld.log"),
            "SlurmdLogFile=" + self.path("log", "slurmd.log"),
            "NodeName=%s CPUs=%d RealMemory=%d State=UNKNOWN" % (self.hostname, self.cpus, mem),
            "PartitionName=%s Nodes=%s Default=YES MaxTime=INFINITE State=UP" %
            (PARTITION, self.hostname),
        ]
        with open(self.conf, "w") as f:
            f.write("\n".join(lines) + "\n")

    def _save_state(self):
        with open(self.path("cluster.json"), "w") as f:
            json.dump({"root": self.root, "pids": self.pids, "owner": self.owner}, f)

    def _run(self, args, timeout=15):
        try:
            return subprocess.run(args, env=self.env(), capture_output=True, text=True,
                                  timeout=timeout)
        except subprocess.TimeoutExpired:
            return subprocess.CompletedProcess(args, 124, "", "timed out")

    def _wait(self, cond, timeout, what, daemon):
        deadline = time.time() + timeout
        while time.time() < deadline:
            for name, pid in self.pids.items():
                if not _alive(pid):
                    raise ClusterUnavailable("%s exited during start-up (%s); its log:\n%s" % (
                        name, what, self._log_tail(name)))
            if cond():
                return
            time.sleep(0.2)
        raise ClusterUnavailable("%s within %d s; %s log:\n%s" % (what, timeout, daemon,
                                                                 self._log_tail(daemon)))

    def _log_tail(self, name):
        if name == "munged":
            return _tail(self.path("munge", "run", "munged.log")) + "\n" + \
                _tail(self.path("log", "munged.stdout"))
        return _tail(self.path("log", name + ".log")) + "\n" + \
            _tail(self.path("log", name + ".stdout"))

    # --- queries ---------------------------------------------------------------------------
    def node_state(self):
        r = self._run(["sinfo", "-h", "-N", "-o", "%T"])
        return r.stdout.strip().rstrip("*") if r.returncode == 0 else None

    def squeue(self, *args):
        """squeue lines (-h) with these extra arguments; raises if squeue fails."""
        r = self._run(["squeue", "-h"] + list(args))
        if r.returncode != 0:
            raise RuntimeError("squeue failed: %s" % r.stderr)
        return [line for line in r.stdout.splitlines() if line.strip()]

    # --- stop ------------------------------------------------------------------------------
    def stop(self):
        """Stops everything this cluster started and removes its directory. Safe to call twice
        and after a failed start. Returns the pids that needed SIGKILL (normally none)."""
        if self.root is None or not os.path.isdir(self.root):
            return []
        ctld = self.pids.get("slurmctld")
        if ctld and _alive(ctld):
            self._run(["scancel", "--quiet", "--full", "--user=root"], timeout=10)
            r = self._run(["squeue", "-h", "-o", "%i"], timeout=10)
            ids = [i for i in r.stdout.split() if i]
            if ids:
                self._run(["scancel", "--quiet"] + ids, timeout=10)
            deadline = time.time() + self.kill_wait + 10
            while time.time() < deadline:
                r = self._run(["squeue", "-h", "-o", "%i"], timeout=10)
                if r.returncode != 0 or not r.stdout.strip():
                    break
                time.sleep(0.3)
            self._run(["scontrol", "shutdown"], timeout=10)
        slurm = [p for n, p in self.pids.items() if n != "munged"]
        if not _wait_gone(slurm, 15):
            for p in slurm:
                self._signal(p, signal.SIGTERM)
            _wait_gone(slurm, 5)
        # Anything else of this cluster: slurmstepd, job steps, strays of a previous stop.
        killed = []
        for sig in (signal.SIGTERM, signal.SIGKILL):
            left = [p for p in self._processes() if p != self.pids.get("munged")]
            left += [p for n, p in self.pids.items() if n != "munged" and _alive(p)]
            if not left:
                break
            for p in set(left):
                self._signal(p, sig)
                if sig == signal.SIGKILL:
                    killed.append(p)
            _wait_gone(left, 5)
        mpid = self.pids.get("munged")
        if mpid and _alive(mpid):
            self._signal(mpid, signal.SIGTERM)
            if not _wait_gone([mpid], 10):
                self._signal(mpid, signal.SIGKILL)
                killed.append(mpid)
                _wait_gone([mpid], 5)
        for p in self._processes():
            self._signal(p, signal.SIGKILL)
            killed.append(p)
        if not os.environ.get("AALAB_KEEP_TEST_DIRS"):
            shutil.rmtree(self.root, ignore_errors=True)
        self.started = False
        return killed

    @staticmethod
    def _signal(pid, sig):
        try:
            os.kill(pid, sig)
        except (ProcessLookupError, PermissionError):
            pass

    def _processes(self):
        """Pids (other than ours) whose command line or open files name the cluster's directory,
        or job steps whose environment does."""
        needle = self.root.encode()
        me = os.getpid()
        found = []
        for d in os.listdir("/proc"):
            if not d.isdigit() or int(d) == me:
                continue
            pid = int(d)
            hit = False
            for name in ("cmdline", "environ"):
                try:
                    with open("/proc/%d/%s" % (pid, name), "rb") as f:
                        text = f.read()
                except OSError:
                    continue
                # By environment only the job steps (SLURM_JOB_ID), not a client such as aalabd
                # that merely has SLURM_CONF pointing here.
                if needle in text and (name == "cmdline" or b"SLURM_JOB_ID=" in text):
                    hit = True
                    break
            if not hit:
                try:
                    for fd in os.listdir("/proc/%d/fd" % pid):
                        try:
                            if os.readlink("/proc/%d/fd/%s" % (pid, fd)).startswith(self.root):
                                hit = True
                                break
                        except OSError:
                            pass
                except OSError:
                    pass
            if hit and _alive(pid):
                found.append(pid)
        return found

    def leftovers(self):
        """Processes of this cluster still running (for a test's final check)."""
        return self._processes() + [p for p in self.pids.values() if _alive(p)]

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()
        return False

    @classmethod
    def attach(cls, root):
        with open(os.path.join(root, "cluster.json")) as f:
            st = json.load(f)
        c = cls(root=st["root"], owner=False)
        c.owner = st.get("owner")
        c.pids = {k: int(v) for k, v in st["pids"].items()}
        c.started = True
        return c


def reap_stale():
    """Stops the clusters of earlier test runs whose owner process is gone (a test killed by
    ctest's timeout cannot run its own clean-up)."""
    for st in glob.glob(os.path.join(tempfile.gettempdir(), "aalab-slurm-*", "cluster.json")):
        try:
            with open(st) as f:
                owner = json.load(f).get("owner")
        except (OSError, ValueError):
            continue
        if owner and not _alive(owner):
            print("slurm_cluster: stopping the stale cluster in %s (its test, pid %d, is gone)"
                  % (os.path.dirname(st), owner), flush=True)
            SlurmCluster.attach(os.path.dirname(st)).stop()


def _exit_on_signal(signum, frame):
    raise SystemExit(128 + signum)  # runs the callers' finally blocks: the cluster stops


def start_or_skip(**kw):
    """A started cluster, or exits 77 (skip) printing why it cannot run here (exit 1 instead if
    AALAB_REQUIRE_SLURM=1). SIGTERM and SIGHUP then end the caller through SystemExit, so that its
    clean-up stops the cluster."""
    for sig in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, _exit_on_signal)
    try:
        return SlurmCluster(**kw).start()
    except ClusterUnavailable as e:
        if os.environ.get("AALAB_REQUIRE_SLURM") == "1":
            print("FAIL: the one-node Slurm cluster did not start (AALAB_REQUIRE_SLURM=1): %s" % e,
                  flush=True)
            sys.exit(1)
        print("SKIP: the one-node Slurm cluster cannot run here: %s" % e, flush=True)
        sys.exit(SKIP)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("start", help="start a cluster and print its environment")
    s.add_argument("--dir", help="directory to use (default: a new one in $TMPDIR)")
    for name in ("stop", "env", "status"):
        p = sub.add_parser(name)
        p.add_argument("dir")
    a = ap.parse_args()
    if a.cmd == "start":
        try:
            c = SlurmCluster(root=a.dir, owner=False).start()
        except ClusterUnavailable as e:
            print("slurm_cluster: cannot start: %s" % e, file=sys.stderr)
            return SKIP
        print("export SLURM_CONF=%s" % c.conf)
        print("# stop with: %s stop %s" % (sys.argv[0], c.root))
        return 0
    c = SlurmCluster.attach(a.dir)
    if a.cmd == "env":
        print("export SLURM_CONF=%s" % c.conf)
    elif a.cmd == "status":
        print("node %s: %s" % (c.hostname, c.node_state()))
    else:
        killed = c.stop()
        if killed:
            print("slurm_cluster: needed SIGKILL for %s" % killed, file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
