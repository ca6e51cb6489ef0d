"""End-to-end: point-set figures per random pattern in random-stats and table3 (issue 31).
- A random-stats job with every figure: rho of each with E2 against scipy.stats.spearmanr on the
  result's own columns (1e-12; p-value 1e-9 relative where above 1e-250); the figures of the best
  random pattern against POST /v1/analyze of it; every answer against its schema (job.json with
  the kind's result schema and point_metrics.json); the same spec gives the same block.
- A table3 job: a block per distribution over every seed's patterns.
- Cancel and progress unchanged: a long job with figures reports progress and cancels.
- Bad specs: 400 naming metrics / metrics[i].
Needs python3-scipy; SKIP (77) without it."""

import json
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, ".."))

try:
    from scipy import stats
except ImportError as e:  # pragma: no cover
    print("SKIP: %s (python3-scipy)" % e)
    sys.exit(77)

import response_check  # noqa: E402
from aalabd_harness import Daemon  # noqa: E402

ALL = ["l2_star", "centered", "wrap_around", "mixture", "star_linf", "min_distance",
       "mean_nn_distance", "min_distance_normalized", "mean_nn_distance_normalized",
       "effective_nyquist", "effective_nyquist_normalized", "oscillation"]
# /v1/analyze's answer: where each figure sits
WHERE = {"l2_star": ("discrepancy",), "centered": ("discrepancy",),
         "wrap_around": ("discrepancy",), "mixture": ("discrepancy",),
         "star_linf": ("discrepancy",), "min_distance": ("spacing",),
         "mean_nn_distance": ("spacing",), "min_distance_normalized": ("spacing",),
         "mean_nn_distance_normalized": ("spacing",), "effective_nyquist": ("spectrum",),
         "effective_nyquist_normalized": ("spectrum",), "oscillation": ("spectrum",)}


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def get(d, path):
    r = d.request("GET", path)
    response_check.check("GET", path, r.status, r.headers, r.body)
    return r


def submit(d, spec):
    r = d.request("POST", "/v1/jobs", spec)
    check(r.status in (200, 201, 202), (r.status, r.body[:300]))
    return r.json()["id"]


def wait(d, job_id, timeout=240):
    end = time.time() + timeout
    while time.time() < end:
        j = get(d, "/v1/jobs/%d" % job_id).json()
        if j["state"] in ("done", "failed", "cancelled", "interrupted"):
            return j
        time.sleep(0.1)
    raise AssertionError("job %d did not end" % job_id)


def against_scipy(block, worst):
    cols = block["patterns"]
    e2 = cols["e2"]
    for entry in block["spearman"]:
        m = entry["metric"]
        pairs = [(x, y) for x, y in zip(cols[m], e2) if x is not None and y is not None]
        check(entry["n"] == len(pairs), (m, entry["n"], len(pairs)))
        if entry["rho"] is None:
            xs = [p[0] for p in pairs]
            check(len(pairs) < 3 or min(xs) == max(xs), (m, "rho null but defined"))
            continue
        ref = stats.spearmanr([p[0] for p in pairs], [p[1] for p in pairs])
        dr = abs(entry["rho"] - ref.correlation)
        check(dr <= 1e-12, ("rho", m, entry["rho"], ref.correlation))
        worst["rho"] = max(worst["rho"], dr)
        if ref.pvalue > 1e-250:
            rel = abs(entry["p_value"] - ref.pvalue) / ref.pvalue
            check(rel <= 1e-9, ("p", m, entry["p_value"], ref.pvalue))
            worst["p"] = max(worst["p"], rel)


def main():
    d = Daemon(sys.argv[1])
    d.start()
    worst = {"rho": 0.0, "p": 0.0}
    try:
        spec = {"kind": "random-stats", "family": "P(1,1,4)", "count": 300, "max_iterations": 50,
                "rng_seed": 1000, "metrics": ALL}
        job = wait(d, submit(d, spec))
        check(job["state"] == "done", job)
        block = job["result"]["point_metrics"]
        check(block["metrics"] == ALL and len(block["patterns"]["e2"]) == 300, block["metrics"])
        against_scipy(block, worst)
        # the study's strongest figure, positive over uniform P(1,1,4) sets
        rho = {e["metric"]: e["rho"] for e in block["spearman"]}
        check(rho["mixture"] > 0.7, rho)
        e2 = block["patterns"]["e2"]
        best = min(range(len(e2)), key=lambda i: e2[i])
        check(e2[best] == job["result"]["random"]["min"], "e2 column")
        r = d.request("POST", "/v1/analyze", {"pattern": job["result"]["best_random"],
                                              "spectrum": {"radius": block["spectrum_radius"]}})
        check(r.status == 200, r.body[:300])
        a = r.json()
        for m in ALL:
            want = a[WHERE[m][0]][m]
            got = block["patterns"][m][best]
            check((want is None and got is None) or
                  abs(got - want) <= 1e-13 * max(1.0, abs(want)), (m, got, want))
        again = wait(d, submit(d, spec))
        check(again["result"]["point_metrics"] == block, "same spec, same figures")

        t3 = wait(d, submit(d, {"kind": "table3", "family": "P(4,4,2)", "seeds": 2, "count": 15,
                                "max_iterations": 20, "distributions": ["jittered", "lloyd"],
                                "metrics": ["mixture", "mean_nn_distance"]}))
        check(t3["state"] == "done", t3)
        for row in t3["result"]["rows"]:
            check(len(row["point_metrics"]["patterns"]["e2"]) == 30, row["distribution"])
            against_scipy(row["point_metrics"], worst)

        # progress and cancel as before: a long job with figures
        long_id = submit(d, {"kind": "random-stats", "family": "P(16,16,4)", "count": 10000,
                             "max_seconds": 600, "metrics": ["star_linf"]})
        seen = 0.0
        end = time.time() + 60
        while time.time() < end and seen <= 0:
            seen = float(get(d, "/v1/jobs/%d" % long_id).json().get("progress") or 0)
            time.sleep(0.2)
        check(0 < seen < 1, ("progress", seen))
        r = d.request("DELETE", "/v1/jobs/%d" % long_id)
        check(r.status in (200, 202), (r.status, r.body[:200]))
        check(wait(d, long_id, 60)["state"] == "cancelled", "cancel")

        for metrics, field in ((["mixture", "mixture"], "metrics[1]"), (["nope"], "metrics[0]"),
                               ("mixture", "metrics"), (ALL + ["mixture"], "metrics"),
                               ([], "metrics"), ([2], "metrics[0]")):
            r = d.request("POST", "/v1/jobs", {"kind": "random-stats", "family": "P(1,1,4)",
                                               "metrics": metrics})
            check(r.status == 400 and r.error_field() == field, (metrics, r.status, r.body))
        r = d.request("POST", "/v1/jobs", {"kind": "random-stats", "family": "P(1,1,4)",
                                           "count": 20000, "metrics": ["mixture"]})
        check(r.status == 400 and r.error_field() == "metrics", r.body)
        check(not d.sanitizer_reports(), d.log_text()[-2000:])
    finally:
        d.stop()
    print("e2e_point_metrics: ok; worst |rho - scipy| %.2g, worst p-value relative %.2g"
          % (worst["rho"], worst["p"]))


if __name__ == "__main__":
    main()
