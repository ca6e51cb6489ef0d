"""End-to-end: optimize jobs with a scene objective (issue 18 point 4, proto/job_scene_objective.h)
through the daemon. A job finishes and reports both figures (predicted RMSE on the scene and
global E2, beside the global-E2 optimum's); the predicted RMSE is POST /v1/predict's of the best
pattern and its E2 POST /v1/evaluate's; the objective is the documented blend; with
max_iterations only the result is reproducible; a bad objective is named; a running job with a
scene objective is cancelled promptly; `aalab optimize --scene` prints both figures. Answers are
checked against their schemas. argv[1]: aalabd, argv[2]: the aalab client."""

import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.dirname(HERE))
import aalabd_harness  # noqa: E402
import response_check  # noqa: E402

aalabd_harness.RESPONSE_HOOK = response_check.check

SCENE = {"name": "half-plane", "width": 96, "height": 96, "angle": 30, "offset": 0.37}


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def wait(d, jid, states=("done", "failed", "cancelled"), timeout=120):
    deadline = time.time() + timeout
    while True:
        j = d.request("GET", "/v1/jobs/%s" % jid).json()
        if j["state"] in states:
            return j
        check(time.time() < deadline, "job %s reached %s in time: %s" % (jid, states, j["state"]))
        time.sleep(0.1)


def submit(d, spec):
    r = d.request("POST", "/v1/jobs", spec)
    check(r.status == 202, "submitted: %d %s" % (r.status, r.body[:300]))
    return r.json()["id"]


def main():
    d = aalabd_harness.Daemon(sys.argv[1], workers=2, tcp=False).start()
    try:
        spec = {"kind": "optimize", "family": "P(1,1,4)", "seeds": 2, "max_iterations": 300,
                "objective": {"scene": SCENE, "blend": 0.25}}
        j = wait(d, submit(d, spec))
        check(j["state"] == "done", "scene job done: %s" % j.get("error"))
        res = j["result"]
        so = res["scene_objective"]
        opt = so["e2_optimum"]
        check(res["reproducible"] is True and res["shards"] == 1, "one reproducible shard")
        check(so["e2"] == res["e2"], "scene_objective.e2 is the result's e2")
        check(so["objective"] <= 1 + 1e-12, "F <= 1 (F = 1 at the E2 optimum it starts from)")
        want = 0.75 * so["predicted_rmse"] / opt["predicted_rmse"] + 0.25 * so["e2"] / opt["e2"]
        check(abs(so["objective"] - want) <= 1e-9 * want, "F is the documented blend")
        pred = d.request("POST", "/v1/predict", {"scene": SCENE, "pattern": res["best"]}).json()
        check(abs(pred["predictions"][0]["predicted_rmse"] - so["predicted_rmse"]) <= 1e-9,
              "predicted_rmse is /v1/predict's")
        ev = d.request("POST", "/v1/evaluate", {"pattern": res["best"]}).json()
        check(abs(ev["e2"] - res["e2"]) <= 1e-9, "e2 is /v1/evaluate's")
        check(j["best"]["e2"] is not None, "the job lists its best")
        print("# figure: P(1,1,4) on a 30-degree half-plane, blend 0.25: predicted RMSE %.4f "
              "(E2 optimum %.4f), E2 %.4f (E2 optimum %.4f), objective %.4f"
              % (so["predicted_rmse"], opt["predicted_rmse"], so["e2"], opt["e2"],
                 so["objective"]))
        # blend 0: the scene alone; the same spec again gives the same bits.
        spec0 = dict(spec, objective={"scene": SCENE})
        a = wait(d, submit(d, spec0))["result"]
        b = wait(d, submit(d, spec0))["result"]
        check(a["best"] == b["best"] and a["scene_objective"] == b["scene_objective"],
              "reproducible with max_iterations only")
        check(a["scene_objective"]["predicted_rmse"] <= opt["predicted_rmse"] + 1e-12,
              "blend 0 predicts no worse than the E2 optimum")
        # Bad objectives are named.
        bad = d.request("POST", "/v1/jobs", dict(spec, objective={"scene": "rings", "blend": 3}))
        check(bad.status == 400 and bad.error_field() == "objective.blend", "bad blend named")
        bad = d.request("POST", "/v1/jobs", dict(spec, objective={"blend": 0}))
        check(bad.status == 400 and bad.error_field() == "objective.scene", "no scene named")
        # Cancellation: a long job with a scene objective stops promptly.
        jid = submit(d, {"kind": "optimize", "family": "P(4,4,2)", "seeds": 4, "max_seconds": 60,
                         "objective": {"scene": "siemens-star", "blend": 0.5}})
        wait(d, jid, states=("running",), timeout=30)
        time.sleep(0.5)
        t0 = time.time()
        r = d.request("DELETE", "/v1/jobs/%s" % jid)
        check(r.status == 202, "cancel accepted: %d" % r.status)
        j = wait(d, jid, states=("cancelled", "done", "failed"), timeout=10)
        check(j["state"] == "cancelled", "cancelled: %s" % j["state"])
        print("# figure: cancelled in %.2f s" % (time.time() - t0))
        # The client prints both figures.
        if len(sys.argv) > 2:
            out = subprocess.run(
                [sys.argv[2], "--socket", d.socket_path, "optimize", "--family", "P(1,1,4)",
                 "--seeds", "1", "--max-iterations", "100", "--scene", "half-plane", "--angle",
                 "2", "--size", "64x64", "--blend", "0.5", "--wait"],
                capture_output=True, text=True, timeout=120)
            check(out.returncode == 0, "aalab optimize --scene: %s" % out.stderr)
            for label in ("predicted RMSE", "E2-optimum E2", "E2-optimum predicted RMSE",
                          "objective"):
                check(label in out.stdout, "client prints %s: %s" % (label, out.stdout))
        reports = d.sanitizer_reports()
        check(not reports, "sanitizer reports: %s" % reports)
    finally:
        d.stop()
    print("e2e_optimize_scene: ok")


if __name__ == "__main__":
    main()
