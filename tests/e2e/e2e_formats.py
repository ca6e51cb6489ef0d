"""End-to-end: the sampling tools' formats (issue 31) against a running daemon.
- UTK .bin: every preset exported by POST /v1/patterns/export?format=bin reads back through the
  points form (base64) with the same E2 to 1e-12 (the aalab header rides as a trailer).
- PSA .rps: float32 pairs without a header; a pattern of float32 points with filter weights
  reads back with the same tile, kernel and weights to 1e-12.
- Several sets in one text file: concatenated utk exports, "set": i is preset i to 1e-12;
  POST /v1/analyze with "set": "all" averages: its radial spectrum is the mean of the sets'
  (1e-12 relative) and its discrepancies the means of theirs; per_set holds each set.
- Metal: format=metal of the D3D standard positions, and not representable cases.
- Bad files: truncated, wrong magic, dimension 3, count mismatch, NaN, too many points, not
  base64, a set past the last: 400 naming the field. Every answer against its schema."""

import base64
import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, ".."))

import aalabd_harness  # noqa: E402
import response_check  # noqa: E402
from aalabd_harness import Daemon  # noqa: E402

TOLERANCE = 1e-12
UTK_MAGIC = 0x214B5455


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def e2_of(d, pattern):
    r = d.request("POST", "/v1/evaluate", {"pattern": pattern})
    check(r.status == 200, (r.status, r.body[:400]))
    return r.json()["e2"]


def b64(data):
    return base64.b64encode(data).decode("ascii")


def expect_400(r, field, part=None):
    check(r.status == 400, (r.status, r.body[:300]))
    err = r.json()["error"]
    check(err["field"] == field, (field, err))
    if part:
        check(part in err["message"], (part, err))


def utk_bin(sets, dtype=5, d=2, n=None):
    """UTK's layout: magic, dtype byte, 3 reserved, m, N, d (little-endian u32), then values."""
    n = len(sets[0]) if n is None else n
    head = struct.pack("<IB3xIII", UTK_MAGIC, dtype, len(sets), n, d)
    fmt = "<d" if dtype == 5 else "<f"
    return head + b"".join(struct.pack(fmt, v) for s in sets for p in s for v in p)


def export(d, pattern, fmt):
    r = d.request("POST", "/v1/patterns/export", {"pattern": pattern, "format": fmt})
    check(r.status == 200, (fmt, r.status, r.body[:300]))
    return r


def main():
    if len(sys.argv) < 2:
        print("usage: e2e_formats.py AALABD")
        return 2
    aalabd_harness.RESPONSE_HOOK = response_check.check
    d = Daemon(sys.argv[1], tcp=False).start()
    try:
        presets = [p["name"] for p in d.request("GET", "/v1/presets").json()["presets"]]
        # bin: every preset, exact through the trailer
        worst_bin = 0.0
        for name in presets:
            pat = {"preset": name}
            want = e2_of(d, pat)
            r = export(d, pat, "bin")
            check(r.headers.get("content-type", "").startswith("application/octet-stream"),
                  r.headers)
            magic, dtype, m, n, dim = struct.unpack("<IB3xIII", r.body[:20])
            check((magic, dtype, m, dim) == (UTK_MAGIC, 5, 1, 2), (name, magic, dtype, m, dim))
            check(r.body[20 + 16 * n:].startswith(b"# aalab-pattern {"), (name, r.body[-80:]))
            got = e2_of(d, {"points": {"format": "bin", "base64": b64(r.body)}})
            check(abs(got - want) <= TOLERANCE, (name, "bin", want, got))
            worst_bin = max(worst_bin, abs(got - want))

        # rps: float32 points, the reader states tile, kernel and weights
        pts = [(struct.unpack("<f", struct.pack("<f", (i * 0.37 + 0.05) % 1.0))[0],
                struct.unpack("<f", struct.pack("<f", (i * 0.61 + 0.11) % 1.0))[0])
               for i in range(16)]
        opts = {"tile": 2, "kernel": 2, "weights": "filter"}
        text = "".join("%.17g %.17g\n" % p for p in pts)
        pat = {"points": dict({"format": "utk", "text": text}, **opts)}
        want = e2_of(d, pat)
        r = export(d, pat, "rps")
        check(len(r.body) == 8 * 16, len(r.body))
        check(list(struct.unpack("<32f", r.body)) == [v for p in pts for v in p], "rps values")
        got = e2_of(d, {"points": dict({"format": "rps", "base64": b64(r.body)}, **opts)})
        check(abs(got - want) <= TOLERANCE, ("rps", want, got))
        worst_rps = abs(got - want)

        # several sets: concatenated exports; set i is preset i
        chosen = presets[:3]
        cat = "".join(export(d, {"preset": n}, "utk").body.decode() for n in chosen)
        for i, name in enumerate(chosen):
            got = e2_of(d, {"points": {"format": "utk", "text": cat, "set": i}})
            check(abs(got - e2_of(d, {"preset": name})) <= TOLERANCE, (name, got))
        expect_400(d.request("POST", "/v1/evaluate", {"pattern": {"points": {
            "format": "utk", "text": cat, "set": 3}}}), "pattern.points.set", "holds 3 sets")
        expect_400(d.request("POST", "/v1/evaluate", {"pattern": {"points": {
            "format": "utk", "text": cat}}}), "pattern.points.text", "choose one with set")
        expect_400(d.request("POST", "/v1/evaluate", {"pattern": {"points": {
            "format": "utk", "text": cat, "set": "all"}}}), "pattern.points.set", "/v1/analyze")

        # analyze "all": pspec's averaging, UTK text without headers and UTK bin
        a = [((i + 0.5) / 8, ((i * 3) % 8 + 0.25) / 8) for i in range(8)]
        b = [((i * 5 % 8 + 0.75) / 8, (i + 0.5) / 8) for i in range(8)]
        two = "".join("%.17g %.17g\n" % p for p in a) + "#\n" + "".join("%.17g %.17g\n" % p
                                                                          for p in b)
        body = {"pattern": {"points": {"format": "utk", "text": two, "set": "all",
                                       "weights": "equal"}}, "spectrum": {"radius": 8}}
        r = d.request("POST", "/v1/analyze", body)
        check(r.status == 200, r.body[:400])
        mean = r.json()
        check(mean["sets"]["count"] == 2 and len(mean["sets"]["per_set"]) == 2, mean.get("sets"))
        single = []
        for i in range(2):
            body1 = {"pattern": {"points": {"format": "utk", "text": two, "set": i,
                                            "weights": "equal"}}, "spectrum": {"radius": 8}}
            single.append(d.request("POST", "/v1/analyze", body1).json())
        worst_avg = 0.0
        for k in range(9):
            want = (single[0]["spectrum"]["radial"][k] + single[1]["spectrum"]["radial"][k]) / 2
            got = mean["spectrum"]["radial"][k]
            check(abs(got - want) <= 1e-12 * max(1.0, abs(want)), (k, got, want))
            worst_avg = max(worst_avg, abs(got - want))
        for key in ("centered", "wrap_around", "mixture", "l2_star", "star_linf"):
            want = (single[0]["discrepancy"][key] + single[1]["discrepancy"][key]) / 2
            check(abs(mean["discrepancy"][key] - want) <= 1e-12 * want, (key, want))
            check(mean["sets"]["per_set"][1]["discrepancy"][key] == single[1]["discrepancy"][key],
                  key)
        check("power" not in mean["sets"]["per_set"][0]["spectrum"], "per_set arrays")
        # the same two sets as one UTK .bin (m = 2)
        rb = d.request("POST", "/v1/analyze", {"pattern": {"points": {
            "format": "bin", "base64": b64(utk_bin([a, b])), "set": "all", "weights": "equal"}},
            "spectrum": {"radius": 8}})
        check(rb.status == 200, rb.body[:300])
        check(rb.json()["spectrum"]["radial"] == mean["spectrum"]["radial"], "bin = text")
        # sets of different sizes cannot average
        r = d.request("POST", "/v1/analyze", {"pattern": {"points": {
            "format": "utk", "text": two + "0.5 0.5\n", "set": "all", "weights": "equal"}}})
        expect_400(r, "pattern.points.set", "set 1 has 9 points")

        # Metal
        m = export(d, {"preset": "d3d-4x"}, "metal").json()
        check(m["api"] == "metal" and m["representable"] and m["sampleCount"] == 4, m)
        for p in m["samplePositions"]:
            check(0 <= p["x"] <= 15 / 16 and (p["x"] * 16).is_integer(), p)
            check(0 <= p["y"] <= 15 / 16 and (p["y"] * 16).is_integer(), p)
        m = export(d, {"preset": "d3d-16x"}, "metal").json()
        check(not m["representable"] and "1, 2, 4 or 8" in m["reason"], m)
        m = export(d, {"preset": "flipquad"}, "metal").json()
        check(not m["representable"] and "1x1" in m["reason"], m)

        # bad files: 400 naming the field
        def ev(points):
            return d.request("POST", "/v1/evaluate", {"pattern": {"points": points}})

        F = "pattern.points.base64"
        good = utk_bin([a])
        expect_400(ev({"format": "bin", "base64": b64(good[:19])}), F, "truncated")
        expect_400(ev({"format": "bin", "base64": b64(good[:-3])}), F, "truncated")
        expect_400(ev({"format": "bin", "base64": b64(good + b"xyz")}), F, "count mismatch")
        expect_400(ev({"format": "bin", "base64": b64(b"XTK!" + good[4:])}), F, "magic")
        expect_400(ev({"format": "bin", "base64": b64(utk_bin([[(0.1, 0.2, 0.3)]], d=3))}), F,
                   "dimension d is 3")
        expect_400(ev({"format": "bin", "base64": b64(utk_bin([[(0.1, math.nan)]]))}), F,
                   "point 0: y is not a finite number")
        expect_400(ev({"format": "bin", "base64": b64(utk_bin([[(0.5, 0.5)] * 4097]))}), F,
                   "N is 4097")
        expect_400(ev({"format": "bin", "base64": b64(utk_bin([a, b]))}), "pattern.points.set",
                   "2 sets")
        expect_400(ev({"format": "rps", "base64": b64(b"\0" * 12)}), F, "whole number")
        expect_400(ev({"format": "rps", "base64": b64(struct.pack("<ff", math.inf, 0.5))}), F,
                   "point 0: x is not a finite number")
        expect_400(ev({"format": "rps", "base64": b64(struct.pack("<f", 0.5) * 2 * 4097)}), F,
                   "more than 4096")
        expect_400(ev({"format": "rps", "base64": "AAA*"}), F, "not base64")
        expect_400(ev({"format": "rps", "text": "0.5 0.5"}), "pattern.points.text", "base64")
        expect_400(ev({"format": "bin", "base64": b64(good), "text": "x"}), "pattern.points.base64")
        expect_400(d.request("POST", "/v1/patterns/export", {"pattern": {"preset": "rgss"},
                                                             "format": "mtl"}), "format")
        check(not d.sanitizer_reports(), d.log_text())
    finally:
        d.stop()
    print("round trip: bin worst |dE2| = %.3g over %d presets; rps |dE2| = %.3g; "
          "analyze all: worst |radial - mean| = %.3g" % (worst_bin, len(presets), worst_rps,
                                                           worst_avg))
    print("e2e_formats: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
