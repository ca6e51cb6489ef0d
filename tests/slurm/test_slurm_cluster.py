#!/usr/bin/env python3
"""The one-node test cluster itself (tests/slurm/slurm_cluster.py): it starts, runs a job array
of this machine's CPU count x 2 tasks (each prints its array index and host), survives a cancel,
and stop() leaves no process and no directory behind. Skips (exit 77, reason printed) where the
cluster cannot start; AALAB_REQUIRE_SLURM=1 makes that a failure."""

import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import slurm_cluster  # noqa: E402


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def sbatch(c, args, script):
    p = subprocess.run(["sbatch", "--parsable"] + args + ([script] if script else []), env=c.env(),
                       capture_output=True, text=True, timeout=30)
    check(p.returncode == 0, "sbatch %s: %s" % (args, p.stderr))
    return p.stdout.strip().split(";")[0]


def main():
    c = slurm_cluster.start_or_skip()
    root = c.root
    out = tempfile.mkdtemp(prefix="aalab-slurm-out-")
    try:
        print("cluster up in %s: node %s %s, %d CPUs" % (root, c.hostname, c.node_state(), c.cpus))
        script = os.path.join(out, "task.sh")
        with open(script, "w") as f:
            f.write("#!/bin/sh\necho \"$SLURM_ARRAY_TASK_ID $(hostname)\"\n")
        n = 2 * c.cpus
        t = time.time()
        arr = sbatch(c, ["--array=0-%d" % (n - 1), "--output=%s/log-%%a.out" % out,
                         "--job-name=fixture"], script)
        deadline = time.time() + 60
        while time.time() < deadline and c.squeue("-j", arr):
            time.sleep(0.2)
        check(not c.squeue("-j", arr), "array %s still queued after 60 s" % arr)
        for i in range(n):
            with open(os.path.join(out, "log-%d.out" % i)) as f:
                idx, host = f.read().split()
            check(idx == str(i) and host.split(".")[0] == c.hostname, (i, idx, host))
        print("array %s of %d tasks ran in %.1f s" % (arr, n, time.time() - t))
        # a long task: cancelled, it leaves squeue within KillWait
        long = sbatch(c, ["--output=%s/long.out" % out, "--wrap=sleep 300"], "")
        deadline = time.time() + 30
        while time.time() < deadline and not c.squeue("-j", long, "-t", "R"):
            time.sleep(0.2)
        check(c.squeue("-j", long, "-t", "R"), "the long task never ran")
        subprocess.run(["scancel", long], env=c.env(), check=True)
        deadline = time.time() + 20
        while time.time() < deadline and c.squeue("-j", long):
            time.sleep(0.2)
        check(not c.squeue("-j", long), "cancelled task still in squeue")
        # another long one left running: stop() must end it
        sbatch(c, ["--output=%s/long2.out" % out, "--wrap=sleep 300"], "")
        deadline = time.time() + 30
        while time.time() < deadline and not c.squeue("-t", "R"):
            time.sleep(0.2)
    finally:
        killed = c.stop()
        subprocess.run(["rm", "-rf", out])
    left = c.leftovers()
    check(not left, "processes left after stop: %r" % left)
    check(not os.path.exists(root), "cluster directory left: %s" % root)
    print("stopped: no process left%s" % (" (SIGKILL needed for %r)" % killed if killed else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
