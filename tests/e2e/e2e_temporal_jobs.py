"""End-to-end: the temporal-optimize job kind and the export of temporal patterns (issue 30,
docs/temporal.md sections 6-7) against a running aalabd:
- T(8) at alpha 0.1, 2 seeds of 6 steps per level with max_iterations: done, E2 below Halton's,
  reproducible (a second job, and one on a daemon with one worker, which runs the seeds one at a
  time instead of in parallel, give the same sequence and E2 to the last bit),
  its best re-evaluated by POST /v1/evaluate (posted, and as {"job": ID}) gives the result's e2,
  mean_phase_e2 and f2 exactly, per-seed table and trace present;
- from a given sequence (preset halton23-8) with a 1/16 grid: start_e2 is Halton's, the first seed
  is the given one, the offsets lie on the grid;
- N = 12 (pairwise swaps) with a flicker weight: done;
- a long job is cancelled promptly, with its best so far;
- bad specs are 400s naming the field; other kinds answer 400 naming pattern.temporal;
- exports: json round trip, jitter-c / jitter-hlsl text, per-phase kernels in the point formats,
  400 naming the field where a format makes no sense.
Every answer is checked against its JSON Schema (e2e_lib's response check)."""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from e2e_lib import Daemon, check, expect_error  # noqa: E402

T8 = {"kind": "temporal-optimize", "family": "T(8)", "blend": {"kind": "exponential", "alpha": 0.1},
      "seeds": 2, "max_iterations": 6}


def run_job(d, spec, timeout=120):
    r = d.post("/v1/jobs", spec)
    check(r.status == 202, r)
    j = d.wait_job(r.json()["id"], timeout=timeout)
    check(j["state"] == "done", j)
    return j


def evaluate(d, pattern):
    r = d.post("/v1/evaluate", {"pattern": pattern})
    check(r.status == 200, r)
    return r.json()


def check_job(d, spec):
    t0 = time.time()
    j = run_job(d, spec)
    wall = time.time() - t0
    res = j["result"]
    halton = evaluate(d, {"temporal": {"preset": "halton23-8"}})
    check(res["e2"] < halton["e2"], (res["e2"], halton["e2"]))
    check(res["family"] == "T(8)" and j["family"] == "T(8)", j)
    check(res["reproducible"] is True and res["seeds_run"] == spec["seeds"], res)
    check(len(res["per_seed"]) == spec["seeds"] and len(res["phase_e2"]) == 8, res)
    check(abs(max(res["phase_e2"]) - res["e2"]) == 0, res)
    check(j["trace"] and j["trace"][-1]["best_e2"] <= j["trace"][0]["best_e2"], j["trace"])
    # Round trip: the result's best evaluates to its figures bit for bit, posted or by reference.
    for pattern in (res["best"], {"job": j["id"]}):
        ev = evaluate(d, pattern)
        check(ev["e2"] == res["e2"] and ev["mean_phase_e2"] == res["mean_phase_e2"] and
              ev["f2"] == res["f2"], (ev["e2"], ev["mean_phase_e2"], ev["f2"], res))
    check(j["best_e2"] is None or abs(j["best_e2"] - res["e2"]) < 1e-12, j)
    print("temporal-optimize T(8), alpha 0.1, 2 seeds x 6 steps: E2 %.4f (Halton %.4f, ratio "
          "%.3f), mean %.4f, F2 %.4f (Halton %.4f), %.2f s job, %.1f s wall" %
          (res["e2"], halton["e2"], res["e2"] / halton["e2"], res["mean_phase_e2"], res["f2"],
           halton["f2"], res["seconds"], wall))
    return j


def test_jobs(d, binary):
    a = check_job(d, T8)
    b = run_job(d, T8)
    check(a["result"]["best"] == b["result"]["best"] and a["result"]["e2"] == b["result"]["e2"],
          "same spec, different results")
    # The seeds run in batches as wide as the idle workers: one worker, one seed at a time, and
    # the same result to the last bit.
    one = Daemon(binary, tcp=False, extra=["--workers", "1"]).start()
    try:
        c = run_job(one, T8)
    finally:
        one.cleanup()
    check(c["result"]["best"] == a["result"]["best"] and c["result"]["e2"] == a["result"]["e2"] and
          c["result"]["per_seed"] == a["result"]["per_seed"], "1 worker and 2 differ")
    # From a given sequence on a 1/16 grid.
    r = run_job(d, {"kind": "temporal-optimize", "pattern": {"temporal": {"preset": "halton23-8"}},
                    "seeds": 1, "max_iterations": 6, "grid": {"bits": 4}})["result"]
    halton = evaluate(d, {"temporal": {"preset": "halton23-8"}})
    check(r["start_e2"] == halton["e2"] and r["per_seed"][0]["start"] == "given", r)
    check(r["grid"] == {"bits": 4, "step": 0.0625}, r)
    for x, y in r["best"]["temporal"]["jitter"]:
        check(x * 16 == round(x * 16) and y * 16 == round(y * 16), (x, y))
    check(r["e2"] < halton["e2"], r)
    print("from halton23-8 on a 1/16 grid: E2 %.4f -> %.4f" % (r["start_e2"], r["e2"]))
    # N = 12 (order by pairwise swaps) with a flicker weight.
    r = run_job(d, {"kind": "temporal-optimize", "family": "T(12)", "flicker_weight": 2,
                    "seeds": 1, "max_iterations": 3})["result"]
    check(r["objective"] == "e2 + 2 f2" and abs(r["score"] - (r["e2"] + 2 * r["f2"])) < 1e-9, r)
    # A long job is cancelled promptly and keeps its best so far.
    r = d.post("/v1/jobs", {"kind": "temporal-optimize", "family": "T(12)", "seeds": 100000,
                            "max_seconds": 600})
    jid = r.json()["id"]
    d.wait_job(jid, states=("running",))
    deadline = time.time() + 240  # the first batch's end (slow under the sanitizers)
    while time.time() < deadline and not d.get("/v1/jobs/%d" % jid).json().get("best"):
        time.sleep(0.1)
    t0 = time.time()
    check(d.delete("/v1/jobs/%d" % jid).status == 202, "cancel")
    j = d.wait_job(jid, timeout=10)
    check(j["state"] == "cancelled", j)
    check(j["best"] and "temporal" in j["best"]["pattern"], j)
    print("cancel of a running T(12) job took %.2f s" % (time.time() - t0))


BAD = [
    ({"kind": "temporal-optimize"}, "family"),
    ({"kind": "temporal-optimize", "family": "T(0)"}, "family"),
    ({"kind": "temporal-optimize", "family": "T(300)"}, "family"),
    ({"kind": "temporal-optimize", "family": "P(1,1,1)"}, "family"),
    ({"kind": "temporal-optimize", "family": "T(8)", "pattern": {"preset": "rgss"}}, "family"),
    ({"kind": "temporal-optimize", "pattern": {"preset": "rgss"}}, "pattern"),
    ({"kind": "temporal-optimize", "pattern": {"temporal": {"preset": "halton23-8"}},
      "blend": {"kind": "box"}}, "blend"),
    ({"kind": "temporal-optimize", "pattern": {"temporal": {"preset": "nope"}}},
     "pattern.temporal.preset"),
    ({"kind": "temporal-optimize", "family": "T(8)", "blend": {"kind": "exponential",
                                                              "alpha": 2}}, "blend.alpha"),
    ({"kind": "temporal-optimize", "family": "T(8)", "resolve": {"filter": {"name": "x"}}},
     "resolve.filter.name"),
    ({"kind": "temporal-optimize", "family": "T(8)", "seeds": 0}, "seeds"),
    ({"kind": "temporal-optimize", "family": "T(8)", "grid": {"bits": 13}}, "grid.bits"),
    ({"kind": "temporal-optimize", "family": "T(8)", "grid": {"bits": 4, "d3d12": True}}, "grid"),
    ({"kind": "temporal-optimize", "family": "T(8)", "order": "random"}, "order"),
    ({"kind": "temporal-optimize", "family": "T(8)", "flicker_weight": -1}, "flicker_weight"),
    ({"kind": "temporal-optimize", "family": "T(8)", "flicker_cap": 0.1}, "flicker_cap"),
    ({"kind": "temporal-optimize", "family": "T(8)", "flicker_weight": 1,
      "resolve": {"filter": {"name": "gaussian"}}}, "flicker_weight"),
    ({"kind": "temporal-optimize", "family": "T(8)", "method": "minimax"}, "method"),
    ({"kind": "temporal-optimize", "family": "T(8)", "max_iterations": 0}, "max_iterations"),
    ({"kind": "optimize", "pattern": {"temporal": {"preset": "halton23-8"}}}, "pattern.temporal"),
    ({"kind": "animation", "scene": "rotating-triangle",
      "pattern": {"temporal": {"preset": "halton23-8"}}}, "pattern.temporal"),
    ({"kind": "optimize", "family": "T(8)"}, "family"),
    ({"kind": "random-stats", "family": "T(8)"}, "family"),
    ({"kind": "table3", "family": "T(8)"}, "family"),
]


def test_bad(d):
    for body, field in BAD:
        e = expect_error(d.post("/v1/jobs", body), 400, field)
        if body["kind"] != "temporal-optimize" and field == "family":
            check("temporal-optimize" in e["message"], e)


def export(d, body):
    return d.post("/v1/patterns/export", body)


def test_exports(d):
    h8 = {"temporal": {"preset": "halton23-8"}}
    ev = evaluate(d, h8)
    # json: the explicit form, which evaluates to the same figures bit for bit.
    r = export(d, {"pattern": h8, "format": "json"})
    check(r.status == 200, r)
    p = r.json()["pattern"]
    check(len(p["temporal"]["jitter"]) == 8 and p["temporal"]["blend"]["alpha"] == 0.1, p)
    ev2 = evaluate(d, p)
    check(ev2["e2"] == ev["e2"] and ev2["f2"] == ev["f2"], (ev, ev2))
    # jitter-c / jitter-hlsl: the offsets (Halton(2,3) index 1: (0, -1/6)), alpha, age weights,
    # and the exact wire form on the first line.
    for fmt, needle in (("jitter-c", "static const float aalab_jitter[AALAB_JITTER_COUNT][2]"),
                        ("jitter-hlsl", "static const float2 AalabJitter[8]")):
        r = export(d, {"pattern": h8, "format": fmt})
        check(r.status == 200 and r.headers.get("content-type", "").startswith("text/plain"), r)
        check(needle in r.body and "0.1" in r.body and "-0.166666667" in r.body, r.body[:600])
        first = r.body.splitlines()[0]
        check(first.startswith("// aalab-temporal "), first)
        wire = json.loads(first[len("// aalab-temporal "):])
        check(evaluate(d, wire)["e2"] == ev["e2"], "jitter-c wire form")
        if fmt == "jitter-c" and shutil.which("cc"):
            with tempfile.NamedTemporaryFile("w", suffix=".c") as src:
                src.write(r.body + "int main(void) { return (int)(aalab_jitter[1][0] * 4 + "
                          "aalab_blend_alpha * aalab_age_weight[0]); }\n")
                src.flush()
                cc = subprocess.run(["cc", "-std=c11", "-Wall", "-Werror", "-fsyntax-only",
                                     src.name], capture_output=True, text=True)
                check(cc.returncode == 0, cc.stderr)
    box = export(d, {"pattern": {"temporal": {"jitter": [[0, 0], [0.25, 0.25]],
                                              "blend": {"kind": "box"}}}, "format": "jitter-c"})
    check(box.status == 200 and "AALAB_BLEND_BOX" in box.body, box)
    # A phase's kernels in the point formats: phase 0 of a box blend over the D3D 4x positions is
    # the D3D 4x kernel, whose csv evaluates to the spatial E2.
    d3d = {"temporal": {"jitter": {"generator": "preset", "preset": "d3d-4x"},
                        "blend": {"kind": "box"}}}
    r = export(d, {"pattern": d3d, "format": "csv", "phase": 0})
    check(r.status == 200, r)
    e_csv = d.post("/v1/evaluate", {"pattern": {"points": {"format": "csv", "text": r.body}}})
    spatial = evaluate(d, {"preset": "d3d-4x"})
    check(e_csv.status == 200 and abs(e_csv.json()["e2"] - spatial["e2"]) < 1e-12,
          (e_csv, spatial["e2"]))
    r = export(d, {"pattern": h8, "format": "xyw", "phase": 3})
    check(r.status == 200 and len([x for x in r.body.splitlines() if not x.startswith("#")]) == 8,
          r)
    # A job's best, by GET and by reference.
    j = run_job(d, dict(T8, seeds=1, max_iterations=2))
    r = d.get("/v1/patterns/%d/export?format=json" % j["id"])
    check(r.status == 200 and r.json()["job"] == j["id"] and
          r.json()["pattern"] == j["result"]["best"], r)
    r = d.get("/v1/patterns/%d/export?format=jitter-hlsl" % j["id"])
    check(r.status == 200 and "AalabJitter" in r.body, r)
    r = d.get("/v1/patterns/%d/export?format=utk&phase=7" % j["id"])
    check(r.status == 200, r)
    expect_error(d.get("/v1/patterns/%d/export?format=utk" % j["id"]), 400, "phase")
    expect_error(d.get("/v1/patterns/%d/export?format=utk&phase=8" % j["id"]), 400, "phase")
    expect_error(d.get("/v1/patterns/%d/export?format=csv&phase=x" % j["id"]), 400, "phase")
    expect_error(d.get("/v1/patterns/%d/export?format=vulkan" % j["id"]), 400, "format")
    r = export(d, {"pattern": {"job": j["id"]}, "format": "jitter-c"})
    check(r.status == 200 and "aalab_jitter" in r.body, r)
    # Where it makes no sense: 400 naming the field.
    for body, field in (
            ({"pattern": h8, "format": "vulkan"}, "format"),
            ({"pattern": h8, "format": "d3d12"}, "format"),
            ({"pattern": h8, "format": "csv"}, "phase"),
            ({"pattern": h8, "format": "csv", "phase": 8}, "phase"),
            ({"pattern": h8, "format": "csv", "phase": -1}, "phase"),
            ({"pattern": h8, "format": "csv", "phase": 1.5}, "phase"),
            ({"pattern": h8, "format": "json", "phase": 0}, "phase"),
            ({"pattern": h8, "format": "jitter-c", "phase": 0}, "phase"),
            ({"pattern": h8, "format": "bogus"}, "format"),
            ({"pattern": {"preset": "rgss"}, "format": "jitter-c"}, "format"),
            ({"pattern": {"preset": "rgss"}, "format": "csv", "phase": 0}, "phase"),
            ({"pattern": {"temporal": {"preset": "nope"}}, "format": "json"},
             "pattern.temporal.preset")):
        expect_error(export(d, body), 400, field)
    expect_error(d.get("/v1/patterns/%d/export?format=bogus" % j["id"]), 400, "format")
    print("exports: json, jitter-c, jitter-hlsl, per-phase point formats ok")


def main():
    d = Daemon(sys.argv[1], tcp=False).start()
    try:
        test_bad(d)
        test_exports(d)
        test_jobs(d, sys.argv[1])
    except BaseException:
        print(d.log_text()[-4000:])
        raise
    finally:
        d.cleanup()
    print("e2e_temporal_jobs: ok")


if __name__ == "__main__":
    main()
