"""aalab.Client against a real daemon: every public call, answers validated against
proto/schemas (the client fixture validates), errors, jobs, cancel, render."""

import json
import os
import socket
import subprocess
import sys

import numpy as np
import pytest

import aalab
from aalab import transport

# Laine & Aila Table 2, to the three digits printed there.
TABLE2 = {"grid-2x2": 0.698, "rgss": 0.439, "quincunx": 0.518, "flipquad": 0.364,
          "fliptri": 0.636}


def test_import_and_client_need_no_daemon(tmp_path):
    env = dict(os.environ, AALAB_SOCKET=str(tmp_path / "none.sock"))
    code = ("import aalab, aalab.formats, aalab.plot, aalab.schemas\n"
            "c = aalab.Client()\n"
            "try:\n"
            "    c.health()\n"
            "except aalab.DaemonUnreachable as e:\n"
            "    print(e.code, e.message)\n")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("unreachable ")
    assert str(tmp_path / "none.sock") in out.stdout and "$AALAB_SOCKET" in out.stdout


def test_socket_discovery_follows_the_c_client(tmp_path, monkeypatch):
    monkeypatch.setenv("AALAB_SOCKET", "/x/explicit-env.sock")
    assert transport.resolve_socket("/given.sock")[0] == "/given.sock"
    assert transport.resolve_socket()[0] == "/x/explicit-env.sock"
    monkeypatch.delenv("AALAB_SOCKET")
    # $XDG_RUNTIME_DIR: used only if a socket is there, else the system socket.
    monkeypatch.setenv("XDG_RUNTIME_DIR", str(tmp_path))
    assert transport.resolve_socket()[0] == transport.SYSTEM_SOCKET
    (tmp_path / "aalab").mkdir()
    s = socket.socket(socket.AF_UNIX)
    s.bind(str(tmp_path / "aalab" / "aalabd.sock"))
    try:
        assert transport.resolve_socket()[0] == str(tmp_path / "aalab" / "aalabd.sock")
        # Without $XDG_RUNTIME_DIR: TMP_DIR/aalab-UID/aalabd.sock if the directory is ours.
        monkeypatch.delenv("XDG_RUNTIME_DIR")
        monkeypatch.setattr(transport, "TMP_DIR", str(tmp_path))
        monkeypatch.setattr(os, "geteuid", lambda: 4242)
        assert transport.resolve_socket()[0] == transport.SYSTEM_SOCKET  # no aalab-4242 dir
        own = tmp_path / ("aalab-%d" % os.getuid())
        own.mkdir(mode=0o700)
        s2 = socket.socket(socket.AF_UNIX)
        s2.bind(str(own / "aalabd.sock"))
        try:
            monkeypatch.setattr(os, "geteuid", os.getuid)
            assert transport.resolve_socket()[0] == str(own / "aalabd.sock")
            # Someone else's directory is not trusted.
            monkeypatch.setattr(os, "geteuid", lambda: os.getuid() + 1)
            other = tmp_path / ("aalab-%d" % (os.getuid() + 1))
            other.symlink_to(own)
            assert transport.resolve_socket()[0] == transport.SYSTEM_SOCKET
        finally:
            s2.close()
    finally:
        s.close()


def test_catalogue(client):
    h = client.health()
    assert h["status"] == "ok" and "optimize" in h["job_kinds"]
    assert {k["name"] for k in client.kinds()} >= {"optimize", "compare", "sleep"}
    presets = {p["name"]: p for p in client.presets()}
    assert set(TABLE2) <= set(presets)
    for name, e2 in TABLE2.items():
        assert presets[name]["published_e2"] == pytest.approx(e2)
    fq = client.preset("flipquad")
    assert "mirrored" in fq["pattern"] and fq["e2"] == pytest.approx(0.364, abs=5e-4)
    filters = client.filters()
    assert [f["name"] for f in filters if f.get("default")] == ["mitchell"]
    tables = client.acuity_tables()
    assert {t["name"] for t in tables} == {"naiman", "naiman-envelope", "uniform"}
    naiman = next(t for t in tables if t["name"] == "naiman")
    assert naiman["version"] == 2  # the revised table (data/README.md)
    assert client.evaluate("rgss", acuity="naiman-envelope").e2 == pytest.approx(0.439, abs=5e-4)
    assert client.usage()["store_bytes"] >= 0


@pytest.mark.parametrize("name", sorted(TABLE2))
def test_evaluate_reproduces_table2(client, name):
    e = client.evaluate(name)
    assert e.e2 == pytest.approx(TABLE2[name], abs=5e-4)
    assert e.per_angle is None and e.angles is None
    assert isinstance(e.argmax, aalab.Argmax)


def test_evaluate_detail_arrays(client):
    e = client.evaluate("flipquad", detail=True)
    assert e.kernel_count == 4 and e.per_angle.shape == (4, e.angle_count)
    assert isinstance(e.per_angle, np.ndarray) and e.angles.shape == (e.angle_count,)
    np.testing.assert_allclose(e.per_angle, e.weight * e.e1, rtol=1e-12)
    k, a = e.argmax
    assert e.per_angle.max() == pytest.approx(e.e2, rel=1e-12)
    assert e.per_angle[k, list(e.angles).index(a)] == pytest.approx(e.e2, rel=1e-12)


def test_evaluate_options(client):
    rgss = client.evaluate("rgss", detail=True, angles=np.array([0.0, 45.0]))
    assert list(rgss.angles) == [0.0, 45.0]
    assert rgss.e2 == pytest.approx(0.438987, abs=1e-6)
    box = client.evaluate("rgss", filter="box")
    assert box.raw["filter"]["name"] == "box" if "filter" in box.raw else True
    assert box.e2 != pytest.approx(rgss.e2)
    uni = client.evaluate("rgss", acuity="uniform", filter={"name": "mitchell", "B": 1 / 3,
                                                             "C": 1 / 3})
    assert uni.e2 > 0
    assert client.evaluate("rgss", lp=4).raw["lp_norm"] > 0


def test_evaluate_pattern_arguments(client, tmp_path):
    wire = client.preset("rgss")["pattern"]
    assert client.evaluate(wire).e2 == pytest.approx(client.evaluate("rgss").e2, rel=1e-15)
    kernels = {"kernels": wire["kernels"]}
    assert client.evaluate(kernels).e2 == pytest.approx(0.438987, abs=1e-6)
    # A saved evaluate request and a document with "pattern" are pattern files too.
    f = tmp_path / "req.json"
    f.write_text(json.dumps({"pattern": kernels, "detail": True}))
    assert client.evaluate(f).e2 == pytest.approx(0.438987, abs=1e-6)
    assert client.evaluate(str(f)).e2 == pytest.approx(0.438987, abs=1e-6)


def test_error_names_the_field(client):
    with pytest.raises(aalab.AalabError) as e:
        client.evaluate("rgss", filter={"name": "mitchell", "B": "x"})
    assert (e.value.code, e.value.field, e.value.status) == ("invalid_field", "filter.B", 400)
    assert "filter.B" in str(e.value)
    with pytest.raises(aalab.AalabError) as e:
        client.evaluate("rgsx")
    assert e.value.field == "pattern.preset" and "rgss" in e.value.message
    with pytest.raises(aalab.AalabError) as e:
        client.evaluate({"kernels": [[[0, 0, 0.5]]]})
    assert e.value.field.startswith("pattern.kernels")
    with pytest.raises(aalab.AalabError) as e:
        client.evaluate(3.5)  # refused locally, before anything is sent
    assert e.value.field == "pattern" and e.value.status is None
    with pytest.raises(aalab.AalabError) as e:
        client.jobs(state="bogus")
    assert e.value.field == "state"
    with pytest.raises(aalab.AalabError) as e:
        client.submit({"kind": "optimize", "family": "P(4,1+,2)", "seeds": 0})
    assert e.value.field == "seeds"
    with pytest.raises(aalab.AalabError) as e:
        client.job(999999).state
    assert e.value.code == "not_found" and e.value.status == 404


def test_enumerate_family(client):
    a = client.enumerate_family("P(4,1+,n)", 1.25)
    b = client.enumerate_family("P(4,1+,1.25)")
    assert len(a) == len(b) == a.raw["count"] > 0
    assert a.configurations == b.configurations and a.index
    for c in a:
        cost = sum(c["corners"]) / 4 + sum(c["edges"]) / 2 + c["interior"]
        assert cost == pytest.approx(1.25)
    with pytest.raises(aalab.AalabError) as e:
        client.enumerate_family("P(4,1+,n)", 1.3)
    assert e.value.field == "cost"


def test_optimize_job(client, opt_job):
    job = client.job(opt_job.id)
    assert job.state == "done" and job.kind == "optimize" and job.progress == 1.0
    assert job.result["reproducible"] is True and job.result["family"] == "P(4,1+,2)"
    assert job.best_e2 == pytest.approx(job.result["e2"])
    assert job.best_pattern["family"] == "P(4,1+,2)" and "mirrored" in job.best_pattern
    t = job.trace
    assert len(t) >= 1 and t.best_e2.shape == t.seconds.shape == (len(t),)
    assert np.all(np.diff(t.best_e2) <= 0) and t.best_e2[-1] == pytest.approx(job.best_e2)
    assert t.iterations.dtype.kind == "i" and np.all(np.diff(t.evaluations) >= 0)
    # The job's best pattern as a pattern argument: the daemon resolves {"job": ID}.
    assert client.evaluate(job).e2 == pytest.approx(job.best_e2, rel=1e-12)
    assert client.evaluate(job.best_pattern).e2 == pytest.approx(job.best_e2, rel=1e-12)
    listed = client.jobs(state="done", kind="optimize")
    assert job.id in [j.id for j in listed]
    mine = [j for j in listed if j.id == job.id][0]
    assert mine.summary["label"] == "pytest P(4,1+,2)"
    assert all(j.summary["state"] == "done" for j in listed)
    assert client.jobs(limit=1)[0].id >= job.id


def test_optimize_is_reproducible_and_takes_patterns(client, opt_job):
    again = client.optimize(family="P(4,1+,2)", seeds=2, max_iterations=60, rng_seed=3)
    again.wait(progress=False, timeout=120)
    assert again.best_e2 == opt_job.best_e2  # max_iterations without max_seconds: bit-exact
    from_pattern = client.optimize(pattern="flipquad", mode="weights", max_iterations=20,
                                   filter="mitchell", acuity="naiman").wait(progress=False)
    assert from_pattern.result["seeds_run"] == 1
    assert from_pattern.best_e2 <= client.evaluate("flipquad").e2 + 1e-12  # a descent never worsens


def test_optimize_for_a_scene(client):
    # objective passes through optimize(**options); the result reports both figures.
    scene = {"name": "half-plane", "angle": 30, "offset": 0.37, "width": 96, "height": 96}
    job = client.optimize(family="P(1,1,4)", seeds=2, max_iterations=200,
                          objective={"scene": scene, "blend": 0.25}).wait(progress=False,
                                                                          timeout=120)
    so = job.result["scene_objective"]
    assert so["blend"] == 0.25 and so["scene"]["angle"] == 30
    assert so["e2"] == pytest.approx(job.result["e2"]) == pytest.approx(job.best_e2)
    assert so["objective"] <= 1 + 1e-12  # F = 1 at the global-E2 optimum it starts from
    assert so["objective"] == pytest.approx(
        0.75 * so["predicted_rmse"] / so["e2_optimum"]["predicted_rmse"]
        + 0.25 * so["e2"] / so["e2_optimum"]["e2"], rel=1e-9)
    with pytest.raises(aalab.AalabError) as e:
        client.optimize(family="P(1,1,4)", objective={"scene": "rings", "blend": 2})
    assert e.value.field == "objective.blend"


def test_export(client, opt_job, tmp_path):
    doc = opt_job.export("json")
    assert doc["job"] == opt_job.id and doc["pattern"]["family"] == "P(4,1+,2)"
    vk = client.export(opt_job.id, "vulkan", path=tmp_path / "vk.json")
    assert "representable" in vk and json.loads((tmp_path / "vk.json").read_text()) == vk
    utk = opt_job.export("utk", path=tmp_path / "best.dat")
    assert (tmp_path / "best.dat").read_text() == utk
    rows = [line.split() for line in utk.splitlines() if line and not line.startswith("#")]
    assert len(rows) >= 4 and all(0 <= float(v) <= 1 for r in rows for v in r)
    with pytest.raises(aalab.AalabError) as e:
        opt_job.export("bogus")
    assert e.value.field == "format"


def test_wait_progress_bar_and_timeout(client, capsys):
    job = client.submit({"kind": "sleep", "seconds": 0.6})
    with pytest.raises(aalab.AalabError) as e:
        job.wait(progress=False, timeout=0.1, poll=0.05)
    assert e.value.code == "timeout" and e.value.job == job.id
    job.wait(progress=True, poll=0.05)
    assert job.state == "done"
    err = capsys.readouterr().err
    assert ("job %d" % job.id) in err and "100%" in err


def test_cancel(client):
    job = client.submit({"kind": "sleep", "seconds": 60, "label": "to cancel"})
    assert job.cancel() in ("queued", "running")
    job.wait(progress=False, timeout=30, poll=0.05)
    assert job.state == "cancelled"
    with pytest.raises(aalab.AalabError) as e:
        job.cancel()
    assert e.value.code == "conflict" and e.value.status == 409
    job.purge()
    with pytest.raises(aalab.AalabError) as e:
        job.refresh()
    assert e.value.code == "not_found"


def test_failed_job_raises_its_error(client):
    job = client.submit({"kind": "sleep", "seconds": 0, "fail": True})
    with pytest.raises(aalab.AalabError) as e:
        job.wait(progress=False, timeout=30, poll=0.05)
    assert e.value.job == job.id and e.value.field == "fail"
    assert job.state == "failed" and job.error.field == "fail"
    assert job.wait(progress=False, raise_on_failure=False).state == "failed"


def test_pin(client, opt_job):
    job = client.job(opt_job.id)
    job.pin(True)
    assert job.info["pinned"] is True
    job.pin(False)
    assert job.refresh()["pinned"] is False


def test_render(client):
    r = client.render("quincunx", scene="siemens-star", size=(64, 48), reference=64,
                      crop={"x": 8, "y": 8, "width": 8, "height": 8, "scale": 4})
    assert r.e2 == pytest.approx(0.518, abs=5e-4)
    assert r.scene["width"] == 64 and r.scene["height"] == 48
    for k in ("pattern", "reference", "difference"):
        img = r.images[k]
        assert img.shape == (48, 64) and img.dtype == np.uint8
    assert r.images["crop_pattern"].shape == (32, 32)
    assert r.rmse > 0 and r.max_dev > 0 and len(r.stats["histogram"]) == 256
    d = r.difference_percent()
    assert d.min() >= 0 and d.max() <= 10 and d.max() > 0
    # The difference image is |pattern - reference| on the 10 % scale (white = none), computed
    # before the two images were rounded to 8 bits (each off by <= 0.5/255: 10 gray levels) and
    # clipped to 0..255 (the filter's negative lobes overshoot): compare where neither clipped.
    p, ref = r.images["pattern"].astype(float), r.images["reference"].astype(float)
    inside = (p > 0) & (p < 255) & (ref > 0) & (ref < 255)
    expect = np.clip(255 * (1 - np.abs(p - ref) / 255 / 0.1), 0, 255)
    assert inside.sum() > 100
    assert np.abs(expect - r.images["difference"])[inside].max() <= 10 + 1e-9
    raw = client.render("rgss", size=16, reference=16, decode=False)
    assert raw.images == {} and client.tile(raw.raw["tiles"]["pattern"]["id"]).startswith(b"\x89PNG")
    with pytest.raises(aalab.AalabError) as e:
        client.render("rgss", scene={"name": "nope"})
    assert e.value.field == "scene.name"


def test_client_options():
    with pytest.raises(ValueError):
        aalab.Client("/x.sock", timeout=0)
    c = aalab.Client("/nonexistent/aalabd.sock")
    assert c.socket == "/nonexistent/aalabd.sock" and "nonexistent" in repr(c)
    with pytest.raises(aalab.DaemonUnreachable) as e:
        c.presets()
    assert isinstance(e.value, ConnectionError) and isinstance(e.value, aalab.AalabError)


def test_timeout_when_the_daemon_does_not_answer(tmp_path):
    path = str(tmp_path / "silent.sock")
    s = socket.socket(socket.AF_UNIX)
    s.bind(path)
    s.listen(1)
    try:
        with pytest.raises(aalab.AalabError) as e:
            aalab.Client(path, timeout=0.3).health()
        assert e.value.code == "timeout" and "timeout" in e.value.message
    finally:
        s.close()


def test_without_numpy_pillow_and_tqdm(daemon):
    # The optional packages hidden: lists instead of arrays, PNG bytes instead of images, no bar.
    code = """
import sys
for m in ("numpy", "PIL", "matplotlib", "tqdm"):
    sys.modules[m] = None
import aalab
c = aalab.Client(sys.argv[1])
e = c.evaluate("flipquad", detail=True)
assert isinstance(e.per_angle, list) and len(e.per_angle) == 4, type(e.per_angle)
r = c.render("rgss", size=16, reference=16)
assert all(isinstance(r.images[k], bytes) and r.images[k][:4] == b"\\x89PNG"
           for k in ("pattern", "reference", "difference"))
j = c.submit({"kind": "sleep", "seconds": 0.1}).wait(progress=True, poll=0.05)
assert j.state == "done" and isinstance(j.trace.seconds, list)
print("ok")
"""
    out = subprocess.run([sys.executable, "-c", code, daemon.socket_path], capture_output=True,
                         text=True, timeout=60)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stdout + out.stderr
    assert out.stderr == ""  # no progress bar without tqdm


def test_analyze(client):
    a = client.analyze("flipquad", radius=8)
    assert isinstance(a, aalab.Analysis)
    assert (a.points, a.tile, a.family) == (8, 2, "P(4,1+,2)")
    d = a.discrepancy
    for key in ("centered", "wrap_around", "mixture", "l2_star"):
        assert d[key] ** 2 == pytest.approx(d[key + "_squared"], rel=1e-14)
    assert 0 < d["star_linf"] < 1
    assert a.power.shape == (17, 17) and a.radial.shape == (9,)
    assert a.radial[0] == pytest.approx(8)
    np.testing.assert_allclose(a.power, a.power[::-1, ::-1], rtol=1e-12, atol=1e-12)  # P(-k)
    assert a.spacing["min_distance_normalized"] == pytest.approx(
        a.spacing["min_distance"] / a.spacing["packing_distance"], rel=1e-14)
    assert a.pcf.shape == a.pcf_r.shape == (64,)
    only = client.analyze("rgss", metrics=["spacing"])
    assert only.discrepancy is None and only.power is None and only.spacing is not None
    with pytest.raises(aalab.AalabError) as e:
        client.analyze("rgss", radius=0)
    assert e.value.field == "spectrum.radius"


def test_job_repr_says_kind_and_state_before_any_attribute(client, opt_job):
    """Issue 34: client.job(ID) printed "<aalab.Job N ? ?>" until an attribute was read."""
    fresh = client.job(opt_job.id)
    assert repr(fresh) == "<aalab.Job %d optimize done>" % opt_job.id


def _ranks(v):
    order = sorted(range(len(v)), key=lambda i: v[i])
    r = [0.0] * len(v)
    i = 0
    while i < len(v):
        j = i
        while j + 1 < len(v) and v[order[j + 1]] == v[order[i]]:
            j += 1
        for k in range(i, j + 1):
            r[order[k]] = (i + j) / 2 + 1
        i = j + 1
    return r


def _spearman(x, y):
    rx, ry = _ranks(x), _ranks(y)
    mx, my = sum(rx) / len(rx), sum(ry) / len(ry)
    sxy = sum((a - mx) * (b - my) for a, b in zip(rx, ry))
    sxx = sum((a - mx) ** 2 for a in rx)
    syy = sum((b - my) ** 2 for b in ry)
    return sxy / (sxx * syy) ** 0.5


def test_random_stats_point_metrics(client):
    """Issue 31: figures per random pattern and rho with E2, checked against the job's own
    columns (ranks computed here) and against POST /v1/analyze of the best random pattern."""
    names = ["mixture", "star_linf", "mean_nn_distance"]
    job = client.submit({"kind": "random-stats", "family": "P(1,1,4)", "count": 60,
                         "max_iterations": 20, "metrics": names}).wait(progress=False)
    pm = job.point_metrics
    assert isinstance(pm, aalab.PointMetrics)
    assert pm.metrics == names and len(pm.e2) == 60
    for m in names:
        s = pm.spearman[m]
        assert isinstance(s, aalab.Spearman) and s.n == 60 and 0 <= s.p_value <= 1
        assert s.rho == pytest.approx(_spearman(list(pm.values[m]), list(pm.e2)), abs=1e-12)
    assert pm.spearman["mixture"].rho > 0.5  # the study: 0.88 over 1000 uniform patterns
    assert [r["metric"] for r in pm.rows()] == names
    best = int(np.argmin(pm.e2))
    assert pm.e2[best] == job.result["random"]["min"]
    a = client.analyze(job.result["best_random"], metrics=["discrepancy", "star_discrepancy",
                                                           "spacing"])
    assert pm.values["mixture"][best] == pytest.approx(a.discrepancy["mixture"], rel=1e-12)
    assert pm.values["star_linf"][best] == pytest.approx(a.discrepancy["star_linf"], rel=1e-12)
    assert pm.values["mean_nn_distance"][best] == pytest.approx(
        a.spacing["mean_nn_distance"], rel=1e-12)
    # the same spec and rng_seed: the same figures
    again = client.submit(dict(job.info["spec"])).wait(progress=False)
    assert again.result["point_metrics"] == job.result["point_metrics"]
    with pytest.raises(aalab.AalabError) as e:
        client.submit({"kind": "random-stats", "family": "P(1,1,4)", "metrics": ["mixture", "x"]})
    assert e.value.field == "metrics[1]"


def test_table3_point_metrics(client):
    job = client.submit({"kind": "table3", "family": "P(4,4,2)", "seeds": 2, "count": 6,
                         "max_iterations": 10, "distributions": ["uniform", "lloyd"],
                         "metrics": ["centered"]}).wait(progress=False)
    pm = job.point_metrics
    assert set(pm) == {"uniform", "lloyd"}
    for d in pm.values():
        assert len(d.e2) == 12 and d.spearman["centered"].n == 12
        assert d.spearman["centered"].rho == pytest.approx(
            _spearman(list(d.values["centered"]), list(d.e2)), abs=1e-12)
