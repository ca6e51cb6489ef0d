"""End-to-end: the temporal-render job kind and POST /v1/predict with a temporal pattern (issue 30
point 5, docs/temporal.md section 9), through the daemon.
- Render check: Halton(2,3) x 8 at alpha 0.1 (preset halton23-8) against the grid-snapped optimized
  sequence of docs/temporal.md section 7 (E2 0.3032), rendered through the TAA loop on seven still
  scenes (the three half-planes of the spatial predictor's check in e2e_predict.py: 27, 63 and the
  pixel-locked 0 degrees; rings, Siemens star, spiral, sliver): the optimized sequence renders a
  lower steady-state RMSE (RMS over phases) on every one, the edge model's prediction of every
  phase is within 0.9-1.1 of the render, and so are its predictions of the flicker (about the
  mean, from F1; frame to frame, from the phases' differences) but on the locked edge.
- The job's predictions are POST /v1/predict's for the same body, its per-phase E2 POST
  /v1/evaluate's, its phases' RMSE POST /v1/render's of the phase (the spatial renderer on the
  phase's kernels) and a compare job's rows (one per phase) within 1e-5; the after-cut curve over 20 periods ends at its phase's steady state (1e-5).
- A box blend over the D3D 4x positions renders exactly the spatial D3D 4x (a compare job with the
  same reference): the same samples with weights 1/4, no flicker.
- A repeated offset has no flicker; the worst phase's tiles are PNGs; a large job is cancelled.
- Bad specs are 400s naming the field. Every answer is checked against its JSON Schema; figures are
  printed as '# figure:' lines. argv[1] is the aalabd binary."""

import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, ".."))

import aalabd_harness  # noqa: E402
import response_check  # noqa: E402
from aalabd_harness import Daemon  # noqa: E402

# docs/temporal.md section 7: bench_temporal 15 0 none 16 (1/16-pixel grid), E2 0.3032.
OPTIMIZED = [[0.25, 0.375], [-0.0625, -0.4375], [-0.5, 0.1875], [0.375, -0.1875],
             [0.0625, 0.5], [-0.375, -0.0625], [0.5, -0.5], [-0.25, 0.0625]]
SCENES = [
    ("half-plane-27", {"name": "half-plane", "width": 192, "height": 192, "angle": 27,
                       "offset": 0.37}),
    ("half-plane-63", {"name": "half-plane", "width": 192, "height": 192, "angle": 63,
                       "offset": -1.2}),
    ("half-plane-0-locked", {"name": "half-plane", "width": 128, "height": 128}),
    ("rings", {"name": "rings", "width": 256, "height": 256}),
    ("siemens-star", {"name": "siemens-star", "width": 256, "height": 256}),
    ("spiral", {"name": "spiral", "width": 256, "height": 256}),
    ("sliver", {"name": "sliver", "width": 256, "height": 256}),
]
REFERENCE = {"spp": 256}


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def submit(d, spec):
    r = d.request("POST", "/v1/jobs", spec)
    check(r.status == 202, "submitted: %d %s" % (r.status, r.body[:300]))
    return r.json()["id"]


def wait(d, jid, states=("done", "failed", "cancelled"), timeout=120):
    deadline = time.time() + timeout
    while True:
        j = d.request("GET", "/v1/jobs/%s" % jid).json()
        if j["state"] in states:
            return j
        check(time.time() < deadline, "job %s reached %s in time: %s" % (jid, states, j["state"]))
        time.sleep(0.1)


def run(d, spec):
    j = wait(d, submit(d, spec))
    check(j["state"] == "done", "job done: %s %s" % (j["state"], j.get("error")))
    # The job list's best E2 is the result's (issue 34: no "—" in the lists).
    listed = [x for x in d.request("GET", "/v1/jobs?limit=500").json()["jobs"] if x["id"] == j["id"]]
    check(j["kind"] != "temporal-render" or listed and listed[0]["best_e2"] == j["result"]["e2"] and
          listed[0]["family"] == "T(%d)" % len(j["result"]["phases"]), listed)
    return j["result"]


def post(d, path, body):
    r = d.request("POST", path, body)
    check(r.status == 200, "%s: %d %s" % (path, r.status, r.body[:300]))
    return r.json()


def expect_400(d, spec, field):
    r = d.request("POST", "/v1/jobs", spec)
    check(r.status == 400 and r.error_field() == field, (field, r.status, r.body[:300]))


def render_check(d):
    for label, scene in SCENES:
        mean = {}
        for name, temporal in (("halton", {"preset": "halton23-8"}),
                               ("optimized", {"jitter": OPTIMIZED})):
            pattern = {"temporal": temporal}
            # 20 periods after a cut: the first frame's share 0.9^159 = 5e-8.
            res = run(d, {"kind": "temporal-render", "scene": scene, "reference": REFERENCE,
                          "tiles": False, "pattern": {"temporal": dict(temporal, cut_frames=160)}})
            N = res["pattern"]["phase_count"]
            check(N == 8 and len(res["phases"]) == 8 and len(res["after_cut"]) == 160,
                  res["pattern"])
            pred = post(d, "/v1/predict", {"scene": scene, "pattern": pattern})["predictions"]
            check(len(pred) == N and [p["temporal"]["phase"] for p in pred] == list(range(N)),
                  "one prediction per phase")
            ev = post(d, "/v1/evaluate", {"pattern": pattern})
            check(abs(ev["e2"] - res["e2"]) <= 1e-12, (ev["e2"], res["e2"]))
            ratios = []
            for p, row, e in zip(pred, res["phases"], ev["phases"]):
                check(abs(p["predicted_rmse"] - row["predicted_rmse"]) <= 1e-9 * row["rmse"],
                      "the job's prediction is /v1/predict's")
                check(abs(e["e2"] - row["e2"]) <= 1e-12, "phase E2 is /v1/evaluate's")
                ratios.append(row["predicted_rmse"] / row["rmse"])
                check(abs(ratios[-1] - row["ratio"]) <= 1e-12, "ratio")
            check(min(ratios) >= 0.9 and max(ratios) <= 1.1,
                  "%s %s: predicted/rendered %.3f-%.3f outside 0.9-1.1" %
                  (label, name, min(ratios), max(ratios)))
            worst = res["steady"]["worst_phase"]
            check(res["steady"]["rmse"] == max(r["rmse"] for r in res["phases"]) ==
                  res["phases"][worst]["rmse"], "worst phase")
            last, steady = res["after_cut"][-1], res["phases"][159 % 8]["rmse"]
            check(abs(last - steady) <= 1e-5 * steady, (last, steady))
            settle = res["frames_to_5pct"]
            check(settle is None or 1 <= settle <= 160, settle)
            mean[name] = res["steady"]["mean_rmse"]
            # POST /v1/render of one phase (its kernels, the spatial renderer) is the loop's.
            for p in (0, N - 1):
                one = post(d, "/v1/render", {"scene": scene, "pattern": pattern, "phase": p,
                                             "reference": REFERENCE})
                check(one["temporal"] == {"phase": p, "phase_count": N}, one["temporal"])
                # The render request's body predicts that phase as is.
                body = {"scene": scene, "pattern": pattern, "phase": p, "reference": REFERENCE}
                alone = post(d, "/v1/predict", body)["predictions"]
                check(len(alone) == 1 and alone[0]["temporal"]["phase"] == p and
                      alone[0]["predicted_rmse"] == pred[p]["predicted_rmse"], alone)
                check(abs(one["stats"]["rmse"] - res["phases"][p]["rmse"]) <=
                      1e-5 * res["phases"][p]["rmse"] and one["e2"] == res["phases"][p]["e2"],
                      (label, name, p, one["stats"]["rmse"], res["phases"][p]["rmse"]))
            fl = res["flicker"]
            check(fl["mean_rmse"] == 0 or
                  abs(fl["ratio"] - fl["predicted_mean_rmse"] / fl["mean_rmse"]) <= 1e-12, fl)
            if "locked" not in label:  # a locked edge's offsets are not spread (temporal.md 9)
                check(0.9 <= fl["ratio"] <= 1.1 and 0.9 <= fl["step_ratio"] <= 1.1,
                      "%s %s: flicker predicted/rendered %.3f, frame to frame %.3f" %
                      (label, name, fl["ratio"], fl["step_ratio"]))
            print("# figure: %s %s: flicker predicted/rendered about the mean %s, frame to frame "
                  "%s" % (label, name, "%.3f" % fl["ratio"] if "ratio" in fl else "-",
                          "%.3f" % fl["step_ratio"] if "step_ratio" in fl else "-"))
            print("# figure: %s %s: E2 %.4f steady RMSE worst %.4f (phase %d) mean %.4f, "
                  "predicted mean %.4f (ratio %.3f, per phase %.3f-%.3f), flicker step %.3f "
                  "about mean %.3f (predicted %.3f), after cut k=1 %.3f, frames to 5%% %s" %
                  (label, name, res["e2"], res["steady"]["rmse"], worst, mean[name],
                   res["steady"]["predicted_rmse"], res["steady"]["ratio"], min(ratios),
                   max(ratios), res["flicker"]["step_rmse"], res["flicker"]["mean_rmse"],
                   res["flicker"]["predicted_mean_rmse"], res["after_cut"][0], settle))
        check(mean["optimized"] < mean["halton"], "%s: optimized %.4f not below Halton %.4f" %
              (label, mean["optimized"], mean["halton"]))
        print("# figure: %s optimized/Halton steady RMSE %.3f" %
              (label, mean["optimized"] / mean["halton"]))


def main():
    aalabd_harness.RESPONSE_HOOK = response_check.check
    d = Daemon(sys.argv[1], tcp=False).start()
    try:
        render_check(d)

        # The box blend over the D3D 4x positions is the spatial D3D 4x, rendered.
        scene = {"name": "rings", "width": 96, "height": 96}
        box = run(d, {"kind": "temporal-render", "scene": scene, "reference": REFERENCE,
                      "pattern": {"temporal": {"jitter": {"generator": "preset",
                                                          "preset": "d3d-4x"},
                                               "blend": {"kind": "box"}}}})
        spatial = run(d, {"kind": "compare", "scene": scene, "reference": REFERENCE,
                          "tiles": False, "patterns": ["d3d-4x"]})["rows"][0]
        for row in box["phases"]:
            check(abs(row["rmse"] - spatial["rmse"]) <= 1e-4, (row["rmse"], spatial["rmse"]))
            check(abs(row["e2"] - spatial["e2"]) <= 1e-12, (row["e2"], spatial["e2"]))
        check(box["flicker"]["step_rmse"] == 0 and box["flicker"]["mean_rmse"] == 0, "no flicker")
        print("# figure: box over D3D 4x positions %.6f, spatial D3D 4x %.6f" %
              (box["phases"][0]["rmse"], spatial["rmse"]))
        # A compare job renders a temporal pattern as one row per phase: the same as the loop's.
        h8 = {"temporal": {"preset": "halton23-8"}}
        loop = run(d, {"kind": "temporal-render", "scene": scene, "reference": REFERENCE,
                       "tiles": False, "pattern": h8})
        rows = run(d, {"kind": "compare", "scene": scene, "reference": REFERENCE, "tiles": False,
                       "patterns": ["rgss", h8]})["rows"]
        check([r["name"] for r in rows] ==
              ["rgss"] + ["halton23-8 phase %d" % p for p in range(8)], [r["name"] for r in rows])
        for row, ph in zip(rows[1:], loop["phases"]):
            check(abs(row["rmse"] - ph["rmse"]) <= 1e-5 * ph["rmse"] and row["e2"] == ph["e2"] and
                  abs(row["predicted_rmse"] - ph["predicted_rmse"]) <= 1e-9 * ph["rmse"],
                  (row, ph))
        # The tiles of the worst phase are PNGs.
        for key in ("pattern", "reference", "difference"):
            r = d.request("GET", box["tiles"][key]["url"])
            check(r.status == 200 and r.body[:8] == b"\x89PNG\r\n\x1a\n", key)

        # A repeated offset: every phase is the same image.
        same = run(d, {"kind": "temporal-render", "scene": scene, "reference": REFERENCE,
                       "tiles": False,
                       "pattern": {"temporal": {"jitter": [[0.2, -0.1]] * 6}}})
        check(same["flicker"]["step_rmse"] == 0 and same["flicker"]["mean_rmse"] == 0, "flicker")
        check(same["frames_to_5pct"] == 1, same["frames_to_5pct"])

        # Cancellation: N = 256 with a Gaussian resolve on a 1024 x 1024 spiral.
        jid = submit(d, {"kind": "temporal-render",
                         "scene": {"name": "spiral", "width": 1024, "height": 1024},
                         "pattern": {"temporal": {
                             "jitter": {"generator": "halton", "count": 256},
                             "resolve": {"filter": {"name": "gaussian"}}}}})
        wait(d, jid, states=("running",), timeout=30)
        time.sleep(0.5)
        t0 = time.time()
        r = d.request("DELETE", "/v1/jobs/%s" % jid)
        check(r.status == 202, "cancel accepted: %d" % r.status)
        j = wait(d, jid, states=("cancelled", "done", "failed"), timeout=10)
        check(j["state"] == "cancelled", "cancelled: %s" % j["state"])
        print("# figure: N = 256 resolved render cancelled in %.2f s" % (time.time() - t0))

        # Bad specs.
        base = {"kind": "temporal-render", "scene": "rings"}
        expect_400(d, dict(base, pattern="rgss"), "pattern")
        expect_400(d, dict(base, scene="rotating-triangle",
                           pattern={"temporal": {"preset": "halton23-8"}}), "scene.name")
        expect_400(d, dict(base, pattern={"temporal": {"preset": "halton23-8",
                                                       "blend": {"kind": "exponential",
                                                                 "alpha": 0}}}),
                   "pattern.temporal.blend.alpha")
        r = d.request("POST", "/v1/render", {"scene": "rings", "size": [32, 32], "phase": 8,
                                             "pattern": {"temporal": {"preset": "halton23-8"}}})
        check(r.status == 400 and r.error_field() == "phase", r.body[:300])
        r = d.request("POST", "/v1/jobs", {"kind": "compare", "scene": "rings", "patterns": [
            {"temporal": {"preset": "halton23-8", "blend": {"kind": "exponential"}}}]})
        check(r.status == 400 and r.error_field() == "patterns[0].temporal.blend.alpha",
              r.body[:300])
        reports = d.sanitizer_reports()
        check(not reports, "sanitizer reports: %s" % reports)
    finally:
        d.stop()


if __name__ == "__main__":
    main()
