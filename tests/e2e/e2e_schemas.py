"""Validates live daemon answers and example requests against proto/schemas (JSON Schema
2020-12, python3-jsonschema)."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from e2e_lib import Daemon, check  # noqa: E402
from schema_check import schemas as load_schemas  # noqa: E402


def valid(schemas, name, doc, what):
    errors = schemas.errors(name, doc)
    check(not errors, "%s does not match %s: %s" % (what, name, errors[:3]))


def invalid(schemas, name, doc, what):
    check(schemas.errors(name, doc), "%s should not match %s" % (what, name))


# Bodies each kind's spec schema rejects, with the field the daemon must name in its 400.
OPT = {"kind": "optimize", "family": "P(4,1+,2)", "max_seconds": 1}
REJECTED = [
    (dict(OPT, seeds=0), "seeds"),
    (dict(OPT, max_seconds=0), "max_seconds"),
    (dict(OPT, mode="all"), "mode"),
    (dict(OPT, method="newton"), "method"),
    (dict(OPT, grid={"bits": 13}), "grid.bits"),
    (dict(OPT, distributions=["gaussian"]), "distributions[0]"),
    (dict(OPT, rng_seed=-1), "rng_seed"),
    (dict(OPT, bogus=1), "bogus"),
    ({"kind": "family-sweep", "cost": 1.25, "seeds_per_config": 0}, "seeds_per_config"),
    ({"kind": "family-sweep", "cost": 20}, "cost"),
    ({"kind": "random-stats", "family": "P(1,4,2)", "count": 0}, "count"),
    ({"kind": "random-stats", "family": "P(1,4,2)", "distribution": "x"}, "distribution"),
    ({"kind": "random-stats", "family": "P(1,4,2)", "mode": "both"}, "mode"),
    ({"kind": "temporal-optimize", "family": "T(8)", "seeds": 0}, "seeds"),
    ({"kind": "temporal-optimize", "family": "P(1,1,1)"}, "family"),
    ({"kind": "temporal-optimize", "family": "T(8)", "order": "random"}, "order"),
    ({"kind": "temporal-optimize", "family": "T(8)", "grid": {"bits": 13}}, "grid.bits"),
    ({"kind": "temporal-optimize", "family": "T(8)", "flicker_cap": 0.1}, "flicker_cap"),
    ({"kind": "temporal-optimize", "pattern": {"temporal": {"preset": "halton23-8"}},
      "jitter_range": 2}, "jitter_range"),
    ({"kind": "compare", "patterns": []}, "patterns"),
    ({"kind": "compare", "patterns": ["rgss"], "tiles": "yes"}, "tiles"),
    ({"kind": "compare", "patterns": ["rgss"], "reference": {"spp": 15}}, "reference.spp"),
    ({"kind": "compare", "patterns": ["rgss"], "scene": {"width": 0}}, "scene.width"),
    ({"kind": "animation", "scene": "siemens-star", "pattern": "rgss"}, "scene.name"),
    ({"kind": "animation", "scene": "rotating-triangle"}, "pattern"),
    ({"kind": "reference-convergence", "levels": [15]}, "levels[0]"),
    ({"kind": "reference-convergence", "kernel_size": 9}, "kernel_size"),
    ({"kind": "reference-convergence", "baseline_spp": 5}, "baseline_spp"),
    ({"kind": "sleep", "seconds": 4000}, "seconds"),
    ({"kind": "sleep", "seconds": 1, "fail": "yes"}, "fail"),
    ({"kind": "sleep", "seconds": 1, "priority": 11}, "priority"),
    ({"kind": "sleep", "seconds": 1, "visibility": "public"}, "visibility"),
]


def main():
    schemas = load_schemas()
    requests = [
        {"pattern": {"preset": "rgss"}},
        {"pattern": {"kernels": [[[0, 0, 0.5], [0.25, 0.25, 0.5]]]}, "detail": True,
         "filter": {"name": "mitchell", "B": 0.3333, "C": 0.3333}, "acuity": {"name": "naiman"}},
        {"pattern": {"mirrored": [[-0.5, 0.25, 0.25], [-0.25, -0.5, 0.25], [0.5, -0.25, 0.25],
                                  [0.25, 0.5, 0.25]]}, "acuity": {"knots": [[0, 1], [45, 2]]},
         "angles": [0, 45, 90]},
        {"pattern": {"tile": {"size": 2, "kernel": 1, "border": True,
                              "samples": [[0.5, 0.5], [1.5, 0.5], [0.5, 1.5], [1.5, 1.5]]}}},
    ]
    for i, r in enumerate(requests):
        valid(schemas, "evaluate_request.json", r, "request %d" % i)
    invalid(schemas, "evaluate_request.json", {"pattern": {"preset": "rgss"}, "bogus": 1}, "bogus")
    invalid(schemas, "evaluate_request.json", {"pattern": {"kernels": [[[0, 0]]]}}, "2-tuple")

    d = Daemon(sys.argv[1], tcp=False).start()
    try:
        for i, r in enumerate(requests):
            resp = d.post("/v1/evaluate", r)
            check(resp.status == 200, resp)
            valid(schemas, "evaluate_response.json", resp.json(), "evaluate answer %d" % i)
        for p in d.get("/v1/presets").json()["presets"]:
            full = d.get("/v1/presets/" + p["name"]).json()
            valid(schemas, "pattern.json", full["pattern"], "encoded preset " + p["name"])
        for f in d.get("/v1/filters").json()["filters"]:
            valid(schemas, "filter.json", f, "filter " + f["name"])
        for bad in ({"pattern": {"preset": "nope"}}, {"pattern": 1}, {"x": 1}):
            resp = d.post("/v1/evaluate", bad)
            check(resp.status == 400, resp)
            valid(schemas, "error.json", resp.json(), "error answer")
        valid(schemas, "error.json", d.get("/v1/nope").json(), "404 answer")
        # The spec schemas and the daemon agree on what a kind refuses.
        for body, field in REJECTED:
            invalid(schemas, "kinds/%s.spec.json" % body["kind"], body, "bad %r" % body)
            resp = d.post("/v1/jobs", body)
            check(resp.status == 400 and resp.json()["error"]["field"] == field,
                  "%r: expected 400 naming %s, got %r" % (body, field, resp))
        r = d.post("/v1/jobs", {"kind": "sleep", "seconds": 0, "pattern": {"preset": "rgss"}})
        valid(schemas, "job.json", r.json(), "POST /v1/jobs answer")
        job = d.wait_job(r.json()["id"])
        valid(schemas, "job.json", job, "finished job")
        for j in d.get("/v1/jobs").json()["jobs"]:
            valid(schemas, "job.json", j, "job summary")
        exp = d.get("/v1/patterns/%d/export?format=json" % job["id"]).json()
        valid(schemas, "pattern.json", exp["pattern"], "exported pattern")
    except BaseException:
        print(d.log_text())
        raise
    finally:
        d.cleanup()
    print("e2e_schemas: ok")


if __name__ == "__main__":
    main()
