"""aalab.plot: every figure written to PNG, non-empty (not one colour) and of the size asked
for; nothing global touched (no pyplot figures, rcParams unchanged)."""

import matplotlib
import numpy as np
import pytest
from matplotlib.figure import Figure
from PIL import Image

import aalab
from aalab import plot


@pytest.fixture(scope="module")
def c(daemon):
    return aalab.Client(daemon.socket_path)


def check_png(fig, path, size, dpi=100):
    assert isinstance(fig, Figure)
    fig.savefig(path, dpi=dpi)
    with Image.open(path) as im:
        assert im.size == (round(size[0] * dpi), round(size[1] * dpi))
        a = np.asarray(im.convert("L"))
    assert path.stat().st_size > 2000
    assert a.std() > 5 and (a < 128).mean() > 0.002  # something dark was drawn on the white


@pytest.fixture
def no_global_state():
    import sys
    rc = dict(matplotlib.rcParams)
    pyplot_loaded = "matplotlib.pyplot" in sys.modules
    yield
    assert dict(matplotlib.rcParams) == rc
    if pyplot_loaded:
        import matplotlib.pyplot as plt
        assert plt.get_fignums() == []
    else:
        assert "matplotlib.pyplot" not in sys.modules


def test_polar(c, tmp_path, no_global_state):
    e = c.evaluate("flipquad", detail=True)
    check_png(plot.polar(e), tmp_path / "polar.png", (5.0, 5.0))
    check_png(plot.polar(c.evaluate("rgss", detail=True), weighted=False, figsize=(3, 3), dpi=80),
              tmp_path / "e1.png", (3, 3), dpi=80)
    with pytest.raises(ValueError):
        plot.polar(c.evaluate("rgss"))  # no detail
    fig = Figure()
    ax = fig.add_subplot(projection="polar")
    assert plot.polar(e, ax=ax) is fig
    with pytest.raises(ValueError):
        plot.polar(e, ax=Figure().add_subplot())


def test_pattern(c, tmp_path, no_global_state):
    check_png(plot.pattern(c.preset("flipquad")["pattern"]), tmp_path / "fq.png", (4.5, 4.5))
    fig = plot.pattern(c.preset("quincunx"), figsize=(4, 4))
    assert fig.axes[0].get_title() == "quincunx"
    check_png(fig, tmp_path / "q.png", (4, 4))
    # Negative weights are drawn hollow; a tile pattern draws from kernels_expanded.
    neg = {"kernels": [[[0.0, 0.0, 1.2], [0.4, 0.4, -0.2]]]}
    fig = plot.pattern(neg)
    cols = fig.axes[0].collections
    hollow = [col for col in cols if len(col.get_facecolors()) == 0 or
              col.get_facecolors()[0][3] == 0]
    assert len(hollow) >= 1 and len(hollow) < len(cols)
    job = c.optimize(family="P(16,16,4)", seeds=1, max_iterations=2).wait(progress=False)
    check_png(plot.pattern(job.best_pattern, kernel=5), tmp_path / "p16.png", (4.5, 4.5))
    with pytest.raises(ValueError):
        plot.pattern({"preset": "rgss"})


def test_trace(c, tmp_path, no_global_state):
    jobs = [c.optimize(family="P(4,1+,1.5)", seeds=2, max_iterations=40, rng_seed=s,
                       label="seed %d" % s) for s in (1, 2)]
    for j in jobs:
        j.wait(progress=False)
    fig = plot.trace(jobs)
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()] == ["seed 1", "seed 2"]
    check_png(fig, tmp_path / "trace.png", (6.4, 4.0))
    check_png(plot.trace({"a": jobs[0].trace}, log=False), tmp_path / "lin.png", (6.4, 4.0))


def test_e2_vs_spp(c, tmp_path, no_global_state):
    presets = {n: c.evaluate(n) for n in ("grid-2x2", "rgss", "quincunx", "flipquad", "fliptri")}
    job = c.optimize(family="P(4,1+,1.25)", seeds=2, max_iterations=30).wait(progress=False)
    series = dict(presets, optimized=[job, (1.5, 0.53), {"spp": 2.0, "e2": 0.36}])
    fig = plot.e2_vs_spp(series)
    ax = fig.axes[0]
    assert len(ax.get_legend().get_texts()) == 6
    xs = np.concatenate([line.get_xdata() for line in ax.get_lines()])
    assert set(np.round(xs, 2)) == {1.25, 1.5, 2.0, 4.0}
    check_png(fig, tmp_path / "spp.png", (6.4, 4.0))
    assert plot.spp_of_family("P(4,1+,1.25)") == 1.25 and plot.spp_of_family("x") is None


def test_tiles(c, tmp_path, no_global_state):
    r = c.render("quincunx", size=96, reference=64)
    fig = plot.tiles(r)
    assert len(fig.axes) == 4  # three images and the difference scale
    check_png(fig, tmp_path / "tiles.png", (10.5, 3.9))
    with pytest.raises(ValueError):
        plot.tiles(c.render("rgss", size=16, reference=16, decode=False))


def test_spectrum_and_pcf(c, tmp_path, no_global_state):
    a = c.analyze("hasselgren-a", radius=16)
    check_png(plot.spectrum(a), tmp_path / "spectrum.png", (10.0, 4.2))
    check_png(plot.pcf(a), tmp_path / "pcf.png", (6.0, 4.0))
    with pytest.raises(ValueError):
        plot.pcf(c.analyze("rgss", metrics=["spacing"]))
