"""End-to-end: the temporal pattern form of POST /v1/evaluate (issue 30, docs/temporal.md).
- Halton(2,3) x 8 from index 1 at alpha 0.1 (preset halton23-8 and the explicit generator):
  E2 0.482 worst phase and 0.459 mean, the issue's independent values to their three digits;
- a box blend over the D3D 4x positions (explicit offsets and the preset generator) answers the
  spatial D3D 4x E2 exactly;
- the FSR2 generator gives 18 / 23 / 32 / 72 phases at 1.5 / 1.7 / 2 / 3;
- a repeated offset has no flicker; alpha 1 has; the after-cut curve has 4 N values and ends
  within 5 % of the steady state;
- every preset answers with its provenance; a resolve and a frame pattern evaluate;
- bad inputs are 400s naming the field. Every answer is checked against its JSON Schema."""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, ".."))

import aalabd_harness  # noqa: E402
import response_check  # noqa: E402
from aalabd_harness import Daemon  # noqa: E402

PRESETS = ["halton23-8", "halton23-16", "fsr2-1.5x", "fsr2-1.7x", "fsr2-2x", "fsr2-3x",
           "urp-like", "filament-rgss4", "filament-halton8", "filament-halton16",
           "filament-halton32"]


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def evaluate(d, pattern, **extra):
    body = {"pattern": pattern}
    body.update(extra)
    r = d.request("POST", "/v1/evaluate", body)
    check(r.status == 200, (r.status, r.body[:400]))
    return r.json()


def expect_400(r, field):
    check(r.status == 400, (r.status, r.body[:300]))
    check(r.error_field() == field, (field, r.body[:300]))


def main():
    aalabd_harness.RESPONSE_HOOK = response_check.check
    d = Daemon(sys.argv[1], tcp=False).start()
    try:
        a = evaluate(d, {"temporal": {"preset": "halton23-8"}})
        b = evaluate(d, {"temporal": {"jitter": {"generator": "halton", "bases": [2, 3],
                                                 "start": 1, "count": 8},
                                      "blend": {"kind": "exponential", "alpha": 0.1}}})
        check(a["e2"] == b["e2"] and a["mean_phase_e2"] == b["mean_phase_e2"], (a["e2"], b["e2"]))
        check(abs(a["e2"] - 0.482) <= 0.0005 and abs(a["mean_phase_e2"] - 0.459) <= 0.0005,
              (a["e2"], a["mean_phase_e2"]))
        check(a["phase_count"] == 8 and len(a["phases"]) == 8 and len(a["after_cut"]) == 32, a)
        check(max(p["e2"] for p in a["phases"]) == a["e2"], "worst phase")
        check(abs(sum(p["age_weight"] for p in a["phases"]) - 1) <= 1e-15, "weights sum")
        check(abs(a["effective_samples"] - 1.9 * (1 - 0.9 ** 8) / (0.1 * (1 + 0.9 ** 8))) <= 1e-12,
              a["effective_samples"])
        check(len(a["phases"][0]["e1"][0]) == a["angle_count"] == len(a["f1"][0]), "rows")
        settle = a["frames_to_5pct"]
        check(isinstance(settle, int) and 1 <= settle <= 32, settle)
        last = a["after_cut"][-1]
        steady = a["phases"][31 % 8]["e2"]
        check(abs(last - steady) <= 0.05 * steady, (last, steady))
        check(a["preset"]["name"] == "halton23-8" and "FSR2" in a["preset"]["source"], a["preset"])
        print("halton23-8: E2 %.6f mean %.6f F2 %.6f frames to 5%% %s" %
              (a["e2"], a["mean_phase_e2"], a["f2"], settle))

        spatial = evaluate(d, {"preset": "d3d-4x"})["e2"]
        box = {"kind": "box"}
        gen = evaluate(d, {"temporal": {"jitter": {"generator": "preset", "preset": "d3d-4x"},
                                        "blend": box}})
        check(gen["e2"] == spatial and gen["f2"] == 0, (gen["e2"], spatial))
        offsets = gen["jitter"]
        exp = evaluate(d, {"temporal": {"jitter": offsets, "blend": box}})
        check(exp["e2"] == spatial, (exp["e2"], spatial))

        for scale, n in ((1.5, 18), (1.7, 23), (2, 32), (3, 72)):
            got = evaluate(d, {"temporal": {"jitter": {"generator": "fsr2", "scale": scale}}})
            check(got["phase_count"] == n, (scale, got["phase_count"]))

        rep = evaluate(d, {"temporal": {"jitter": [[0.1, -0.2]] * 8}})
        check(rep["f2"] == 0 and all(v == 0 for v in rep["f1"][0]), rep["f2"])
        one = evaluate(d, {"temporal": {"preset": "halton23-8",
                                        "blend": {"kind": "exponential", "alpha": 1}}})
        check(one["f2"] > 0 and one["effective_samples"] == 1, one["f2"])

        for name in PRESETS:
            got = evaluate(d, {"temporal": {"preset": name}})
            check(got["preset"]["source"], name)
            print("%-18s N %3d E2 %.4f mean %.4f F2 %.4f frames to 5%% %s" %
                  (name, got["phase_count"], got["e2"], got["mean_phase_e2"], got["f2"],
                   got["frames_to_5pct"]))
        msaa = evaluate(d, {"temporal": {"preset": "halton23-8",
                                         "frame_pattern": {"preset": "d3d-2x"}}})
        check(msaa["cost_spp"] == 2, msaa["cost_spp"])

        expect_400(d.request("POST", "/v1/evaluate", {"pattern": {"temporal": {
            "jitter": [[0, 0], [0.7, 0]]}}}), "pattern.temporal.jitter[1]")
        expect_400(d.request("POST", "/v1/evaluate", {"pattern": {"temporal": {
            "preset": "halton23-8", "blend": {"kind": "exponential", "alpha": 0}}}}),
            "pattern.temporal.blend.alpha")
        # A point format exports one phase's kernels: without a phase, 400 naming it (the
        # exports themselves: e2e_temporal_jobs).
        expect_400(d.request("POST", "/v1/patterns/export", {"pattern": {"temporal": {
            "preset": "halton23-8"}}, "format": "csv"}), "phase")
        check(not d.sanitizer_reports(), d.log_text())
    finally:
        d.stop()
    print("e2e_temporal: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
