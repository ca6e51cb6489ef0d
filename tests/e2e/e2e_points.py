"""End-to-end: point sets in and out of the daemon. Every export format of a job's best pattern
(P(4,1+,2) and P(16,16,4), short reproducible optimize jobs) and of every preset reads back
through the "points" pattern form with the same E2 to 1e-12; POST /v1/patterns/export exports
any pattern; bad point sets are 400s naming the field and the line. Every answer is checked
against its JSON Schema (response_check)."""

import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, ".."))

import aalabd_harness  # noqa: E402
import response_check  # noqa: E402
from aalabd_harness import Daemon  # noqa: E402

TOLERANCE = 1e-12
TEXT_FORMATS = ("utk", "xyw", "csv")


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def e2_of(d, pattern):
    r = d.request("POST", "/v1/evaluate", {"pattern": pattern})
    check(r.status == 200, (r.status, r.body[:400]))
    return r.json()["e2"]


def reimport(fmt, body):
    """The exported answer as a points pattern."""
    if fmt == "points-json":
        return {"points": {"format": "json", "data": json.loads(body)}}
    return {"points": {"format": fmt, "text": body.decode("utf-8")}}


def round_trip(d, what, export, want):
    """export(fmt) -> response; worst |E2 difference| over the point-set formats."""
    worst = 0.0
    for fmt in TEXT_FORMATS + ("points-json",):
        r = export(fmt)
        check(r.status == 200, (what, fmt, r.status, r.body[:300]))
        ctype = r.headers.get("content-type", "")
        check(ctype.startswith("application/json" if fmt == "points-json" else "text/plain"),
              (what, fmt, ctype))
        if fmt in TEXT_FORMATS:
            check(r.body.startswith(b"# aalab-pattern {"), (what, fmt, r.body[:80]))
        got = e2_of(d, reimport(fmt, r.body))
        diff = abs(got - want)
        check(diff <= TOLERANCE, "%s as %s: E2 %.17g read back as %.17g" % (what, fmt, want, got))
        worst = max(worst, diff)
    # points-json also as a JSON text
    r = export("points-json")
    got = e2_of(d, {"points": {"format": "json", "text": r.body.decode("utf-8")}})
    check(abs(got - want) <= TOLERANCE, (what, "json text", got, want))
    return worst


def wait_done(d, jid, timeout=240):
    deadline = time.time() + timeout
    while time.time() < deadline:
        j = d.request("GET", "/v1/jobs/%d" % jid).json()
        if j["state"] in ("done", "failed", "cancelled", "interrupted"):
            check(j["state"] == "done", j)
            return j
        time.sleep(0.2)
    raise AssertionError("job %d did not finish" % jid)


def expect_400(r, field, message_part=None):
    check(r.status == 400, (r.status, r.body[:300]))
    err = r.json()["error"]
    check(err["field"] == field, (field, err))
    if message_part:
        check(message_part in err["message"], (message_part, err))


def main():
    if len(sys.argv) < 2:
        print("usage: e2e_points.py AALABD")
        return 2
    aalabd_harness.RESPONSE_HOOK = response_check.check
    d = Daemon(sys.argv[1], tcp=False).start()
    worst = {}
    try:
        # every preset through POST /v1/patterns/export
        presets = [p["name"] for p in d.request("GET", "/v1/presets").json()["presets"]]
        w = 0.0
        for name in presets:
            pat = {"preset": name}
            want = e2_of(d, pat)
            w = max(w, round_trip(d, name, lambda f, pat=pat: d.request(
                "POST", "/v1/patterns/export", {"pattern": pat, "format": f}), want))
        worst["presets"] = w

        # a job's best pattern through GET /v1/patterns/{job}/export
        for family in ("P(4,1+,2)", "P(16,16,4)"):
            r = d.request("POST", "/v1/jobs", {"kind": "optimize", "family": family, "seeds": 2,
                                               "max_iterations": 40, "rng_seed": 5})
            check(r.status == 202, r.body[:300])
            jid = r.json()["id"]
            job = wait_done(d, jid)
            want = e2_of(d, {"job": jid})
            check(abs(want - job["result"]["e2"]) <= TOLERANCE, (want, job["result"]["e2"]))
            worst[family] = round_trip(d, family, lambda f, jid=jid: d.request(
                "GET", "/v1/patterns/%d/export?format=%s" % (jid, f)), want)
            # the same text from both routes
            a = d.request("GET", "/v1/patterns/%d/export?format=csv" % jid).body
            b = d.request("POST", "/v1/patterns/export",
                          {"pattern": {"job": jid}, "format": "csv"}).body
            check(a == b, "GET and POST exports differ:\n%s\n%s" % (a[:300], b[:300]))
            # json keeps its old answer, with the job id
            j = d.request("GET", "/v1/patterns/%d/export?format=json" % jid).json()
            check(j["job"] == jid and j["pattern"]["family"] == family, j)

        # a posted pattern, json and GPU formats of POST
        pat = {"points": {"format": "utk", "text": "0.25 0.25\n0.75 0.75\n", "weights": "equal"}}
        j = d.request("POST", "/v1/patterns/export", {"pattern": pat, "format": "json"}).json()
        check("job" not in j and j["pattern"]["form"] == "tile", j)
        v = d.request("POST", "/v1/patterns/export", {"pattern": pat, "format": "vulkan"}).json()
        check(v["representable"] and v["sampleLocationsPerPixel"] == "VK_SAMPLE_COUNT_2_BIT", v)

        # weights from the request's filter
        pf = {"points": {"format": "utk", "text": "0.2 0.3\n0.7 0.6\n0.4 0.9\n",
                         "weights": "filter"}}
        mitchell = d.request("POST", "/v1/evaluate", {"pattern": pf}).json()["e2"]
        box = d.request("POST", "/v1/evaluate",
                        {"pattern": pf, "filter": {"name": "catmull-rom"}}).json()["e2"]
        tile = d.request("POST", "/v1/evaluate", {"pattern": {"tile": {
            "size": 1, "samples": [[0.2, 0.3], [0.7, 0.6], [0.4, 0.9]]}}}).json()["e2"]
        check(mitchell == tile, (mitchell, tile))
        check(box != mitchell, "weights follow the request's filter")

        # bad point sets: 400 naming the field and the line
        def ev(points):
            return d.request("POST", "/v1/evaluate", {"pattern": {"points": points}})
        expect_400(ev({"format": "utk", "text": "0.5 0.5\n"}), "pattern.points.weights",
                   "the points have no weights; choose filter or equal")
        expect_400(ev({"format": "xyw", "text": "0.1 0.2 1\n\n0.3\n"}), "pattern.points.text",
                   "line 3: expected 2 or 3 numbers")
        expect_400(ev({"format": "csv", "text": "x,y,z\n", "weights": "equal"}),
                   "pattern.points.text", "unknown column 'z'")
        expect_400(ev({"format": "json", "data": [[0.5, 0.5], [1, "a"]], "weights": "equal"}),
                   "pattern.points.data[1]")
        expect_400(ev({"format": "dat", "text": ""}), "pattern.points.format")
        expect_400(d.request("POST", "/v1/patterns/export", {"pattern": {"preset": "rgss"},
                                                             "format": "png"}), "format")
        expect_400(d.request("POST", "/v1/patterns/export", {"format": "csv"}), "pattern")
        expect_400(d.request("POST", "/v1/patterns/export", {"pattern": {"preset": "rgss"},
                                                             "format": "csv", "x": 1}), "x")
        r = d.request("GET", "/v1/patterns/export")
        check(r.status == 405, r.status)
        # a job spec takes the points form too
        r = d.request("POST", "/v1/jobs", {"kind": "optimize", "pattern": pf, "max_iterations": 5})
        check(r.status == 202, r.body[:300])
        wait_done(d, r.json()["id"])
        check(not d.sanitizer_reports(), d.log_text())
    finally:
        d.stop()
    for k, v in worst.items():
        print("round trip %s: worst |dE2| = %.3g over utk, xyw, csv, points-json" % (k, v))
    print("e2e_points: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
