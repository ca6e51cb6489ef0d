"""aalab.formats: the point-set reader and writer offline (the daemon's rules and messages),
and round trips through the daemon: export -> import gives the same E2 to 1e-12 for every
preset and for jobs' best P(4,1+,2) and P(16,16,4) patterns."""

import json

import numpy as np
import pytest

import aalab
from aalab import formats

POINT_FORMATS = ("utk", "xyw", "csv", "points-json")


def fmt_of(export_format):
    return "json" if export_format == "points-json" else export_format


# -- offline ----------------------------------------------------------------------------------

def test_utk_and_xyw():
    ps = formats.loads("# made by hand\n\n0.25 0.5\n  0.75\t0.125  \n", "utk")
    assert ps.points == ((0.25, 0.5), (0.75, 0.125)) and ps.weights is None and ps.meta is None
    assert ps.xy.shape == (2, 2) and ps.w is None and len(ps) == 2
    w = formats.loads("0 0 0.5\r\n1e-1 .5 5.e-1\r\n", "xyw")
    assert w.points == ((0.0, 0.0), (0.1, 0.5)) and w.weights == (0.5, 0.5)
    np.testing.assert_array_equal(w.w, [0.5, 0.5])


def test_header():
    ps = formats.loads('# aalab-pattern {"tile": 2, "kernel": 1}\n0.1 0.2\n', "utk")
    assert ps.meta == {"tile": 2, "kernel": 1}
    assert formats.loads("# aalab-patternless comment\n0 0\n", "utk").meta is None


BAD_TEXTS = [
    ("0.1\n", "utk", "line 1: expected 2 numbers (x y)"),
    ("0.1 0.2 0.3\n", "utk", "line 1: expected 2 numbers (x y)"),
    ("0 0\n\n1 2 3 4\n", "xyw", "line 3: expected 2 or 3 numbers (x y [w])"),
    ("0.1 0.2 0.3\n0.1 0.2\n", "xyw", "line 2: 2 numbers, but line 1 has 3"),
    ("0 nan\n", "xyw", "line 1: 'nan' is not a number"),
    ("0 1_0\n", "xyw", "line 1: '1_0' is not a number"),
    ("0 0x1p3\n", "xyw", "line 1: '0x1p3' is not a number"),
    ("# only comments\n", "utk", "no points"),
    ("0 0\n# aalab-pattern {}\n", "utk", "line 2: the aalab-pattern header must come before"),
    ('# aalab-pattern {}\n# aalab-pattern {}\n0 0\n', "utk", "line 2: a second aalab-pattern"),
    ("# aalab-pattern [1]\n0 0\n", "utk", "line 1: the aalab-pattern header is not a JSON object"),
    ("x,y,z\n0,0,0\n", "csv", "line 1: unknown column 'z'"),
    ("x,y,w,q\n", "csv", "line 1: unknown column 'q'"),
    ("a,b,c,d,e,f,g,h,i\n", "csv", "line 1: more than 8 columns"),
    ("x,x\n", "csv", "line 1: column x twice"),
    ("x,w\n", "csv", "line 1: the header line must name columns x and y"),
    ("0.1,0.2\n", "csv", "line 1: unknown column '0.1'"),
    ("x,y\n0.1\n", "csv", "line 2: 1 field, but the header (line 1) names 2"),
    ("x,y\n0,1,2\n", "csv", "line 2: 3 fields, but the header (line 1) names 2"),
    ("x,y\n0,1,2,3,4,5,6,7,8\n", "csv", "line 2: more than 8 fields, but the header (line 1) names 2"),
    ("y,x\n0,a\n", "csv", "line 2: x: 'a' is not a number"),
    ("\n", "csv", "no header line"),
    ("[[0, 0], [1]]", "json", "point 1: a point is [x, y] or [x, y, w]"),
    ('[{"x": 0, "y": 0, "z": 1}]', "json", "point 0: unknown key 'z'"),
    ('[[0, 0, 1], [0, 0]]', "json", "point 1: has no w but point 0 has"),
    ('[[0, true]]', "json", "point 0: y must be a finite number"),
    ('[]', "json", "no points"),
    ('{"points": [[0, 0]], "x": 1}', "json", "unknown field"),
    ('[[0, 0]', "json", "line 1: not valid JSON"),
]


@pytest.mark.parametrize("text,fmt,message", BAD_TEXTS)
def test_errors_name_the_line(text, fmt, message):
    with pytest.raises(formats.FormatError) as e:
        formats.loads(text, fmt)
    assert e.value.message.startswith(message), e.value.message
    assert e.value.field.startswith("pattern.points.text") and e.value.code == "invalid_field"


@pytest.mark.parametrize("text,fmt,message", BAD_TEXTS)
def test_daemon_gives_the_same_errors(client, text, fmt, message):
    # The package's reader and the daemon's C codec (proto/pointset_parse.c) agree word for word.
    with pytest.raises(formats.FormatError) as local:
        formats.loads(text, fmt)
    with pytest.raises(aalab.AalabError) as remote:
        client.evaluate({"points": {"format": fmt, "text": text, "weights": "equal"}})
    assert remote.value.status == 400
    if message.endswith("not valid JSON"):  # the rest is the JSON parser's own words
        assert remote.value.message.startswith(message)
    else:
        assert remote.value.message == local.value.message
    assert remote.value.field == local.value.field


def test_csv_and_json_forms():
    c = formats.loads('# aalab-pattern {"a": 1}\n# note\n W , "x",y\n0.5,0.25,0.75\n\n', "csv")
    assert c.points == ((0.25, 0.75),) and c.weights == (0.5,) and c.meta == {"a": 1}
    j = formats.loads('[{"x": 0.5, "y": 0.25, "w": 1}, [0.1, 0.2, 0]]', "json")
    assert j.points == ((0.5, 0.25), (0.1, 0.2)) and j.weights == (1.0, 0.0)
    o = formats.loads('{"aalab": {"tile": 1}, "points": [[0.5, 0.5]]}', "json")
    assert o.meta == {"tile": 1} and o.weights is None


@pytest.mark.parametrize("fmt", [f for f in formats.FORMATS if f not in formats.BINARY_FORMATS])
def test_write_read_is_exact(tmp_path, fmt):
    rng = np.random.default_rng(5)
    pts = rng.random((50, 2))
    w = rng.normal(size=50)
    meta = {"tile": 1, "note": "x"}
    path = tmp_path / ("p." + {"utk": "dat", "xyw": "txt", "csv": "csv", "json": "json"}[fmt])
    formats.write(path, pts, weights=None if fmt == "utk" else w, meta=meta)
    back = formats.read(path)
    assert back.format == fmt and back.meta == meta
    np.testing.assert_array_equal(back.xy, pts)  # bit-exact: repr of every double
    if fmt != "utk":
        np.testing.assert_array_equal(back.w, w)
    # A PointSet written again keeps its header and weights.
    assert formats.loads(formats.dumps(back, fmt), fmt) == formats.loads(back.text, fmt)


def test_writer_refuses_what_it_cannot_write(tmp_path):
    with pytest.raises(aalab.AalabError) as e:
        formats.dumps([[0, 0, 1]], "utk")
    assert "weight" in e.value.message
    with pytest.raises(aalab.AalabError):
        formats.dumps([[0, 0]], "svg")
    with pytest.raises(aalab.AalabError):
        formats.dumps([[0, float("nan")]], "xyw")
    with pytest.raises(aalab.AalabError) as e:
        formats.write(tmp_path / "p.xyz", [[0, 0]])
    assert "suffix" in e.value.message
    with pytest.raises(formats.FormatError) as e:
        (tmp_path / "bad.dat").write_text("0 0\n0\n")
        formats.read(tmp_path / "bad.dat")
    assert str(tmp_path / "bad.dat") in e.value.message and "line 2" in e.value.message


def test_to_pattern():
    ps = formats.loads("0.25 0.25\n0.75 0.75\n", "utk")
    with pytest.raises(aalab.AalabError) as e:
        ps.to_pattern()
    assert e.value.field == "pattern.points.weights" and "filter or equal" in e.value.message
    p = ps.to_pattern(tile=2, weights="equal", border=False)
    assert p == {"points": {"format": "utk", "text": ps.text, "tile": 2, "border": False,
                            "weights": "equal"}}
    arr = aalab.as_pattern(np.array([[0.5, 0.5, 1.0]]))
    assert arr == {"points": {"format": "json", "data": [[0.5, 0.5, 1.0]]}}
    with pytest.raises(aalab.AalabError) as e:
        aalab.as_pattern(np.zeros((3, 4)))
    assert e.value.field == "pattern.points.data[0]"
    with pytest.raises(aalab.AalabError):
        ps.to_pattern(weights="heavy")


def test_pattern_arguments(tmp_path):
    assert aalab.as_pattern("rgss") == {"preset": "rgss"}
    assert aalab.as_pattern({"mirrored": [[0, 0, 1]]}) == {"mirrored": [[0, 0, 1]]}
    assert aalab.as_pattern({"pattern": {"preset": "x"}, "format": "json"}) == {"preset": "x"}
    f = tmp_path / "pts.csv"
    f.write_text("x,y,w\n0.5,0.5,1\n")
    assert aalab.as_pattern(f)["points"]["format"] == "csv"
    assert aalab.as_pattern(str(f), tile=2)["points"]["tile"] == 2
    j = tmp_path / "pts.json"
    j.write_text('{"aalab": {"tile": 1}, "points": [[0.5, 0.5]]}')
    assert aalab.as_pattern(j)["points"]["format"] == "json"
    with pytest.raises(aalab.AalabError) as e:
        aalab.as_pattern(tmp_path / "missing.dat")
    assert "no such file" in e.value.message


# -- through the daemon -----------------------------------------------------------------------

@pytest.fixture(scope="module")
def preset_names(daemon):
    return [p["name"] for p in aalab.Client(daemon.socket_path).presets()]


def assert_round_trips(client, source, e2, tmp_path):
    """Every point format, exported by the daemon, read by aalab.formats and by the daemon
    (as text and as a file), and written again by aalab.formats, gives E2 to 1e-12."""
    for ef in POINT_FORMATS:
        out = client.export(source, ef)
        text = json.dumps(out) if ef == "points-json" else out
        ps = formats.loads(text, fmt_of(ef))
        assert ps.meta is not None
        assert client.evaluate(ps).e2 == pytest.approx(e2, abs=1e-12), ef
        rewritten = formats.loads(formats.dumps(ps, fmt_of(ef)), fmt_of(ef))
        assert client.evaluate(rewritten).e2 == pytest.approx(e2, abs=1e-12), ef
        suffix = {"utk": ".dat", "xyw": ".txt", "csv": ".csv", "points-json": ".json"}[ef]
        path = tmp_path / ("pattern" + suffix)
        client.export(source, ef, path=path)
        assert client.evaluate(path).e2 == pytest.approx(e2, abs=1e-12), ef


def test_every_preset_round_trips(client, preset_names, tmp_path):
    assert len(preset_names) >= 20
    for name in preset_names:
        assert_round_trips(client, name, client.evaluate(name).e2, tmp_path)


@pytest.mark.parametrize("family,seeds,iters", [("P(4,1+,2)", 2, 30), ("P(16,16,4)", 1, 3)])
def test_job_best_round_trips(client, family, seeds, iters, tmp_path):
    job = client.optimize(family=family, seeds=seeds, max_iterations=iters, rng_seed=11)
    job.wait(progress=False, timeout=120)
    e2 = job.best_e2
    assert client.evaluate(job.best_pattern).e2 == pytest.approx(e2, abs=1e-12)
    assert_round_trips(client, job, e2, tmp_path)
    assert_round_trips(client, job.best_pattern, e2, tmp_path)  # POST /v1/patterns/export


def test_points_without_header(client):
    # RGSS in the unit square of a 1-pixel tile (kernel samples + 0.5), equal weights.
    k = client.preset("rgss")["pattern"]["kernels"][0]
    pts = np.array([[x + 0.5, y + 0.5] for x, y, _ in k])
    rgss = client.evaluate("rgss").e2
    assert client.evaluate(aalab.as_pattern(pts, weights="equal")).e2 == pytest.approx(rgss,
                                                                                      abs=1e-12)
    with_w = np.column_stack([pts, [w for _, _, w in k]])
    assert client.evaluate(with_w).e2 == pytest.approx(rgss, abs=1e-12)
    with pytest.raises(aalab.AalabError) as e:  # the daemon's own check of the same points
        client.evaluate({"points": {"format": "json", "data": pts.tolist()}})
    assert e.value.field == "pattern.points.weights" and e.value.status == 400
    with pytest.raises(aalab.AalabError) as e:
        client.evaluate({"points": {"format": "xyw", "text": "0.1 0.2\n0.3\n", "weights": "equal"}})
    assert e.value.field == "pattern.points.text" and "line 2" in e.value.message
    with pytest.raises(aalab.AalabError) as e:
        client.evaluate({"points": {"format": "json", "data": [[0.1, 0.2], [0.3]],
                                    "weights": "equal"}})
    assert e.value.field == "pattern.points.data[1]"


def test_points_given_as_arrays_are_checked():
    with pytest.raises(aalab.AalabError) as e:
        formats.dumps([[0, 0, 1], [0, 0]], "xyw")
    assert e.value.field == "points[1]" and "weight" in e.value.message
    with pytest.raises(aalab.AalabError) as e:
        formats.dumps([[0, "a"]], "xyw")
    assert e.value.field == "points[0]"
    with pytest.raises(aalab.AalabError) as e:
        formats.dumps([[0, 0]], "xyw", weights=[float("inf")])
    assert e.value.field == "weights[0]"
    with pytest.raises(aalab.AalabError) as e:
        formats.dumps([[0, 0]], "xyw", weights=[1, 2])
    assert e.value.field == "weights"
    with pytest.raises(aalab.AalabError):
        formats.dumps([], "csv")
    ps = formats.loads("0.5 0.5 1\n", "xyw")
    assert formats.dumps(ps, "csv", weights=[0.25]) == "x,y,w\n0.5,0.5,0.25\n"
    with pytest.raises(aalab.AalabError) as e:
        aalab.as_pattern([[0.1, 0.2], [0.3, 0.4, 1.0]])
    assert e.value.field == "pattern.points.data[1]"
