#!/usr/bin/env python3
"""Cluster benchmark: the Slurm executor on a real one-node cluster (tests/slurm/slurm_cluster.py)
against local execution in the same run. A benchmark, not a timed test: it prints figures and
fails only if something does not work.

    bench/bench_cluster.py build/dev/server/aalabd [--trivial 20] [--shards 16]
                           [--shard-iterations 3000] [--rounds 2] [--p16-iterations 500]

aalab-worker is taken from beside aalabd. The task files are real ones: the bench submits jobs
with executor slurm to an aalabd started on the cluster and copies the TASK.json files the daemon
writes into its shared directory (so shard descriptors stay the kind's own business), then runs
those same tasks itself, pointing each task's output and trace at the bench's own directory:

 (a) per-task overhead, sbatch submission -> the shard's started_unix (in the worker's output
     file), for N trivial shards (optimize P(1,4,1), one seed, max_iterations 1):
       - one at a time (submit, wait for the output, submit the next): the pure latency;
       - all N as one array, 2 CPUs: latency including the wait for a free CPU;
     plus the daemon's own end-to-end time for the job that produced them.
 (b) shards per minute: the same S shards (optimize P(1,16,8), one seed each, max_iterations M)
     run by aalab-worker directly, 2 at a time (the node's CPUs), and as one Slurm array, from
     start (sbatch) to the last output written; printed side by side with their ratio.
 (c) the time of one P(16,16,4) seed with max_iterations K, run by aalab-worker alone (1 thread),
     for docs/cluster.md's estimate of a 1000-seed job.
Exit 77 (skip, reason printed) where the cluster cannot start."""

import argparse
import glob
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "slurm"))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "e2e"))
import slurm_cluster  # noqa: E402
from e2e_lib import Daemon  # noqa: E402


def say(msg):
    print(msg, flush=True)


def capture_tasks(d, spec, want, keep_job=False, timeout=120):
    """Submits spec with executor slurm and returns copies of the first `want` TASK.json files of
    stage 0 the daemon writes (sorted by shard index); cancels the job unless keep_job."""
    r = d.post("/v1/jobs", dict(spec, executor="slurm"))
    if r.status != 202:
        raise RuntimeError("submit %s: %r" % (spec, r))
    jid = r.json()["id"]
    t_submit = time.time()
    stage = os.path.join(d.shared, "job-%d" % jid, "stage-0")
    tasks = {}
    deadline = time.time() + timeout
    while len(tasks) < want and time.time() < deadline:
        for p in glob.glob(os.path.join(stage, "task-*.json")):
            i = int(os.path.basename(p)[5:-5])
            if i not in tasks:
                try:
                    with open(p) as f:
                        tasks[i] = json.load(f)
                except (OSError, ValueError):
                    pass  # being written
        time.sleep(0.02)
    if len(tasks) < want:
        raise RuntimeError("job %d: %d task files in %s, %d wanted" %
                           (jid, len(tasks), stage, want))
    job_seconds = None
    if keep_job:
        j = d.wait_job(jid, timeout=timeout)
        if j["state"] != "done":
            raise RuntimeError("job %d ended %s: %s" % (jid, j["state"], json.dumps(j)[:1000]))
        job_seconds = time.time() - t_submit
    else:
        d.delete("/v1/jobs/%d" % jid)
        d.wait_job(jid, timeout=60)
    return [tasks[i] for i in sorted(tasks)][:want], job_seconds


def write_tasks(tasks, outdir):
    """The tasks with output/trace in outdir, written as outdir/task-<i>.json; returns paths."""
    os.makedirs(outdir, exist_ok=True)
    paths = []
    for i, t in enumerate(tasks):
        t = dict(t)
        t["output"] = os.path.join(outdir, "output-%d.json" % i)
        t["trace"] = os.path.join(outdir, "trace-%d.json" % i)
        p = os.path.join(outdir, "task-%d.json" % i)
        with open(p, "w") as f:
            json.dump(t, f)
        paths.append(p)
    return paths


def read_output(outdir, i):
    try:
        with open(os.path.join(outdir, "output-%d.json" % i)) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def sbatch(cluster, outdir, worker, array, name):
    script = os.path.join(outdir, "array.sh")
    if not os.path.exists(script):
        with open(script, "w") as f:
            f.write("#!/bin/sh\nexec %s %s/task-\"$SLURM_ARRAY_TASK_ID\".json\n" % (worker, outdir))
        os.chmod(script, 0o755)
    t = time.time()
    p = subprocess.run(["sbatch", "--parsable", "--array=" + array, "--job-name=" + name,
                        "--cpus-per-task=1", "--time=10", "--output=%s/log-%%a.out" % outdir,
                        script], env=cluster.env(), capture_output=True, text=True, timeout=30)
    if p.returncode != 0:
        raise RuntimeError("sbatch: %s" % p.stderr)
    return t


def wait_outputs(outdir, indices, timeout):
    deadline = time.time() + timeout
    got = {}
    while time.time() < deadline:
        for i in indices:
            if i not in got:
                o = read_output(outdir, i)
                if o is not None:
                    got[i] = o
        if len(got) == len(indices):
            return got
        time.sleep(0.02)
    logs = ""
    for i in indices:
        if i not in got:
            try:
                with open(os.path.join(outdir, "log-%d.out" % i)) as f:
                    logs += "log-%d: %s\n" % (i, f.read()[-500:])
            except OSError:
                pass
    raise RuntimeError("outputs missing after %d s: %s\n%s" %
                       (timeout, sorted(set(indices) - set(got)), logs))


def run_local(worker, paths, parallel):
    """Runs the tasks with aalab-worker, `parallel` at a time; returns seconds to the last end."""
    env = dict(os.environ)
    env.pop("SLURM_CPUS_PER_TASK", None)
    t = time.time()
    todo = list(paths)
    running = []
    while todo or running:
        while todo and len(running) < parallel:
            p = todo.pop(0)
            running.append((p, subprocess.Popen([worker, p], env=env,
                                                stdout=subprocess.DEVNULL,
                                                stderr=subprocess.PIPE)))
        for item in list(running):
            if item[1].poll() is not None:
                running.remove(item)
                if item[1].returncode != 0:
                    raise RuntimeError("aalab-worker %s exited %d: %s" % (
                        item[0], item[1].returncode, item[1].stderr.read().decode()[-500:]))
        time.sleep(0.01)
    return time.time() - t


def stable(output):
    """A shard output as canonical JSON without its compute seconds (a clock reading)."""
    def strip(v):
        if isinstance(v, dict):
            return {k: strip(x) for k, x in v.items() if k != "seconds"}
        if isinstance(v, list):
            return [strip(x) for x in v]
        return v
    return json.dumps(strip(output), sort_keys=True)


def fmt(xs):
    return "median %.2f s, max %.2f s, min %.2f s" % (statistics.median(xs), max(xs), min(xs))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("aalabd")
    ap.add_argument("--trivial", type=int, default=20)
    ap.add_argument("--shards", type=int, default=16)
    ap.add_argument("--shard-iterations", type=int, default=3000)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--p16-iterations", type=int, default=500, help="0: skip (c)")
    a = ap.parse_args()
    aalabd = os.path.abspath(a.aalabd)
    worker = os.path.join(os.path.dirname(aalabd), "aalab-worker")
    if not os.access(worker, os.X_OK):
        say("bench_cluster: no aalab-worker beside %s" % aalabd)
        return 1
    cluster = slurm_cluster.start_or_skip()
    os.environ["SLURM_CONF"] = cluster.conf
    shared = tempfile.mkdtemp(prefix="aalab-bench-shared-")
    work = tempfile.mkdtemp(prefix="aalab-bench-")
    os.chmod(shared, 0o755)
    d = None
    try:
        maxt = max(a.trivial, a.shards)
        d = Daemon(aalabd, tcp=False, extra=["--workers", "2", "--slurm-shared-dir", shared,
                                             "--slurm-poll", "1", "--slurm-max-tasks", str(maxt)])
        d.shared = shared
        d.start()
        say("cluster: one node %s, %d CPUs, Slurm %s; aalabd %s; load average %.2f" % (
            cluster.hostname, cluster.cpus,
            subprocess.run(["sinfo", "-V"], capture_output=True, text=True).stdout.strip(), aalabd,
            os.getloadavg()[0]))

        # (a) per-task overhead
        trivial = {"kind": "optimize", "family": "P(1,4,1)", "seeds": a.trivial,
                   "max_iterations": 1, "rng_seed": 1}
        tasks, job_s = capture_tasks(d, trivial, a.trivial, keep_job=True)
        say("(a) daemon end to end: a job of %d trivial shards (executor slurm, one array, "
            "poll 1 s): %.1f s from POST to done" % (a.trivial, job_s))
        seq = os.path.join(work, "seq")
        paths = write_tasks(tasks, seq)
        lat = []
        for i in range(len(paths)):
            t = sbatch(cluster, seq, worker, str(i), "bench-seq")
            o = wait_outputs(seq, [i], 60)[i]
            lat.append(o["started_unix"] - t)
        say("(a) submission -> started_unix, %d single-task submissions one after another: %s"
            % (len(lat), fmt(lat)))
        arr = os.path.join(work, "arr")
        write_tasks(tasks, arr)
        t = sbatch(cluster, arr, worker, "0-%d" % (len(tasks) - 1), "bench-arr")
        outs = wait_outputs(arr, list(range(len(tasks))), 120)
        alat = [outs[i]["started_unix"] - t for i in outs]
        run_s = [outs[i]["finished_unix"] - outs[i]["started_unix"] for i in outs]
        say("(a) submission -> started_unix, one array of %d tasks on %d CPUs: %s "
            "(task run time median %.3f s)" % (len(alat), cluster.cpus, fmt(alat),
                                               statistics.median(run_s)))

        # (b) shards per minute, alternating local and Slurm runs of the same shards (the
        # machine may be shared: each round prints the load average it ran under)
        spec = {"kind": "optimize", "family": "P(1,16,8)", "seeds": a.shards,
                "max_iterations": a.shard_iterations, "rng_seed": 1}
        tasks, _ = capture_tasks(d, spec, a.shards)
        say("(b) %d shards of optimize P(1,16,8), 1 seed x %d iterations each, aalab-worker with "
            "1 thread; local: 2 at a time (the node's CPUs); Slurm: one array, --cpus-per-task=1"
            % (len(tasks), a.shard_iterations))
        say("    %-6s %-34s %8s %12s %16s %10s" % ("round", "", "seconds", "shards/min",
                                                   "shard median s", "load avg"))
        same = True
        rates = {"local": [], "slurm": []}
        for rnd in range(a.rounds):
            loc = os.path.join(work, "local-%d" % rnd)
            lpaths = write_tasks(tasks, loc)
            local_s = run_local(worker, lpaths, cluster.cpus)
            louts = [read_output(loc, i) for i in range(len(tasks))]
            lshard = [o["finished_unix"] - o["started_unix"] for o in louts]
            rates["local"].append(60 * len(tasks) / local_s)
            say("    %-6d %-34s %8.1f %12.1f %16.2f %10.2f" % (
                rnd, "local, aalab-worker 2 at a time", local_s, rates["local"][-1],
                statistics.median(lshard), os.getloadavg()[0]))
            sl = os.path.join(work, "slurm-%d" % rnd)
            write_tasks(tasks, sl)
            t = sbatch(cluster, sl, worker, "0-%d" % (len(tasks) - 1), "bench-tput")
            souts = wait_outputs(sl, list(range(len(tasks))), 600)
            slurm_s = max(o["finished_unix"] for o in souts.values()) - t
            sshard = [o["finished_unix"] - o["started_unix"] for o in souts.values()]
            rates["slurm"].append(60 * len(tasks) / slurm_s)
            say("    %-6d %-34s %8.1f %12.1f %16.2f %10.2f" % (
                rnd, "one-node Slurm, one array", slurm_s, rates["slurm"][-1],
                statistics.median(sshard), os.getloadavg()[0]))
            same = same and all(stable(louts[i]["output"]) == stable(souts[i]["output"])
                                for i in range(len(tasks)))
        lr, sr = statistics.median(rates["local"]), statistics.median(rates["slurm"])
        say("    median shards/min: local %.1f, Slurm %.1f, ratio slurm/local %.2f; shard outputs "
            "identical (but for compute seconds): %s" % (lr, sr, sr / lr, same))
        if not same:
            say("    ERROR: a shard's output differs between local and Slurm")
        if not a.p16_iterations:
            return 0 if same else 1

        # (c) one P(16,16,4) seed
        spec = {"kind": "optimize", "family": "P(16,16,4)", "seeds": 2,
                "max_iterations": a.p16_iterations, "rng_seed": 1}
        tasks, _ = capture_tasks(d, spec, 1)
        p16 = os.path.join(work, "p16")
        ppaths = write_tasks(tasks[:1], p16)
        wall = run_local(worker, ppaths, 1)
        o = read_output(p16, 0)
        say("(c) one P(16,16,4) seed, max_iterations %d, aalab-worker with 1 thread: %.1f s "
            "(worker's own started..finished %.1f s; load average %.2f)" % (
                a.p16_iterations, wall, o["finished_unix"] - o["started_unix"],
                os.getloadavg()[0]))
        return 0 if same else 1
    finally:
        if d is not None:
            try:
                d.cleanup()
            except Exception as e:
                say("daemon cleanup: %s" % e)
        cluster.stop()
        shutil.rmtree(shared, ignore_errors=True)
        shutil.rmtree(work, ignore_errors=True)
        left = cluster.leftovers()
        if left:
            say("ERROR: processes left: %r" % left)


if __name__ == "__main__":
    sys.exit(main())
