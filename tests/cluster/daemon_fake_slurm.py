"""aalabd with executor "slurm" against the fake Slurm commands of this directory (fake_slurm/,
on PATH) and the fake worker, with the test kind "sleep": health, 503 slurm_unavailable, 400 for
a kind without a split, a job run to the end, cancel, re-attach after SIGTERM and after kill -9,
a shard failing twice, Slurm not answering, --max-job-seconds.
Every answer is checked against its schema (tests/e2e/response_check.py).
usage: daemon_fake_slurm.py AALABD"""

import atexit
import os
import shutil
import signal
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "e2e"))
from e2e_lib import Daemon, check, expect_error  # noqa: E402


def lines(path):
    try:
        with open(path) as f:
            return f.read().splitlines()
    except OSError:
        return []


def wait(cond, what, timeout=30):
    deadline = time.time() + timeout
    while time.time() < deadline:
        if cond():
            return
        time.sleep(0.05)
    raise AssertionError("timed out waiting for " + what)


def submit(d, seconds, status=202, **extra):
    body = {"kind": "sleep", "seconds": seconds, "executor": "slurm"}
    body.update(extra)
    r = d.post("/v1/jobs", body)
    check(r.status == status, r)
    return r


def stop_fake_tasks(fake):
    """Kills every fake array element that may still run (each is a session of its own: setsid
    in sbatch), so that none writes into a directory being removed (seen: a worker's stage
    output landing in shared/ after the daemon's directory was removed)."""
    piddir = os.path.join(fake, "pid")
    for name in os.listdir(piddir) if os.path.isdir(piddir) else []:
        try:
            with open(os.path.join(piddir, name)) as f:
                os.killpg(int(f.read()), signal.SIGKILL)
        except (OSError, ValueError):
            pass  # gone already


def remove_fake(fake):
    stop_fake_tasks(fake)
    for _ in range(20):  # a dying task may still drop a file while the tree goes
        shutil.rmtree(fake, True)
        if not os.path.exists(fake):
            return
        time.sleep(0.1)


def cleanup(d, fake):
    stop_fake_tasks(fake)
    d.cleanup()


def main():
    binary = sys.argv[1]
    fake = tempfile.mkdtemp(prefix="aalab-fake-slurm-")
    atexit.register(remove_fake, fake)  # the fake queue and logs, whatever the outcome
    os.environ["FAKE_SLURM_DIR"] = fake
    os.environ["PATH"] = os.path.join(HERE, "fake_slurm") + ":" + os.environ.get("PATH", "/usr/bin:/bin")
    sbatch_log = os.path.join(fake, "sbatch.log")
    scancel_log = os.path.join(fake, "scancel.log")

    # Not configured: health says so and a Slurm submit is a 503 naming executor.
    d = Daemon(binary, tcp=False)
    d.start()
    try:
        s = d.get("/v1/health").json()["slurm"]
        check(s["configured"] is False and s["answering"] is None, s)
        e = expect_error(submit(d, 0.1, status=503), 503, "executor")
        check(e["code"] == "slurm_unavailable" and "not configured" in e["message"], e)
        expect_error(d.post("/v1/jobs", {"kind": "sleep", "seconds": 0.1, "executor": "cloud"}), 400,
                     "executor")
    finally:
        d.cleanup()

    root = tempfile.mkdtemp(prefix="aalab-e2e-slurm-")
    shared = os.path.join(root, "shared")
    extra = ["--slurm-shared-dir", shared, "--slurm-worker", os.path.join(HERE, "fake_worker.py"),
             "--slurm-poll", "0.2", "--slurm-max-tasks", "4", "--slurm-time-limit", "7",
             "--slurm-partition", "debug"]
    d = Daemon(binary, root=root, tcp=False, extra=extra)
    d.start()
    try:
        wait(lambda: d.get("/v1/health").json()["slurm"]["answering"] is True, "slurm answering")
        # A kind without a split.
        expect_error(d.post("/v1/jobs", {"kind": "compare", "executor": "slurm"}), 400, "executor")

        # A whole job.
        job = submit(d, 0.4).json()
        j = d.wait_job(job["id"], timeout=60)
        check(j["state"] == "done", j)
        check(j["executor"] == "slurm" and j["result"]["steps"] == 100, j)
        check(abs(j["best"]["e2"] - 0.2) < 1e-12 and j["progress"] == 1, j)
        check(len(j["trace"]) >= 1, j)
        check(len(lines(sbatch_log)) == 1 and "--partition=debug" in lines(sbatch_log)[0], lines(sbatch_log))
        # Its shared files live as long as its record: a purge removes them.
        job_dir = os.path.join(shared, "job-%d" % job["id"])
        check(os.path.isdir(job_dir), "no %s after the job" % job_dir)
        r = d.delete("/v1/jobs/%d?purge=1" % job["id"])
        check(r.status in (200, 204), r)
        # The probe thread removes them, woken by the purge (not the handler itself).
        wait(lambda: not os.path.exists(job_dir), "%s removed after the purge" % job_dir)
        local = d.post("/v1/jobs", {"kind": "sleep", "seconds": 0.05}).json()
        check(d.wait_job(local["id"])["executor"] == "local", local)

        # Cancel: the array is scancelled and leaves the queue.
        job = submit(d, 60).json()
        wait(lambda: len(lines(sbatch_log)) == 2, "second sbatch")
        r = d.delete("/v1/jobs/%d" % job["id"])
        check(r.status in (200, 202), r)
        j = d.wait_job(job["id"], timeout=60)
        check(j["state"] == "cancelled", j)
        check(len(lines(scancel_log)) == 1, lines(scancel_log))
        check(not os.listdir(os.path.join(fake, "queue")), os.listdir(os.path.join(fake, "queue")))

        # SIGTERM: the array keeps running; the next start re-attaches.
        job = submit(d, 1.5).json()
        wait(lambda: len(lines(sbatch_log)) == 3, "third sbatch")
        check(d.stop() == 0, "clean exit")
        # The files of a job the daemon no longer has (deleted by retention, say) are swept.
        orphan = os.path.join(shared, "job-999999", "stage-0")
        os.makedirs(orphan)
        open(os.path.join(orphan, "output-0.json"), "w").close()
        d.start()
        wait(lambda: not os.path.exists(os.path.dirname(orphan)), "the orphan's files swept")
        j = d.wait_job(job["id"], timeout=60)
        check(j["state"] == "done" and j["result"]["steps"] == 100, j)
        check(len(lines(sbatch_log)) == 3 and len(lines(scancel_log)) == 1,
              (lines(sbatch_log), lines(scancel_log)))

        # kill -9: the same.
        wait(lambda: d.get("/v1/health").json()["slurm"]["answering"] is True, "slurm answering")
        job = submit(d, 1.5).json()
        wait(lambda: len(lines(sbatch_log)) == 4, "fourth sbatch")
        d.stop(sig=signal.SIGKILL)
        time.sleep(1.0)
        d.start()
        j = d.wait_job(job["id"], timeout=60)
        check(j["state"] == "done" and j["result"]["steps"] == 100, j)
        check(len(lines(sbatch_log)) == 4, lines(sbatch_log))

        # A shard that fails twice fails the job with its log tail.
        wait(lambda: d.get("/v1/health").json()["slurm"]["answering"] is True, "slurm answering")
        open(os.path.join(fake, "fail-always-0-3"), "w").close()
        job = submit(d, 0.2).json()
        j = d.wait_job(job["id"], timeout=60)
        check(j["state"] == "failed", j)
        m = j["error"]["message"]
        check("shard 3 of stage 0 failed twice" in m and "always fails" in m, j["error"])
        os.unlink(os.path.join(fake, "fail-always-0-3"))

        # Slurm stops answering: health says so within a probe interval, submit is a 503.
        open(os.path.join(fake, "down"), "w").close()
        wait(lambda: d.get("/v1/health").json()["slurm"]["answering"] is False, "slurm down", 20)
        e = expect_error(submit(d, 0.1, status=503), 503, "executor")
        check("not answering" in e["message"], e)
    finally:
        cleanup(d, fake)

    # --max-job-seconds stops a Slurm job too: its arrays are scancelled, the job fails with
    # time_limit.
    os.unlink(os.path.join(fake, "down"))
    root = tempfile.mkdtemp(prefix="aalab-e2e-slurm-")
    d = Daemon(binary, root=root, tcp=False,
               extra=extra[:1] + [os.path.join(root, "shared")] + extra[2:] + ["--max-job-seconds", "2"])
    d.start()
    try:
        wait(lambda: d.get("/v1/health").json()["slurm"]["answering"] is True, "slurm answering")
        cancels = len(lines(scancel_log))
        job = submit(d, 0.5).json()  # shards sleep up to 0.5 s: done well within 2 s
        check(d.wait_job(job["id"], timeout=60)["state"] == "done", job)
        job = submit(d, 60).json()
        j = d.wait_job(job["id"], timeout=60)
        check(j["state"] == "failed" and j["error"]["code"] == "time_limit", j)
        check(len(lines(scancel_log)) == cancels + 1, lines(scancel_log))
        check(not os.listdir(os.path.join(fake, "queue")), os.listdir(os.path.join(fake, "queue")))
    finally:
        cleanup(d, fake)
    print("daemon_fake_slurm: ok")


if __name__ == "__main__":
    main()
