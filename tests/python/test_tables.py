"""Issue 34: each job kind's result as a table, a pandas DataFrame (to_frame, python3-pandas)
and a Jupyter HTML table (_repr_html_), from recorded daemon answers (tests/client/fixtures),
and a live job's."""

import csv
import html.parser
import io
import json
import os

import pytest

import aalab

FIXTURES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "client", "fixtures")
KINDS = ["optimize", "family-sweep", "random-stats", "table3", "compare", "animation",
         "reference-convergence", "temporal-optimize", "temporal-render"]


def fixture(kind):
    with open(os.path.join(FIXTURES, "job_%s.json" % kind)) as f:
        return json.load(f)


class _Cells(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.head, self.rows, self._cell, self._in = [], [], None, None

    def handle_starttag(self, tag, attrs):
        if tag == "tr":
            self.rows.append([])
        if tag in ("th", "td"):
            self._in, self._cell = tag, ""

    def handle_data(self, data):
        if self._in:
            self._cell += data

    def handle_endtag(self, tag):
        if tag in ("th", "td") and self._in:
            (self.head if tag == "th" else self.rows[-1]).append(self._cell)
            self._in = None


def expected_rows(kind, result):
    """How many rows each kind's table has, from its result."""
    key = {"optimize": "per_seed", "family-sweep": "ranked", "table3": "rows",
           "compare": "rows", "animation": "frames", "reference-convergence": "rows",
           "temporal-optimize": "per_seed", "temporal-render": "phases"}
    return 1 if kind == "random-stats" else len(result[key[kind]])


@pytest.mark.parametrize("kind", KINDS)
def test_every_kind_has_a_table_with_unique_ascii_columns(kind):
    job = fixture(kind)
    t = aalab.result_table(kind, job["result"])
    assert t.kind == kind
    assert len(t) == expected_rows(kind, job["result"]) > 0
    assert len(set(t.columns)) == len(t.columns), t.columns
    assert all(c.isascii() and c.isidentifier() for c in t.columns), t.columns
    assert all(len(r) == len(t.columns) for r in t.rows)
    # The same columns read back through Python's csv module.
    buf = io.StringIO()
    csv.writer(buf).writerows([t.columns] + t.rows)
    back = list(csv.reader(io.StringIO(buf.getvalue())))
    assert back[0] == t.columns and len(back) == len(t) + 1


def test_table_values_are_the_results():
    r = fixture("optimize")["result"]
    t = aalab.result_table("optimize", r)
    assert [x["e2"] for x in t.records()] == [s["e2"] for s in r["per_seed"]]
    r = fixture("table3")["result"]
    t = aalab.result_table("table3", r)
    first = t.records()[0]
    cols = r["rows"][0]["columns"]
    assert first["opt_wp"] == cols["opt_wp"]["mean"] and first["opt_wp_sd"] == cols["opt_wp"]["sd"]
    assert first["min_paper"] == cols["min"].get("paper")
    r = fixture("random-stats")["result"]
    rec = aalab.result_table("random-stats", r).records()[0]
    assert (rec["min"], rec["opt_w"], rec["opt_wp"]) == (r["random"]["min"], r["opt_w"]["e2"],
                                                         r["opt_wp"]["e2"])
    r = fixture("temporal-optimize")["result"]
    t = aalab.result_table("temporal-optimize", r)
    assert t.columns == ["seed", "start", "initial_score", "score", "e2", "f2"]
    assert [(x["start"], x["score"], x["f2"]) for x in t.records()] == \
        [(s["start"], s["score"], s["f2"]) for s in r["per_seed"]]
    assert min(x["e2"] for x in t.records()) == r["e2"]
    r = fixture("temporal-render")["result"]
    t = aalab.result_table("temporal-render", r)
    assert t.columns == ["phase", "e2", "rmse", "max_dev", "predicted_rmse", "ratio"]
    assert [(x["rmse"], x["predicted_rmse"], x["ratio"]) for x in t.records()] == \
        [(p["rmse"], p["predicted_rmse"], p["ratio"]) for p in r["phases"]]
    assert max(x["e2"] for x in t.records()) == r["e2"]
    assert "worst phase %d" % r["steady"]["worst_phase"] in t.caption
    # A kind without a table of its own: key,value rows; no result: no rows.
    assert aalab.result_table("sleep", {"elapsed": 1.5}).rows == [["elapsed", 1.5]]
    assert len(aalab.result_table("compare", None)) == 0


@pytest.mark.parametrize("kind", KINDS)
def test_repr_html_is_the_table(kind):
    job = fixture(kind)
    t = aalab.result_table(kind, job["result"])
    p = _Cells()
    p.feed(t._repr_html_())
    assert p.head == t.columns
    body = [r for r in p.rows if r]
    assert len(body) == len(t)
    assert all(len(r) == len(t.columns) for r in body)


@pytest.mark.parametrize("kind", KINDS)
def test_to_frame(kind):
    pd = pytest.importorskip("pandas")
    job = fixture(kind)
    t = aalab.result_table(kind, job["result"])
    f = t.to_frame()
    assert isinstance(f, pd.DataFrame)
    assert list(f.columns) == t.columns and len(f) == len(t)
    assert f.attrs["kind"] == kind


def test_live_job_to_frame_and_html(client, opt_job):
    job = client.job(opt_job.id)
    t = job.table()
    assert t.columns == ["seed", "distribution", "initial_e2", "e2", "iterations"]
    assert len(t) == 2 and min(r["e2"] for r in t.records()) >= opt_job.best_e2 - 1e-12
    page = job._repr_html_()
    assert page.startswith("<p><b>aalab job %d</b> optimize, done</p>" % opt_job.id)
    assert '<table class="aalab-result" data-kind="optimize">' in page
    try:
        import pandas  # noqa: F401
    except ImportError:
        return
    f = job.to_frame()
    assert list(f["seed"]) == [0, 1]


def test_live_temporal_jobs_to_frame_and_html(client):
    """The two temporal kinds (issue 30), small, through Job.table/_repr_html_/to_frame."""
    opt = client.submit({"kind": "temporal-optimize", "family": "T(4)", "seeds": 1,
                         "max_iterations": 3}).wait(progress=False, timeout=120)
    t = opt.table()
    assert t.columns == ["seed", "start", "initial_score", "score", "e2", "f2"]
    assert len(t) == 1 and t.records()[0]["e2"] == opt.result["e2"]
    assert '<table class="aalab-result" data-kind="temporal-optimize">' in opt._repr_html_()
    ren = client.submit({"kind": "temporal-render",
                         "scene": {"name": "siemens-star", "width": 32, "height": 32},
                         "pattern": {"temporal": {"preset": "halton23-8"}},
                         "reference": {"spp": 16}}).wait(progress=False, timeout=120)
    t = ren.table()
    assert [r["phase"] for r in t.records()] == list(range(8))
    assert max(r["e2"] for r in t.records()) == ren.result["e2"]
    assert '<table class="aalab-result" data-kind="temporal-render">' in ren._repr_html_()
    try:
        import pandas  # noqa: F401
    except ImportError:
        return
    f = ren.to_frame()
    assert list(f["ratio"]) == [p["ratio"] for p in ren.result["phases"]]
