#!/usr/bin/env python3
"""Behaviour of two aalabd builds side by side, for refactors that must change nothing a client
sees: every case of the bad-input catalogue (status and the whole body) and one deterministic job
of every kind (the whole GET /v1/jobs/{id} answer without its clock fields, and the job's best
pattern export). Prints the differences; exit status 1 if there is any.

Usage: compare_behaviour.py --old OLD/server/aalabd --new NEW/server/aalabd [--only SUBSTR]
       compare_behaviour.py --record OUT.json --aalabd BUILD/server/aalabd
"""

import argparse
import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests"))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "bad_inputs"))
import aalabd_harness as H  # noqa: E402
import run_bad_inputs as B  # noqa: E402

# One job per kind, each deterministic: iteration counts instead of time limits, fixed seeds.
JOBS = [
    {"kind": "sleep", "seconds": 0, "pattern": {"preset": "rgss"}},
    {"kind": "optimize", "family": "P(4,1+,2)", "seeds": 2, "max_iterations": 40, "rng_seed": 7},
    {"kind": "family-sweep", "cost": 1.25, "seeds_per_config": 1, "max_iterations": 10,
     "rng_seed": 1},
    {"kind": "random-stats", "family": "P(1,4,2)", "count": 40, "distribution": "poisson",
     "max_iterations": 10, "rng_seed": 3, "metrics": ["cd", "min_distance"]},
    {"kind": "table3", "family": "P(4,4,2)", "seeds": 2, "count": 10, "max_iterations": 10,
     "rng_seed": 5},
    {"kind": "compare", "scene": {"name": "siemens-star", "width": 48, "height": 48},
     "patterns": ["rgss", {"preset": "flipquad"}], "reference": {"spp": 64}},
    {"kind": "animation", "scene": {"name": "translating-circle", "width": 32, "height": 32,
                                    "frames": 3}, "pattern": "rgss", "reference": {"spp": 64}},
    {"kind": "reference-convergence", "scene": {"name": "siemens-star", "width": 48, "height": 48},
     "levels": [16, 64], "baseline_spp": 256},
    {"kind": "temporal-render", "scene": "rings", "size": [32, 32],
     "pattern": {"temporal": {"preset": "halton23-8"}}, "reference": {"spp": 64}},
    {"kind": "temporal-optimize", "family": "T(8)", "blend": {"kind": "exponential", "alpha": 0.1},
     "seeds": 2, "max_iterations": 10, "rng_seed": 2},
]

# Fields of an answer that are clocks, or follow from clocks: the stored size counts the digits
# of the timings, and a trace samples the run at wall-clock moments.
VOLATILE = {"submitted", "started", "finished", "elapsed", "updated", "created", "seconds",
            "bytes", "trace", "id"}


def scrub(v):
    if isinstance(v, dict):
        return {k: ("<volatile>" if k in VOLATILE or k.endswith("_seconds") else scrub(x))
                for k, x in v.items()}
    if isinstance(v, list):
        return [scrub(x) for x in v]
    return v


def normalise_body(body):
    text = body.decode("utf-8", "replace")
    try:
        return json.dumps(scrub(json.loads(text)), sort_keys=True)
    except ValueError:
        return text


def record(binary, only=None):
    with open(os.path.join(HERE, "..", "tests", "bad_inputs", "cases.jsonl")) as f:
        cases = [json.loads(line) for line in f if line.strip()]
    if only:
        cases = [c for c in cases if only in c["name"]]
    d = H.Daemon(binary)
    d.web_dir = B.make_web_dir(d.root)
    d.start()
    out = {}
    cache = {}
    try:
        for c in cases:
            try:
                resp, _ = B.run_case(d, c, cache)
                out["case " + c["name"]] = "%d %s" % (resp.status, normalise_body(resp.body))
            except Exception as e:  # noqa: BLE001
                out["case " + c["name"]] = "request failed: %r" % e
        for spec in JOBS:
            name = "job " + spec["kind"]
            r = d.request("POST", "/v1/jobs", spec)
            if r.status != 202:
                out[name] = "submit %d %s" % (r.status, r.body.decode("utf-8", "replace"))
                continue
            jid = r.json()["id"]
            deadline = time.time() + 300
            while time.time() < deadline:
                g = d.request("GET", "/v1/jobs/%s" % jid, timeout=30)
                if g.json().get("state") not in ("queued", "running"):
                    break
                time.sleep(0.1)
            j = g.json()
            j.pop("id", None)
            out[name] = json.dumps(scrub(j), sort_keys=True, indent=1)
            e = d.request("GET", "/v1/patterns/%s/export?format=json" % jid)
            out[name + " export"] = "%d %s" % (e.status, normalise_body(e.body))
    finally:
        d.stop()
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--old")
    ap.add_argument("--new")
    ap.add_argument("--aalabd")
    ap.add_argument("--record")
    ap.add_argument("--only")
    a = ap.parse_args()
    if a.record:
        with open(a.record, "w") as f:
            json.dump(record(a.aalabd, a.only), f, indent=1, sort_keys=True)
        return 0
    old, new = record(a.old, a.only), record(a.new, a.only)
    diffs = [k for k in sorted(set(old) | set(new)) if old.get(k) != new.get(k)]
    for k in diffs:
        print("DIFF %s\n  old: %s\n  new: %s" % (k, str(old.get(k))[:600], str(new.get(k))[:600]))
    jobs = sum(1 for k in old if k.startswith("job ") and not k.endswith(" export"))
    print("%d answers compared (%d catalogue cases, %d jobs with their exports), %d differ"
          % (len(old), sum(1 for k in old if k.startswith("case ")), jobs, len(diffs)))
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())
