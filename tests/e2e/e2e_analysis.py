"""End-to-end: POST /v1/analyze against independent values.
- The four L2 discrepancies (CD, WD, MD, L2-star) of random sets of 4 to 1024 points and of every
  preset's tile points: against a reference evaluated here in numpy's long double (the defining
  sums over all pairs; eps 1.1e-19), to 1e-12 relative; and against scipy.stats.qmc.discrepancy
  (python3-scipy), which sums in double without compensation and returns the squares of CD, WD
  and MD but the root of L2-star: the largest relative difference is printed, and must be within
  scipy's own rounding (a few eps times the terms over the square).
- The spacing against a brute-force toroidal nearest-neighbour search here.
- Every answer against analyze_response.json (response_check); the metrics filter; a job
  reference. Needs python3-scipy and python3-numpy; SKIP (77) without them."""

import json
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, ".."))

try:
    import numpy as np
    from scipy.stats import qmc
except ImportError as e:  # pragma: no cover
    print("SKIP: %s (python3-numpy, python3-scipy)" % e)
    sys.exit(77)

import response_check  # noqa: E402
from aalabd_harness import Daemon  # noqa: E402

REL = 1e-12
EPS = 2.0 ** -52


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def long_double_squares(p):
    """CD^2, WD^2, MD^2, L2-star^2 by their defining sums in long double."""
    x = np.asarray(p, dtype=np.longdouble)
    n = np.longdouble(len(x))
    a = np.abs(x - np.longdouble(0.5))
    cd1 = np.prod(1 + a / 2 - a * a / 2, axis=1).sum()
    md1 = np.prod(np.longdouble(5) / 3 - a / 4 - a * a / 4, axis=1).sum()
    l21 = np.prod(1 - x * x, axis=1).sum()
    d = np.abs(x[:, None, :] - x[None, :, :])
    ai, aj = a[:, None, :], a[None, :, :]
    cd2 = np.prod(1 + ai / 2 + aj / 2 - d / 2, axis=2).sum()
    wd2 = np.prod(np.longdouble(1.5) - d * (1 - d), axis=2).sum()
    md2 = np.prod(np.longdouble(15) / 8 - ai / 4 - aj / 4 - 3 * d / 4 + d * d / 2, axis=2).sum()
    l22 = np.prod(1 - np.maximum(x[:, None, :], x[None, :, :]), axis=2).sum()
    return {
        "centered": (np.longdouble(13) / 12) ** 2 - 2 * cd1 / n + cd2 / (n * n),
        "wrap_around": -(np.longdouble(4) / 3) ** 2 + wd2 / (n * n),
        "mixture": (np.longdouble(19) / 12) ** 2 - 2 * md1 / n + md2 / (n * n),
        "l2_star": np.longdouble(1) / 9 - l21 / (2 * n) + l22 / (n * n),
    }


SCIPY = {"centered": "CD", "wrap_around": "WD", "mixture": "MD", "l2_star": "L2-star"}
# The largest term of each square's pair sum (scipy's rounding is a few eps of it per term).
TERM = {"centered": 1.56, "wrap_around": 2.25, "mixture": 3.52, "l2_star": 1.0}


def nearest_distances(p):
    x = np.asarray(p, dtype=float)
    d = np.abs(x[:, None, :] - x[None, :, :])
    d = np.minimum(d, 1 - d)
    r = np.sqrt((d * d).sum(axis=2))
    np.fill_diagonal(r, np.inf)
    return r.min(axis=1)


def analyze(d, body):
    r = d.request("POST", "/v1/analyze", body)
    check(r.status == 200, (r.status, r.body[:400]))
    response_check.check("POST", "/v1/analyze", r.status, r.headers, r.body)
    return r.json()


def compare(what, points, got, worst):
    ref = long_double_squares(points)
    for key, want in ref.items():
        square = got["discrepancy"][key + "_squared"]
        rel = abs(np.longdouble(square) - want) / want
        check(rel <= REL, "%s %s^2: %.17g against %.17g (rel %.2g)" % (what, key, square,
                                                                        float(want), float(rel)))
        check(abs(got["discrepancy"][key] - math.sqrt(square)) <= 1e-15 * got["discrepancy"][key],
              (what, key, "root"))
        sp = qmc.discrepancy(np.asarray(points), method=SCIPY[key])
        # scipy (1.10, Debian 12) returns the squares of CD, WD and MD but the root of L2-star.
        if key == "l2_star":
            sp = sp * sp
        rel_sp = abs(sp - square) / square
        # scipy's own error: about n^2 rounded terms, random walk sqrt(n^2) = n of them.
        bound = 8 * EPS * TERM[key] * max(len(points), 4) / square
        check(rel_sp <= max(bound, REL), "%s %s: scipy %.17g, aalab %.17g (rel %.2g > %.2g)"
              % (what, key, sp, square, rel_sp, bound))
        worst["long double"] = max(worst["long double"], float(rel))
        worst["scipy"] = max(worst["scipy"], rel_sp)


def main():
    binary = sys.argv[1]
    d = Daemon(binary)
    d.start()
    worst = {"long double": 0.0, "scipy": 0.0}
    try:
        rng = np.random.default_rng(20261128)
        for n in (4, 16, 64, 256, 1024):
            for trial in range(3 if n <= 256 else 1):
                pts = rng.random((n, 2)).tolist()
                got = analyze(d, {"pattern": {"points": {"format": "json", "data": pts,
                                                         "weights": "equal"}},
                                  "metrics": ["discrepancy", "spacing"]})
                check(got["points"] == n and got["tile"] == 1, got)
                compare("random %d" % n, pts, got, worst)
                nn = nearest_distances(pts)
                sp = got["spacing"]
                check(abs(sp["min_distance"] - nn.min()) <= 1e-15, ("min distance", n))
                check(abs(sp["mean_nn_distance"] - nn.mean()) <= 1e-13, ("mean nn", n))
                check(set(got) == {"points", "tile", "family", "discrepancy", "spacing"}, got.keys())
        presets = d.request("GET", "/v1/presets").json()["presets"]
        analysed = 0
        for p in presets:
            r = d.request("POST", "/v1/patterns/export", {"pattern": {"preset": p["name"]},
                                                          "format": "points-json"})
            check(r.status == 200, (p["name"], r.status))
            pts = [q[:2] for q in json.loads(r.body)["points"]]
            if len(pts) < 2:
                continue
            got = analyze(d, {"pattern": {"preset": p["name"]}})
            check(got["points"] == len(pts), (p["name"], got["points"], len(pts)))
            compare(p["name"], pts, got, worst)
            s = got["spectrum"]
            check(len(s["power"]) == 65 and len(s["radial"]) == 33, p["name"])
            check(abs(s["radial"][0] - len(pts)) < 1e-9, (p["name"], s["radial"][0]))
            check(len(got["pcf"]["g"]) == 64, p["name"])
            analysed += 1
        check(analysed >= 10, analysed)
        # a job's best pattern by reference
        r = d.request("POST", "/v1/jobs", {"kind": "optimize", "family": "P(4,1+,2)",
                                           "max_iterations": 5, "rng_seed": 1})
        check(r.status == 202, r.body[:300])
        jid = r.json()["id"]
        for _ in range(300):
            j = d.request("GET", "/v1/jobs/%d" % jid).json()
            if j["state"] in ("done", "failed", "cancelled", "interrupted"):
                break
            time.sleep(0.1)
        check(j["state"] == "done", j["state"])
        got = analyze(d, {"pattern": {"job": jid}, "metrics": ["star_discrepancy"]})
        check(0 < got["discrepancy"]["star_linf"] < 1, got)
        # A temporal pattern: the N jitter offsets around the pixel centre, as points of the
        # pixel; the same figures as the points form of those positions (computed here).
        def radical_inverse(i, b):
            f, r = 1.0, 0.0
            while i:
                f /= b
                r += f * (i % b)
                i //= b
            return r
        h8 = [[radical_inverse(i, 2), radical_inverse(i, 3)] for i in range(1, 9)]
        got = analyze(d, {"pattern": {"temporal": {"preset": "halton23-8"}}, "spectrum": {"radius": 8}})
        ref = analyze(d, {"pattern": {"points": {"format": "json", "data": h8, "weights": "equal"}},
                          "spectrum": {"radius": 8}})
        check(got["points"] == 8 and got["tile"] == 1, got)

        def close(a, b):  # (h - 1/2) + 1/2 may differ from h in the last bit
            if isinstance(a, dict):
                return a.keys() == b.keys() and all(close(a[k], b[k]) for k in a)
            if isinstance(a, list):
                return len(a) == len(b) and all(close(x, y) for x, y in zip(a, b))
            if isinstance(a, float) or isinstance(b, float):
                return abs(a - b) <= 1e-12 * max(1.0, abs(b))
            return a == b
        for key in ("discrepancy", "spacing", "spectrum", "pcf"):
            check(close(got[key], ref[key]), (key, got[key], ref[key]))
        # With an MSAA 2x frame pattern: 2 N points; range 2 wraps the offsets around the pixel.
        got = analyze(d, {"pattern": {"temporal": {"jitter": [[0.4, 0.4], [-0.7, 0.1]],
                                                   "jitter_range": 2,
                                                   "frame_pattern": {"preset": "d3d-2x"}}},
                          "metrics": ["spacing"]})
        check(got["points"] == 4, got)
        r = d.request("POST", "/v1/analyze", {"pattern": {"temporal": {"jitter": {
            "generator": "halton", "count": 1024}, "frame_pattern": {"preset": "d3d-8x"}}}})
        check(r.status == 400 and r.json()["error"]["field"] == "pattern.temporal", r.body[:300])
        r = d.request("POST", "/v1/analyze", {"pattern": {"temporal": {"jitter": [[0, 0], [0.9, 0]]}}})
        check(r.status == 400 and r.json()["error"]["field"].startswith("pattern.temporal.jitter"),
              r.body[:300])
        check(not d.sanitizer_reports(), d.log_text())
    finally:
        d.stop()
    print("# figure: CD, WD, MD, L2-star squares against long double: worst relative %.2g "
          "(limit %.0e); against scipy.stats.qmc.discrepancy: worst relative %.2g"
          % (worst["long double"], REL, worst["scipy"]))
    print("e2e_analysis: ok (%d presets)" % analysed)
    return 0


if __name__ == "__main__":
    sys.exit(main())
