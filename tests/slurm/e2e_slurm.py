#!/usr/bin/env python3
"""End-to-end on a real one-node Slurm cluster (tests/slurm/slurm_cluster.py): aalabd with
--slurm-shared-dir hands optimize, family-sweep and random-stats (with point-set metrics) jobs to
Slurm as job arrays run by aalab-worker, and

  - the results with executor slurm equal the same spec's local result to the last bit (best
    pattern, E2, every per-seed / per-configuration figure), for two --slurm-max-tasks values;
  - cancel mid-run: the job ends cancelled and squeue shows no task of it;
  - `scancel <array>_<i>` of a running shard: the shard is resubmitted and the job still gives
    the local result; killed a second time, the job fails naming the shard and its log's tail;
  - kill -9 of aalabd mid-array, restart on the same state dir: the job re-attaches and gives the
    local result;
  - executor slurm on a kind without a split (compare) is a 400 naming "executor"; a daemon
    without --slurm-shared-dir answers 503 slurm_unavailable; GET /v1/health reports slurm.

Usage: e2e_slurm.py AALABD   (aalab-worker is expected beside it, as the build puts it).
Skips (exit 77, the reason printed) where the cluster cannot start; AALAB_REQUIRE_SLURM=1 makes
that a failure. The budgets are iterations (max_iterations), never seconds, so that every result
is reproducible."""

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "e2e"))
import slurm_cluster  # noqa: E402
from e2e_lib import Daemon, check, expect_error  # noqa: E402

# Small reproducible jobs (iterations per seed, no clock). OPT_SHORT / SWEEP run in a few seconds;
# OPT_LONG's shards (2 seeds of P(1,16,8), ~4 s each on one core) run long enough to scancel one
# or kill the daemon while they run. P(1,r,n) families are used because a tiled family in mode
# both refines each seed's optimum by iterated local search beyond max_iterations (slower).
OPT_SHORT = {"kind": "optimize", "family": "P(1,4,2)", "seeds": 8, "max_iterations": 400,
             "rng_seed": 11}
SWEEP = {"kind": "family-sweep", "cost": 1.25, "seeds_per_config": 2, "max_iterations": 300,
         "rng_seed": 5}
# Issue 31: point-set figures per random pattern, computed by each shard's aalab-worker and ranked
# (Spearman's rho with E2) after the merge: the point_metrics block equals the local one.
RS_METRICS = {"kind": "random-stats", "family": "P(1,1,4)", "count": 400, "max_iterations": 100,
              "rng_seed": 4, "metrics": ["mixture", "star_linf", "mean_nn_distance"]}
OPT_LONG = {"kind": "optimize", "family": "P(1,16,8)", "seeds": 8, "max_iterations": 4000,
            "rng_seed": 3}
# OPT_CANCEL never ends within the test: ~50 seeds of several seconds in each shard.
OPT_CANCEL = {"kind": "optimize", "family": "P(1,16,8)", "seeds": 200, "max_iterations": 1000000,
              "rng_seed": 9}

# Result fields that legitimately differ between executors or runs: the executor itself, the
# number of shards, and wall-clock figures.
VOLATILE = {"executor", "shards", "seconds", "started", "finished", "elapsed", "wall_seconds"}

T0 = time.time()


def log(msg):
    print("[%6.1fs] %s" % (time.time() - T0, msg), flush=True)


def comparable(result):
    """The result without the fields that may differ between executors (recursively), as
    canonical JSON: equal strings mean equal to the last bit (json prints doubles with 17
    significant digits, the daemon's codec round-trips them)."""
    def strip(v):
        if isinstance(v, dict):
            return {k: strip(x) for k, x in v.items() if k not in VOLATILE}
        if isinstance(v, list):
            return [strip(x) for x in v]
        return v
    return json.dumps(strip(result), sort_keys=True)


def first_difference(a, b, path="result"):
    if type(a) is not type(b):
        return "%s: %r vs %r" % (path, a, b)
    if isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            if k in VOLATILE:
                continue
            if k not in a or k not in b:
                return "%s.%s present on one side only" % (path, k)
            d = first_difference(a[k], b[k], path + "." + k)
            if d:
                return d
        return None
    if isinstance(a, list):
        if len(a) != len(b):
            return "%s: length %d vs %d" % (path, len(a), len(b))
        for i, (x, y) in enumerate(zip(a, b)):
            d = first_difference(x, y, "%s[%d]" % (path, i))
            if d:
                return d
        return None
    return None if a == b and repr(a) == repr(b) else "%s: %r vs %r" % (path, a, b)


class Env:
    def __init__(self, binary, cluster):
        self.binary = binary
        self.cluster = cluster
        self.daemons = []
        self.dirs = []

    def shared_dir(self):
        d = tempfile.mkdtemp(prefix="aalab-slurm-shared-")
        os.chmod(d, 0o755)
        self.dirs.append(d)
        return d

    def daemon(self, slurm=True, max_tasks=4, shared=None, workers=2):
        extra = ["--workers", str(workers)]
        if slurm:
            shared = shared or self.shared_dir()
            extra += ["--slurm-shared-dir", shared, "--slurm-poll", "1",
                      "--slurm-max-tasks", str(max_tasks), "--slurm-time-limit", "10"]
        d = Daemon(self.binary, tcp=False, extra=extra)
        d.shared = shared
        d.start()
        self.daemons.append(d)
        return d

    def cleanup(self):
        errors = []
        for d in self.daemons:
            try:
                d.cleanup()
            except Exception as e:  # a sanitizer report or a hang: report after cleaning up
                errors.append(e)
        for p in self.dirs:
            shutil.rmtree(p, ignore_errors=True)
        return errors


# --- Slurm views ----------------------------------------------------------------------------
def tasks_of(cluster, job_id, states=None):
    """[(array_job_id, task_id_string, state)] of the Slurm tasks of aalab job job_id (name
    aalab-<id>-s<stage>), from squeue (pending ones as one "<array>_[a-b]" line)."""
    args = ["-o", "%F|%i|%j|%T"]  # %F: the array's base job id (%A differs per element)
    if states:
        args += ["-t", states]
    out = []
    for line in cluster.squeue(*args):
        arr, tid, name, state = line.split("|", 3)
        if re.fullmatch(r"aalab-%d-s\d+" % job_id, name.strip()):
            out.append((arr.strip(), tid.strip(), state.strip()))
    return out


def worker_processes(shared):
    """Pids of processes whose command line names this shared dir (aalab-worker runs)."""
    found = []
    for d in os.listdir("/proc"):
        if d.isdigit() and int(d) != os.getpid():
            try:
                with open("/proc/%s/cmdline" % d, "rb") as f:
                    if shared.encode() in f.read():
                        found.append(int(d))
            except OSError:
                pass
    return found


def outputs_of(shared, job_id):
    base = os.path.join(shared, "job-%d" % job_id)
    found = []
    for root, _, files in os.walk(base):
        found += [os.path.join(root, f) for f in files if re.fullmatch(r"output-\d+\.json", f)]
    return found


def submit(d, spec, executor=None):
    body = dict(spec)
    if executor:
        body["executor"] = executor
    r = d.post("/v1/jobs", body)
    check(r.status == 202, "submit %s: %r" % (body, r))
    return r.json()["id"]


def run(d, spec, executor=None, timeout=120):
    jid = submit(d, spec, executor)
    j = d.wait_job(jid, timeout=timeout)
    check(j["state"] == "done", "job %d (%s) ended %s: %s" % (jid, executor or "local",
                                                             j["state"], json.dumps(j)[:2000]))
    return j


def wait_running_tasks(cluster, jid, n=1, timeout=60):
    deadline = time.time() + timeout
    while time.time() < deadline:
        running = [t for t in tasks_of(cluster, jid) if t[2] == "RUNNING"]
        if len(running) >= n:
            return running
        time.sleep(0.2)
    raise AssertionError("job %d: no %d running Slurm task(s) within %d s: %r" %
                         (jid, n, timeout, tasks_of(cluster, jid)))


def expect_same(local, other, what):
    a, b = local["result"], other["result"]
    diff = first_difference(a, b)
    check(diff is None and comparable(a) == comparable(b),
          "%s: result differs from the local run: %s" % (what, diff))
    e2 = b.get("e2", b.get("ranked", [{}])[0].get("e2"))
    log("%s: same result as local (e2 %r)" % (what, e2))


def check_result_meta(j, executor, max_shards=None):
    res = j["result"]
    check(res.get("executor") == executor, "result.executor %r, want %r" % (res.get("executor"),
                                                                          executor))
    check(res.get("reproducible") is True, "max_iterations without max_seconds must be "
          "reproducible: %r" % res.get("reproducible"))
    if max_shards is not None:
        check(isinstance(res.get("shards"), int) and 1 <= res["shards"] <= max_shards,
              "result.shards %r, want 1..%d" % (res.get("shards"), max_shards))


# --- the checks -----------------------------------------------------------------------------
def check_unconfigured(env):
    d = env.daemon(slurm=False)
    h = d.get("/v1/health").json()
    check("slurm" in h and h["slurm"].get("configured") is False,
          "health of a daemon without --slurm-shared-dir: %r" % h.get("slurm"))
    e = expect_error(d.post("/v1/jobs", dict(OPT_SHORT, executor="slurm")), 503, "executor")
    check(e["code"] == "slurm_unavailable", e)
    check(re.search(r"configur|slurm-shared-dir", e["message"], re.I),
          "the 503 says that Slurm is not configured: %r" % e)
    log("no --slurm-shared-dir: health configured=false, submit 503 slurm_unavailable (%s)" %
        e["message"])
    d.cleanup()
    env.daemons.remove(d)


def wait_answering(d, timeout=30):
    deadline = time.time() + timeout
    while time.time() < deadline:
        s = d.get("/v1/health").json().get("slurm", {})
        if s.get("configured") and s.get("answering") is True:
            return s
        time.sleep(0.3)
    raise AssertionError("health never showed slurm answering: %r" % s)


def check_same_as_local(env, d, d3):
    s = wait_answering(d)
    log("health: %r" % s)
    # compare has no split: slurm is refused with a 400 naming the field
    compare = {"kind": "compare", "scene": {"name": "siemens-star", "width": 64, "height": 64},
               "patterns": ["rgss", {"preset": "flipquad"}], "reference": {"spp": 64}}
    e = expect_error(d.post("/v1/jobs", dict(compare, executor="slurm")), 400, "executor")
    log("compare with executor slurm: 400 executor (%s)" % e["message"])

    local = {}
    for name, spec in (("optimize", OPT_SHORT), ("family-sweep", SWEEP),
                       ("random-stats with metrics", RS_METRICS)):
        local[name] = run(d, spec)
        check_result_meta(local[name], "local")
        sl = run(d, spec, "slurm")
        check_result_meta(sl, "slurm", 4)
        check(sl["result"]["shards"] > 1, "%s: a split into more than one shard expected, got %r"
              % (name, sl["result"]["shards"]))
        expect_same(local[name], sl, "%s slurm (max tasks 4, %d shards)" %
                    (name, sl["result"]["shards"]))
        check(not tasks_of(env.cluster, sl["id"]), "finished job still in squeue")
        # and with another --slurm-max-tasks (another daemon, its own shared dir)
        other = run(d3, spec, "slurm")
        check_result_meta(other, "slurm", 3)
        expect_same(local[name], other, "%s slurm (max tasks 3, %d shards)" %
                    (name, other["result"]["shards"]))
    return local


def check_cancel(env, d):
    jid = submit(d, OPT_CANCEL, "slurm")
    wait_running_tasks(env.cluster, jid)
    r = d.delete("/v1/jobs/%d" % jid)
    check(r.status == 202, r)
    t = time.time()
    j = d.wait_job(jid, timeout=60)
    check(j["state"] == "cancelled", "cancelled slurm job ended %s" % j["state"])
    left = tasks_of(env.cluster, jid)
    deadline = time.time() + 15
    while left and time.time() < deadline:
        time.sleep(0.2)
        left = tasks_of(env.cluster, jid)
    check(not left, "tasks of the cancelled job still in squeue 15 s after it ended: %r" % left)
    # aalab-worker stops on SIGTERM (exit 75); no process of the job is left on the node
    deadline = time.time() + 10
    procs = worker_processes(os.path.join(d.shared, "job-%d" % jid))
    while procs and time.time() < deadline:
        time.sleep(0.2)
        procs = worker_processes(os.path.join(d.shared, "job-%d" % jid))
    check(not procs, "worker processes of the cancelled job still running: %r" % procs)
    log("cancel: job cancelled after %.1f s, no task in squeue, no worker left" % (time.time() - t))


def check_scancel_retry(env, d, local):
    jid = submit(d, OPT_LONG, "slurm")
    running = wait_running_tasks(env.cluster, jid)
    arr, tid, _ = running[0]
    arrays = {a for a, _, _ in tasks_of(env.cluster, jid)}
    p = subprocess.run(["scancel", tid], env=env.cluster.env(), capture_output=True, text=True)
    check(p.returncode == 0, "scancel %s: %s" % (tid, p.stderr))
    log("scancel %s (job %d)" % (tid, jid))
    deadline = time.time() + 180
    while time.time() < deadline:
        arrays |= {a for a, _, _ in tasks_of(env.cluster, jid)}
        j = d.get("/v1/jobs/%d" % jid).json()
        if j["state"] not in ("queued", "running"):
            break
        time.sleep(0.2)
    check(j["state"] == "done", "job with a scancelled shard ended %s: %s" %
          (j["state"], json.dumps(j)[:2000]))
    check(len(arrays) >= 2, "the scancelled shard was not resubmitted as a new array (seen %r)"
          % sorted(arrays))
    expect_same(local, j, "optimize with shard %s scancelled (arrays %s)" %
                (tid, ",".join(sorted(arrays))))


def check_retry_exhausted(env, d):
    """A shard killed twice fails the job, naming the shard and the tail of its log; the job's
    other tasks leave the queue."""
    jid = submit(d, OPT_CANCEL, "slurm")
    arr, tid, _ = wait_running_tasks(env.cluster, jid)[0]
    index = tid.split("_", 1)[1]
    subprocess.run(["scancel", tid], env=env.cluster.env(), check=True)
    deadline = time.time() + 60
    retry = None
    while retry is None and time.time() < deadline:
        for a, t, state in tasks_of(env.cluster, jid):
            # running, or pending behind the other shards (squeue shows it as "<array>_[i]")
            if a != arr and t.split("_", 1)[1].strip("[]") == index:
                retry = "%s_%s" % (a, index)
        time.sleep(0.2)
    check(retry, "shard %s was not resubmitted after scancel %s: %r" %
          (index, tid, tasks_of(env.cluster, jid)))
    subprocess.run(["scancel", retry], env=env.cluster.env(), check=True)
    j = d.wait_job(jid, timeout=60)
    check(j["state"] == "failed", "job with a shard killed twice ended %s" % j["state"])
    text = json.dumps(j.get("error"))
    check(re.search(r"shard %s\b" % index, text) and "log-%s.out" % index in text and
          "CANCELLED" in text.upper(),
          "the failure names the shard, its log and the tail of the log: %s" % text)
    deadline = time.time() + 20
    while tasks_of(env.cluster, jid) and time.time() < deadline:
        time.sleep(0.2)
    check(not tasks_of(env.cluster, jid), "tasks of the failed job still in squeue: %r" %
          tasks_of(env.cluster, jid))
    log("shard %s killed twice (%s, %s): job failed: %s" % (index, tid, retry,
                                                            j["error"]["message"][:200]))


def check_kill9_restart(env, d, local):
    jid = submit(d, OPT_LONG, "slurm")
    wait_running_tasks(env.cluster, jid)
    # let at least one shard finish while the daemon is alive, then kill it with others running
    deadline = time.time() + 120
    while not outputs_of(d.shared, jid) and time.time() < deadline:
        time.sleep(0.2)
    still = tasks_of(env.cluster, jid)
    d.stop(sig=signal.SIGKILL)
    before = {}
    for p in outputs_of(d.shared, jid):
        with open(p) as f:
            before[p] = json.load(f)["started_unix"]
    log("kill -9 aalabd with job %d: %d output(s) written, still in squeue: %r" %
        (jid, len(outputs_of(d.shared, jid)), still))
    # shards finish while no daemon runs
    time.sleep(3)
    d.start()
    j = d.wait_job(jid, timeout=180)
    check(j["state"] == "done", "job after kill -9 and restart ended %s: %s" %
          (j["state"], json.dumps(j)[:2000]))
    expect_same(local, j, "optimize across kill -9 and restart")
    # re-attached, not resubmitted: the shards finished before the restart did not run again
    for p, t in before.items():
        with open(p) as f:
            check(json.load(f)["started_unix"] == t, "%s was run again after the restart" % p)
    check(not tasks_of(env.cluster, jid), "finished job still in squeue after restart")


def main():
    if len(sys.argv) != 2:
        print("usage: e2e_slurm.py AALABD", file=sys.stderr)
        return 2
    binary = os.path.abspath(sys.argv[1])
    worker = os.path.join(os.path.dirname(binary), "aalab-worker")
    helptext = subprocess.run([binary, "--help"], capture_output=True, text=True).stdout
    check("--slurm-shared-dir" in helptext, "%s --help has no --slurm-shared-dir" % binary)
    check(os.access(worker, os.X_OK), "no aalab-worker beside aalabd (%s)" % worker)

    cluster = slurm_cluster.start_or_skip()
    log("cluster up: %s (node %s, %d CPUs)" % (cluster.conf, cluster.hostname, cluster.cpus))
    os.environ["SLURM_CONF"] = cluster.conf  # the daemons inherit it
    env = Env(binary, cluster)
    ok = False
    try:
        check_unconfigured(env)
        d = env.daemon(max_tasks=4)
        d3 = env.daemon(max_tasks=3)
        wait_answering(d3)
        check_same_as_local(env, d, d3)
        d3.cleanup()
        env.daemons.remove(d3)
        check_cancel(env, d)
        local_long = run(d, OPT_LONG, timeout=180)
        log("optimize %s local: e2 %r" % (OPT_LONG["family"], local_long["result"]["e2"]))
        check_scancel_retry(env, d, local_long)
        check_retry_exhausted(env, d)
        check_kill9_restart(env, d, local_long)
        ok = True
    finally:
        errors = env.cleanup()
        killed = cluster.stop()
        left = cluster.leftovers()
        if killed:
            print("cluster stop needed SIGKILL for %r" % killed, flush=True)
        for e in errors:
            print("cleanup: %s" % e, flush=True)
        if ok and (errors or left):
            raise AssertionError("cleanup failed: %r %r" % (errors, left))
    log("all slurm checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
