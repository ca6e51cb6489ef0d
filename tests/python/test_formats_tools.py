"""aalab.formats: the sampling tools' formats (issue 31), offline and in step with the daemon's
parser (proto/pointset_binary.c, pointset_parse.c): UTK's binary .bin, PSA's raw float32 .rps,
several '#'-separated sets in one text; round trips through the daemon keep E2 to 1e-12 (bin
for every preset; rps for float32 points); analyze(set="all") averages as pbrt's pspec."""

import math
import struct

import numpy as np
import pytest

import aalab
from aalab import formats

MAGIC = 0x214B5455


def utk_bin(sets, dtype=5, d=2, n=None):
    n = len(sets[0]) if n is None else n
    head = struct.pack("<IB3xIII", MAGIC, dtype, len(sets), n, d)
    f = "<d" if dtype == 5 else "<f"
    return head + b"".join(struct.pack(f, v) for s in sets for p in s for v in p)


A = [((i + 0.5) / 8, ((i * 3) % 8 + 0.25) / 8) for i in range(8)]
B = [((i * 5 % 8 + 0.75) / 8, (i + 0.5) / 8) for i in range(8)]


# -- offline ----------------------------------------------------------------------------------

def test_bin_and_rps_read():
    ps = formats.loads_bytes(utk_bin([A, B]), "bin", set=1)
    assert ps.points == tuple(B) and ps.set == 1 and ps.weights is None
    assert formats.count_sets(utk_bin([A, B]), "bin") == 2
    f32 = formats.loads_bytes(utk_bin([A], dtype=4), "bin")
    assert f32.points == tuple(A)  # eighths are float32 numbers
    r = formats.loads_bytes(struct.pack("<4f", 0.25, 0.5, 0.75, 0.125), "rps")
    assert r.points == ((0.25, 0.5), (0.75, 0.125)) and r.format == "rps"


def test_text_sets():
    text = ("# made by a sampler\n0.1 0.2\n0.3 0.4\n#\n\n0.5 0.5\n0.25 0.75\n# set 2\n"
            "0.9 0.9\nbad\n#\n")
    assert formats.count_sets(text, "utk") == 3 and formats.count_sets(text, "csv") == 1
    s1 = formats.loads(text, "utk", set=1)
    assert s1.points == ((0.5, 0.5), (0.25, 0.75)) and s1.text == text and s1.set == 1
    with pytest.raises(formats.FormatError) as e:
        formats.loads(text, "utk", set=2)
    assert e.value.message == "line 10: 'bad' is not a number"
    with pytest.raises(formats.FormatError) as e:
        formats.loads(text, "utk", set=3)
    assert e.value.field == "pattern.points.set" and "holds 3 sets" in e.value.message


BAD_BYTES = [  # (bytes, fmt, set, field, message): word for word the daemon's
    (utk_bin([A])[:19], "bin", None, "base64",
     "truncated: 19 bytes, but UTK's header alone is 20"),
    (utk_bin([A])[:-3], "bin", None, "base64", "truncated: the header says m = 1 sets of N = 8"),
    (utk_bin([A]) + b"xyz", "bin", None, "base64", "count mismatch: the header says m = 1"),
    (b"XTK!" + utk_bin([A])[4:], "bin", None, "base64", "bytes 0-3: magic is 0x214B5458"),
    (utk_bin([A], dtype=0)[:20] + b"\0" * 64, "bin", None, "base64", "byte 4: dtype is 0 (int32)"),
    (utk_bin([[(0.1, 0.2, 0.3)]], d=3), "bin", None, "base64", "bytes 16-19: dimension d is 3"),
    (utk_bin([[(0.1, math.nan)]]), "bin", None, "base64", "point 0: y is not a finite number (nan)"),
    (utk_bin([[(0.5, 0.5)] * 4097]), "bin", None, "base64", "bytes 12-15: N is 4097"),
    (utk_bin([A, B]), "bin", None, "set", "the file holds 2 sets (UTK's m); choose one with set"),
    (utk_bin([A, B]), "bin", 2, "set", "is 2 but the file holds 2 sets"),
    (b"\0" * 12, "rps", None, "base64", "truncated: 12 bytes is not a whole number of points"),
    (b"", "rps", None, "base64", "no points (an empty file)"),
    (struct.pack("<ff", math.inf, 0.5), "rps", None, "base64",
     "point 0: x is not a finite number (inf)"),
    (struct.pack("<f", 0.5) * 2 * 4097, "rps", None, "base64", "4097 points, more than 4096"),
    (struct.pack("<ff", 0.5, 0.5), "rps", 1, "set", "is 1 but an rps file holds one set"),
]


@pytest.mark.parametrize("data,fmt,set_,field,message", BAD_BYTES)
def test_binary_errors(data, fmt, set_, field, message):
    with pytest.raises(formats.FormatError) as e:
        formats.loads_bytes(data, fmt, set_)
    assert e.value.field == "pattern.points." + field
    assert e.value.message.startswith(message), e.value.message


@pytest.mark.parametrize("data,fmt,set_,field,message", BAD_BYTES)
def test_daemon_gives_the_same_binary_errors(client, data, fmt, set_, field, message):
    import base64
    with pytest.raises(formats.FormatError) as local:
        formats.loads_bytes(data, fmt, set_)
    body = {"format": fmt, "base64": base64.b64encode(data).decode(), "weights": "equal"}
    if set_ is not None:
        body["set"] = set_
    with pytest.raises(aalab.AalabError) as remote:
        client.evaluate({"points": body})
    assert remote.value.status == 400
    assert (remote.value.field, remote.value.message) == (local.value.field, local.value.message)


def test_write_read(tmp_path):
    rng = np.random.default_rng(3)
    pts = rng.random((40, 2))
    meta = {"tile": 1, "note": "x"}
    p = formats.write(tmp_path / "p.bin", pts, meta=meta)
    back = formats.read(p)
    assert back.meta == meta and back.format == "bin"
    np.testing.assert_array_equal(back.xy, pts)  # float64: exact
    r = formats.read(formats.write(tmp_path / "p.rps", pts))
    np.testing.assert_array_equal(r.xy, pts.astype(np.float32).astype(float))
    with pytest.raises(aalab.AalabError):
        formats.dumps_bytes(pts, "rps", meta=meta)  # rps has no room for a header
    with pytest.raises(aalab.AalabError):
        formats.write(tmp_path / "w.bin", pts, weights=np.ones(40))


# -- through the daemon -----------------------------------------------------------------------

SET_CASES = [  # (text, fmt, set): errors of a set, word for word the daemon's
    ("0.1 0.1\n#\n0.5 x\n", "utk", 1),
    ("0.1 0.1\n#\n0.5 0.5\n", "utk", 2),
    ("0.1 0.1 1\n#\n0.5 0.5\n# c\n\n0.3\n", "xyw", 2),
    ("x,y\n0.5,0.5\n", "csv", 0),
    ('# aalab-pattern {"tile":1,"weights":[[1]]}\n0.5 0.5\n# aalab-pattern {"tile":1}\n0.5 0.5\n',
     "utk", None),
]


@pytest.mark.parametrize("text,fmt,set_", SET_CASES)
def test_daemon_gives_the_same_set_errors(client, text, fmt, set_):
    with pytest.raises(formats.FormatError) as local:
        formats.loads(text, fmt, set=set_)
    body = {"format": fmt, "text": text, "weights": "equal"}
    if set_ is not None:
        body["set"] = set_
    with pytest.raises(aalab.AalabError) as remote:
        client.evaluate({"points": body})
    assert (remote.value.field, remote.value.message) == (local.value.field, local.value.message)


@pytest.fixture(scope="module")
def preset_names(daemon):
    return [p["name"] for p in aalab.Client(daemon.socket_path).presets()]


def test_every_preset_round_trips_as_bin(client, preset_names, tmp_path):
    worst = 0.0
    for name in preset_names:
        e2 = client.evaluate(name).e2
        data = client.export(name, "bin", path=tmp_path / "p.bin")
        assert isinstance(data, bytes) and data[:4] == b"UTK!"
        local = formats.read(tmp_path / "p.bin")
        assert local.meta is not None
        got = client.evaluate(tmp_path / "p.bin").e2
        assert abs(got - e2) <= 1e-12, name
        # the package's own writer gives the daemon's bytes (the header's numbers may be
        # spelled differently: jansson writes 17 digits, Python the shortest)
        mine, end = formats.dumps_bytes(local, "bin"), 20 + 16 * len(local)
        assert mine[:end] == data[:end], name
        assert formats.loads_bytes(mine, "bin").meta == local.meta
        worst = max(worst, abs(got - e2))
    print("bin round trip over %d presets: worst |dE2| = %.3g" % (len(preset_names), worst))


def test_rps_round_trip(client, tmp_path):
    pts = np.random.default_rng(8).random((16, 2)).astype(np.float32).astype(float)
    opts = dict(tile=2, kernel=2, weights="filter")
    e2 = client.evaluate(aalab.as_pattern(pts, **opts)).e2
    data = client.export(aalab.as_pattern(pts, **opts), "rps")
    assert data == formats.dumps_bytes(pts, "rps")
    path = tmp_path / "p.rps"
    path.write_bytes(data)
    assert abs(client.evaluate(aalab.as_pattern(path, **opts)).e2 - e2) <= 1e-12


def test_sets_and_analyze_all(client, preset_names, tmp_path):
    names = preset_names[:3]
    cat = "".join(client.export(n, "utk") for n in names)
    (tmp_path / "three.dat").write_text(cat)
    for i, n in enumerate(names):
        ps = formats.read(tmp_path / "three.dat", set=i)
        assert abs(client.evaluate(ps).e2 - client.evaluate(n).e2) <= 1e-12
    assert [s.set for s in formats.read_sets(tmp_path / "three.dat")] == [0, 1, 2]
    # pspec's averaging: the mean radial spectrum of two sets
    path = tmp_path / "two.bin"
    path.write_bytes(utk_bin([A, B]))
    mean = client.analyze(aalab.as_pattern(path, weights="equal", set="all"), radius=8)
    one = [client.analyze(formats.read(path, set=i).to_pattern(weights="equal"), radius=8)
           for i in range(2)]
    np.testing.assert_allclose(mean.radial, (np.asarray(one[0].radial) + one[1].radial) / 2,
                               rtol=1e-12, atol=1e-12)
    assert mean.raw["sets"]["count"] == 2 and len(mean.raw["sets"]["per_set"]) == 2
    with pytest.raises(aalab.AalabError) as e:
        client.analyze(tmp_path / "three.dat", set="all")  # presets of different sizes
    assert e.value.field == "pattern.points.set"
