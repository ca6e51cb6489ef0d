"""End-to-end: every endpoint of aalabd through curl, over the Unix socket and TCP loopback."""

import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from e2e_lib import Daemon, check, expect_error  # noqa: E402


def make_web_dir(root):
    web = os.path.join(root, "web")
    os.makedirs(os.path.join(web, "js"))
    with open(os.path.join(web, "index.html"), "w") as f:
        f.write("<!doctype html><title>aalab</title>")
    with open(os.path.join(web, "js", "app.js"), "w") as f:
        f.write("export const x = 1;\n")
    with open(os.path.join(root, "secret.txt"), "w") as f:
        f.write("secret")
    os.symlink(os.path.join(root, "secret.txt"), os.path.join(web, "escape.txt"))
    return web


def test_catalogue(d):
    r = d.get("/v1/health")
    check(r.status == 200, r)
    h = r.json()
    for k in ("version", "uptime_seconds", "workers", "queue", "jobs"):
        check(k in h, "health lacks " + k)
    check("sleep" in h["job_kinds"], h)
    check("access-control-allow-origin" not in r.headers, "no CORS header")

    r = d.get("/v1/presets")
    names = [p["name"] for p in r.json()["presets"]]
    check(r.status == 200 and "quincunx" in names and "rgss" in names, r)
    r = d.get("/v1/presets/quincunx")
    check(r.status == 200 and abs(r.json()["e2"] - 0.518) < 5e-4, r)
    expect_error(d.get("/v1/presets/nope"), 404, "name")

    r = d.get("/v1/filters")
    fnames = [f["name"] for f in r.json()["filters"]]
    check(r.status == 200 and "mitchell" in fnames and "lanczos" in fnames, r)
    r = d.get("/v1/acuity")
    check(r.status == 200 and r.json()["default"] == "naiman", r)


def test_evaluate(d):
    r = d.post("/v1/evaluate", {"pattern": {"preset": "rgss"}})
    check(r.status == 200, r)
    e = r.json()
    check(abs(e["e2"] - 0.439) < 5e-4, e)
    check(e["family"] == "P(1,1,4)" and e["cost_spp"] == 4, e)
    check(set(e["argmax"]) == {"kernel", "angle_deg"}, e)
    again = d.post("/v1/evaluate", {"pattern": {"preset": "rgss"}})
    check(again.body == r.body, "cached answer identical")

    flipquad = {"mirrored": [[-0.5, 0.25, 0.25], [-0.25, -0.5, 0.25], [0.5, -0.25, 0.25],
                             [0.25, 0.5, 0.25]]}
    r = d.post("/v1/evaluate", {"pattern": flipquad, "detail": True,
                                "filter": {"name": "mitchell", "B": 1 / 3, "C": 1 / 3},
                                "acuity": {"name": "naiman"}})
    check(r.status == 200, r)
    e = r.json()
    check(e["family"] == "P(4,1+,2)", e)
    check(len(e["detail"]) == 4 and len(e["detail"][0]["angles"]) == e["angle_count"], e)
    a0 = e["detail"][0]["angles"][0]
    check(set(a0) == {"angle_deg", "weight", "e1", "weighted"}, a0)
    check(abs(max(x["weighted"] for k in e["detail"] for x in k["angles"]) - e["e2"]) < 1e-12, e)

    r = d.post("/v1/evaluate", {"pattern": {"kernels": [[[0, 0, 1]]]},
                                "acuity": {"knots": [[0, 1], [45, 2]]}, "angles": [0, 30, 60]})
    check(r.status == 200 and r.json()["angle_count"] == 3, r)

    expect_error(d.post("/v1/evaluate", {"pattern": {"kernels": [[[0, 0, 0.5], [0, "x", 0.5]]]}}),
                 400, "pattern.kernels[0][1][1]")
    expect_error(d.post("/v1/evaluate", {"pattern": {"kernels": [[[0, 0, 0.5], [0.1, 0, 0.4]]]}}),
                 400, "pattern.kernels[0]")
    expect_error(d.post("/v1/evaluate", {"pattern": {"preset": "nope"}}), 400, "pattern.preset")
    expect_error(d.post("/v1/evaluate", {"pattern": {"preset": "rgss"}, "filter": {"name": "x"}}),
                 400, "filter.name")
    expect_error(d.post("/v1/evaluate", {"pattern": {"preset": "rgss"}, "bogus": 1}), 400, "bogus")
    expect_error(d.post("/v1/evaluate", raw_body='{"pattern":{"preset":"rgss"}'), 400)
    expect_error(d.post("/v1/evaluate", raw_body='{"pattern":1,"pattern":2}'), 400)
    expect_error(d.post("/v1/evaluate", raw_body="[]"), 400)
    expect_error(d.curl("POST", "/v1/evaluate", raw_body='{"pattern":{"preset":"rgss"}}',
                        headers={"Content-Type": "text/plain"}, ctype=False), 415)
    expect_error(d.post("/v1/evaluate", raw_body='{"x":"' + "a" * (9 << 20) + '"}'), 413)
    expect_error(d.get("/v1/evaluate"), 405)
    expect_error(d.get("/v1/nope"), 404)


def test_jobs(d):
    r = d.post("/v1/jobs", {"kind": "sleep", "seconds": 0.3,
                            "pattern": {"preset": "rgss"}})
    check(r.status == 202, r)
    jid = r.json()["id"]
    check(isinstance(jid, int), r)
    j = d.wait_job(jid)
    check(j["state"] == "done" and j["progress"] == 1, j)
    check(j["owner_uid"] == os.getuid(), j)
    check(len(j["trace"]) >= 1 and all("best_e2" in p for p in j["trace"]), j)
    check(j["result"]["pattern"]["kernels"], j)
    lst = d.get("/v1/jobs").json()["jobs"]
    check(any(x["id"] == jid for x in lst), lst)
    lst = d.get("/v1/jobs?state=done&limit=1").json()["jobs"]
    check(len(lst) == 1 and lst[0]["id"] == jid, lst)
    expect_error(d.get("/v1/jobs?state=sleepy"), 400, "state")
    expect_error(d.get("/v1/jobs?limit=0"), 400, "limit")

    # export in every format
    r = d.get("/v1/patterns/%d/export?format=json" % jid)
    check(r.status == 200 and r.json()["pattern"]["family"] == "P(1,1,4)", r)
    r = d.get("/v1/patterns/%d/export?format=utk" % jid)
    lines = [x for x in r.body.splitlines() if x and not x.startswith("#")]
    check(r.status == 200 and r.headers["content-type"].startswith("text/plain") and
          len(lines) == 4, r)
    r = d.get("/v1/patterns/%d/export?format=vulkan" % jid)
    v = r.json()
    check(v["representable"] and v["sampleLocationsPerPixel"] == "VK_SAMPLE_COUNT_4_BIT", v)
    r = d.get("/v1/patterns/%d/export?format=d3d12" % jid)
    v = r.json()
    check(v["representable"] and v["NumSamplesPerPixel"] == 4, v)
    expect_error(d.get("/v1/patterns/%d/export?format=bmp" % jid), 400, "format")
    expect_error(d.get("/v1/patterns/999999/export?format=json"), 404)

    # a pattern reference to the job evaluates its best pattern
    r = d.post("/v1/evaluate", {"pattern": {"job": jid}})
    check(r.status == 200 and abs(r.json()["e2"] - 0.439) < 5e-4, r)
    expect_error(d.post("/v1/evaluate", {"pattern": {"job": 999999}}), 400, "pattern.job")

    # cancel a running job, then cancelling again conflicts
    r = d.post("/v1/jobs", {"kind": "sleep", "seconds": 60})
    jid2 = r.json()["id"]
    d.wait_job(jid2, states=("running",))
    r = d.delete("/v1/jobs/%d" % jid2)
    check(r.status == 202, r)
    j = d.wait_job(jid2, timeout=5)
    check(j["state"] == "cancelled", j)
    expect_error(d.delete("/v1/jobs/%d" % jid2), 409)
    expect_error(d.delete("/v1/jobs/999999"), 404, "id")
    expect_error(d.get("/v1/jobs/abc"), 404, "id")

    # failing job, bad specs
    r = d.post("/v1/jobs", {"kind": "sleep", "seconds": 0, "fail": True})
    j = d.wait_job(r.json()["id"])
    check(j["state"] == "failed" and j["error"]["field"] == "fail" and
          j["error"]["code"] == "invalid_field", j)
    expect_error(d.post("/v1/jobs", {"kind": "nope"}), 400, "kind")
    expect_error(d.post("/v1/jobs", {"seconds": 1}), 400, "kind")
    expect_error(d.post("/v1/jobs", {"kind": "sleep", "seconds": -1}), 400, "seconds")
    expect_error(d.post("/v1/jobs", {"kind": "sleep", "seconds": 1,
                                     "pattern": {"kernels": [[[0, 0, 2]]]}}), 400,
                 "pattern.kernels[0]")


def test_random_stats(d):
    """L&A Table 3 workflow: random patterns, then Opt W and Opt W+P of the best one."""
    r = d.post("/v1/jobs", {"kind": "random-stats", "family": "P(1,4,3)", "count": 200,
                            "distribution": "poisson", "max_seconds": 3, "rng_seed": 7})
    check(r.status == 202, r)
    j = d.wait_job(r.json()["id"])
    check(j["state"] == "done", j)
    res = j["result"]
    rnd = res["random"]
    check(res["count"] == 200 and res["distribution"] == "poisson", res)
    check(0 < rnd["min"] <= rnd["avg"] <= rnd["max"], rnd)
    check(res["opt_w"]["e2"] <= rnd["min"] and res["opt_wp"]["e2"] <= rnd["min"], res)
    # positions add freedom: W+P reaches below the weights-only optimum
    check(res["opt_wp"]["e2"] < res["opt_w"]["e2"], res)
    check(res["e2"] == res["opt_wp"]["e2"], res)
    # the automatic step rules: minimax for the convex weights-only stage
    check(res["opt_w"]["method"] == "minimax" and res["opt_wp"]["method"] == "laine-aila", res)
    for key in ("best_random", "best"):
        e = d.post("/v1/evaluate", {"pattern": res[key]})
        check(e.status == 200, e)
    e = d.post("/v1/evaluate", {"pattern": res["best"]}).json()
    check(abs(e["e2"] - res["e2"]) < 1e-9 and e["family"] == "P(1,4,3)", (e, res["e2"]))


def test_table3(d):
    """L&A Table 3 over seeds: a row per distribution with mean, sd and the paper's value of each
    column (the paper's values for P(16,16,4) only), each seed's values, the Poisson generator
    and its radius, the acuity table by name and version; a clock-free budget repeats exactly;
    the trace is the Opt W+P progress; a long one is cancelled."""
    spec = {"kind": "table3", "family": "P(4,4,2)", "seeds": 2, "count": 12,
            "max_iterations": 40, "rng_seed": 3, "acuity": {"name": "naiman-envelope"}}
    ids = [d.post("/v1/jobs", spec).json()["id"] for _ in range(2)]
    a, b = (d.wait_job(i, timeout=120) for i in ids)
    check(a["state"] == "done" and b["state"] == "done", (a, b))
    res = a["result"]
    check(res == b["result"] and res["reproducible"], (res, b["result"]))
    check(res["acuity"] == {"name": "naiman-envelope", "version": 1}, res["acuity"])
    check(res["seeds"] == [3, 4] and res["count"] == 12, res)
    check([r["distribution"] for r in res["rows"]] == ["poisson", "jittered"], res["rows"])
    gen = res["rows"][0]["generator"]
    check(gen["name"] == "dart-throwing-torus" and abs(gen["radius"] - 0.73 / 2 ** 0.5) < 1e-12,
          gen)
    check(res["rows"][1]["generator"] == {"name": "jittered-grid"}, res["rows"][1])
    best = float("inf")
    for row in res["rows"]:
        for col in ("min", "avg", "max", "opt_w", "opt_wp"):
            vals = [s[col] for s in row["per_seed"]]
            mean = sum(vals) / len(vals)
            sd = (sum((v - mean) ** 2 for v in vals) / (len(vals) - 1)) ** 0.5
            st = row["columns"][col]
            check(abs(st["mean"] - mean) < 1e-12 and abs(st["sd"] - sd) < 1e-12
                  and st["paper"] is None, (col, st, vals))
        for s in row["per_seed"]:
            check(s["opt_w"] <= s["min"] and s["opt_wp"] <= s["min"] <= s["avg"] <= s["max"], s)
            best = min(best, s["opt_wp"])
    check(res["e2"] == best, (res["e2"], best))
    e = d.post("/v1/evaluate", {"pattern": res["best"], "acuity": {"name": "naiman-envelope"}})
    check(abs(e.json()["e2"] - res["e2"]) < 1e-9, (e.json(), res["e2"]))
    # A shard's two cells run side by side: when the cell holding the job's best reports first,
    # no later point improves on it, so one point is a whole trace here.
    check_trace(a, min_points=1)
    # P(16,16,4) with the defaults, cancelled while it runs
    r = d.post("/v1/jobs", {"kind": "table3", "seeds": 2, "count": 20, "max_seconds": 60})
    check(r.status == 202, r)
    jid = r.json()["id"]
    d.wait_job(jid, states=("running",))
    r = d.delete("/v1/jobs/%d" % jid)
    check(r.status == 202, r)
    j = d.wait_job(jid, timeout=10)
    check(j["state"] == "cancelled", j)
    expect_error(d.post("/v1/jobs", {"kind": "table3", "poisson_radius": 0.5}), 400,
                 "poisson_radius")
    expect_error(d.post("/v1/jobs", {"kind": "table3", "family": "P(4,1+,2)"}), 400, "family")


def test_optimize_methods(d):
    """The step rule a job uses: "auto" picks by family and mode, the same for a family and for a
    pattern of it; an explicit one is used as asked; the result names it."""
    p142 = {"tile": {"size": 1, "kernel": 2, "border": False,
                     "samples": [[0.25, 0.25], [0.75, 0.75]]}}
    cases = [({"family": "P(1,4,2)"}, "laine-aila"),
             ({"pattern": p142}, "laine-aila"),
             ({"family": "P(4,4,1)"}, "smooth"),
             ({"family": "P(1,1,2)", "mode": "weights"}, "minimax"),
             ({"pattern": p142, "method": "smooth"}, "smooth"),
             ({"family": "P(1,1,2)", "method": "auto"}, "laine-aila")]
    for spec, want in cases:
        body = dict({"kind": "optimize", "seeds": 1, "max_seconds": 1, "rng_seed": 3}, **spec)
        r = d.post("/v1/jobs", body)
        check(r.status == 202, (spec, r))
        j = d.wait_job(r.json()["id"])
        check(j["state"] == "done" and j["result"]["method"] == want, (spec, want, j.get("result")))


def check_trace(j, min_points=2):
    """A job's error-against-time trace: seconds, iterations and evaluations never go back, the
    best E2 never rises, and it ends at the result's E2 (nothing better was seen and lost)."""
    t, res = j["trace"], j["result"]
    check(len(t) >= min_points, j)
    for a, b in zip(t, t[1:]):
        for key in ("seconds", "iterations", "evaluations"):
            check(b[key] >= a[key], (key, a, b, j["spec"]))
        check(b["best_e2"] < a["best_e2"], (a, b, j["spec"]))
    check(abs(t[-1]["best_e2"] - res["e2"]) < 1e-12, (t[-1], res["e2"], j["spec"]))


def test_optimizer_traces(d):
    """Every optimizer job kind: one trace over all its phases (screening, focused seeds, random
    patterns, Opt W, Opt W+P), ending at the result; a family sweep ranks every configuration."""
    specs = [{"kind": "optimize", "family": "P(4,1+,2)", "seeds": 4, "max_seconds": 2,
              "rng_seed": 7, "method": "minimax"},
             {"kind": "optimize", "family": "P(4,1+,2)", "seeds": 4, "max_seconds": 2,
              "rng_seed": 7},
             {"kind": "optimize", "family": "P(1,4,2)", "seeds": 4, "max_seconds": 1,
              "rng_seed": 7},
             {"kind": "random-stats", "family": "P(1,4,3)", "count": 100,
              "distribution": "jittered", "max_seconds": 2, "rng_seed": 7},
             {"kind": "family-sweep", "cost": 1.25, "seeds_per_config": 2, "max_seconds": 3,
              "rng_seed": 7}]
    ids = []
    for spec in specs:
        r = d.post("/v1/jobs", spec)
        check(r.status == 202, (spec, r))
        ids.append(r.json()["id"])
    for jid in ids:
        j = d.wait_job(jid, timeout=120)
        check(j["state"] == "done", j)
        check_trace(j)
        e = d.post("/v1/evaluate", {"pattern": j["result"]["best"]}).json()
        check(abs(e["e2"] - j["result"]["e2"]) < 1e-9, (e, j["result"]["e2"], j["spec"]))
    sweep = d.get("/v1/jobs/%d" % ids[-1]).json()["result"]
    ranked = sweep["ranked"]
    check(sweep["configurations"] == len(ranked) >= 2, sweep)
    check([row["rank"] for row in ranked] == list(range(1, len(ranked) + 1)), ranked)
    check(all(a["e2"] <= b["e2"] for a, b in zip(ranked, ranked[1:])), ranked)
    check(sweep["e2"] == ranked[0]["e2"], sweep)
    for row in ranked:
        check(abs(row["cost"] - 1.25) < 1e-12, row)
        e = d.post("/v1/evaluate", {"pattern": row["best"]}).json()
        check(abs(e["e2"] - row["e2"]) < 1e-9, (e, row))


def test_enumerate_render(d):
    r = d.post("/v1/families/enumerate", {"family": "P(4,1+,n)", "cost": 1.25})
    check(r.status == 200, r)
    check("count" in r.json() and "configurations" in r.json(), r)
    expect_error(d.post("/v1/families/enumerate", {"family": "P(4,1+,n)", "cost": 1.3}), 400,
                 "cost")
    expect_error(d.post("/v1/families/enumerate", {"family": "Q(1)", "cost": 1}), 400, "family")
    check(d.get("/v1/health").json()["render"] is True, "render not in health")
    # a finished job's pattern, by reference, rendered; its tiles are served as PNG
    r = d.post("/v1/jobs", {"kind": "sleep", "seconds": 0, "pattern": {"preset": "quincunx"}})
    jid = r.json()["id"]
    d.wait_job(jid)
    scene = {"name": "siemens-star", "width": 32, "height": 32}
    r = d.post("/v1/render", {"pattern": {"job": jid}, "scene": scene})
    check(r.status == 200, r)
    out = r.json()
    check(abs(out["e2"] - 0.518) < 5e-4, out)
    urls = [t["url"] for t in out["tiles"].values() if isinstance(t, dict) and "url" in t]
    check(urls, out["tiles"])
    for u in urls:
        t = d.get(u)
        check(t.status == 200 and t.headers["content-type"] == "image/png" and "PNG" in t.body[:8],
              (u, t.status, t.headers))
    expect_error(d.post("/v1/render", {"pattern": {"job": 999999}, "scene": scene}), 400,
                 "pattern.job")
    expect_error(d.get("/v1/tiles/0123456789abcdef0123456789abcdef.png"), 404)


def test_render_jobs_acuity(d):
    """compare and animation results record the acuity table their E2 values use, by name and
    version, like evaluations and the optimizer kinds; custom knots are "custom"."""
    versions = {t["name"]: t["version"] for t in d.get("/v1/acuity").json()["tables"]}
    scene = {"name": "siemens-star", "width": 16, "height": 16}
    specs = [({"kind": "compare", "scene": scene, "reference": {"spp": 16}, "tiles": False,
               "patterns": ["rgss"], "acuity": {"name": "naiman-envelope"}},
              {"name": "naiman-envelope", "version": versions["naiman-envelope"]}),
             ({"kind": "animation", "scene": {"name": "translating-circle", "width": 16,
                                              "height": 16, "frames": 2},
               "reference": {"spp": 16}, "tiles": False, "pattern": "rgss"},
              {"name": "naiman", "version": versions["naiman"]}),
             ({"kind": "animation", "scene": {"name": "translating-circle", "width": 16,
                                              "height": 16, "frames": 2},
               "reference": {"spp": 16}, "tiles": False, "pattern": "rgss",
               "acuity": {"knots": [[0, 1], [45, 2]]}}, {"name": "custom"})]
    for spec, want in specs:
        r = d.post("/v1/jobs", spec)
        check(r.status == 202, r)
        j = d.wait_job(r.json()["id"], timeout=60)
        check(j["state"] == "done", j)
        res = j["result"]
        check(res["acuity"] == want, (spec["kind"], res["acuity"], want))
        e2 = res["rows"][0]["e2"] if spec["kind"] == "compare" else res["e2"]
        e = d.post("/v1/evaluate", {"pattern": {"preset": "rgss"},
                                    "acuity": spec.get("acuity", {"name": "naiman"})}).json()
        check(abs(e["e2"] - e2) < 1e-9 and e["acuity"] == want, (e, e2, want))


def test_tcp(d):
    auth = {"Authorization": "Bearer " + d.token}
    # every API request over TCP needs the token, reads included
    for path in ("/v1/health", "/v1/jobs", "/v1/presets", "/v1/tokens"):
        expect_error(d.get(path, tcp=True), 401)
    r = d.get("/v1/health", tcp=True, headers=auth)
    check(r.status == 200 and r.json()["tcp"] is True, r)
    expect_error(d.get("/v1/health", tcp=True, headers=dict(auth, Host="evil.example")), 403)
    expect_error(d.post("/v1/tokens", {}, tcp=True, headers=auth), 403)
    expect_error(d.post("/v1/jobs", {"kind": "sleep", "seconds": 0}, tcp=True), 401)
    expect_error(d.post("/v1/jobs", {"kind": "sleep", "seconds": 0}, tcp=True,
                        headers={"Authorization": "Bearer wrong"}), 401)
    r = d.post("/v1/jobs", {"kind": "sleep", "seconds": 0}, tcp=True,
               headers=auth)
    check(r.status == 202, r)
    check("access-control-allow-origin" not in r.headers, r.headers)
    r = d.get("/", tcp=True)
    check(r.status == 200 and r.headers["content-type"].startswith("text/html"), r)
    r = d.get("/js/app.js", tcp=True)
    check(r.status == 200 and "javascript" in r.headers["content-type"], r)
    for bad in ("/../secret.txt", "/%2e%2e/secret.txt", "/escape.txt", "/index.html%00.png",
                "/js/../../secret.txt"):
        r = d.get(bad, tcp=True)
        check(r.status in (400, 403, 404) and "secret" not in r.body, (bad, r))
    # static files are not served on the Unix socket
    expect_error(d.get("/"), 404)


def main():
    binary = sys.argv[1]
    root = tempfile.mkdtemp(prefix="aalab-e2e-")
    web = make_web_dir(root)
    d = Daemon(binary, root=root, web_dir=web, extra=["--workers", "2"]).start()
    try:
        test_catalogue(d)
        test_evaluate(d)
        test_jobs(d)
        test_random_stats(d)
        test_table3(d)
        test_optimize_methods(d)
        test_optimizer_traces(d)
        test_enumerate_render(d)
        test_render_jobs_acuity(d)
        test_tcp(d)
        check(d.stop() == 0, "clean exit on SIGTERM")
        check(not os.path.exists(d.sock), "socket removed at exit")
    except BaseException:
        print(d.log_text())
        raise
    finally:
        d.cleanup()
    print("e2e_api: ok")


if __name__ == "__main__":
    main()
