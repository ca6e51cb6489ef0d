#!/usr/bin/env python3
"""Fake aalab-worker for the sleep kind's split (tests/cluster, and e2e tests before the real
worker): reads TASK.json, sleeps, writes a trace and the output atomically. Lower indices sleep
longer so outputs arrive out of shard order. Controlled by files in $FAKE_SLURM_DIR (or
$FAKE_WORKER_DIR): fail-once-<stage>-<i> (removed, exit 1), fail-always-<stage>-<i> (exit 70)."""
import json, os, socket, sys, time

def write_atomic(path, obj):
    tmp = "%s.tmp.%d" % (path, os.getpid())
    with open(tmp, "w") as f:
        json.dump(obj, f)
        f.flush()
        os.fsync(f.fileno())
    os.rename(tmp, path)

def main():
    if len(sys.argv) != 2:
        print("usage: fake_worker.py TASK.json", file=sys.stderr)
        return 64
    try:
        task = json.load(open(sys.argv[1]))
    except Exception as e:
        print("fake worker: cannot read %s: %s" % (sys.argv[1], e), file=sys.stderr)
        return 65
    ctl = os.environ.get("FAKE_WORKER_DIR") or os.environ.get("FAKE_SLURM_DIR") or "/nonexistent"
    stage, i = task["stage"], task["shard_index"]
    print("fake worker: job %d stage %d shard %d on %s" % (task["job_id"], stage, i, socket.gethostname()))
    sys.stdout.flush()
    once = os.path.join(ctl, "fail-once-%d-%d" % (stage, i))
    if os.path.exists(once):
        os.unlink(once)
        print("fake worker: shard %d fails once" % i, file=sys.stderr)
        return 1
    if os.path.exists(os.path.join(ctl, "fail-always-%d-%d" % (stage, i))):
        print("fake worker: shard %d always fails" % i, file=sys.stderr)
        return 70
    t0 = time.time()
    seconds = float(task["shard"]["seconds"]) * (4 - i) / 2.0
    e2 = 1.0 / (i + 2)
    steps = 10 * (i + 1)
    points = [{"seconds": 0.0, "iterations": 0, "evaluations": 0, "best_e2": 1.0}]
    write_atomic(task["trace"], {"format": "aalab-shard-trace/1", "started_unix": t0, "progress": 0.0, "points": points})
    time.sleep(max(seconds, 0.0))
    points.append({"seconds": time.time() - t0, "iterations": steps, "evaluations": steps, "best_e2": e2})
    write_atomic(task["trace"], {"format": "aalab-shard-trace/1", "started_unix": t0, "progress": 1.0, "points": points})
    write_atomic(task["output"], {"format": "aalab-shard-output/1", "job_id": task["job_id"], "stage": stage,
                                  "shard_index": i, "host": socket.gethostname(), "started_unix": t0,
                                  "finished_unix": time.time(),
                                  "output": {"index": i, "steps": steps, "e2": e2}})
    return 0

if __name__ == "__main__":
    sys.exit(main())
