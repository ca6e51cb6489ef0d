"""Temporal patterns in the Python package (issue 30, docs/temporal.md): the wire forms the
builders make, the typed answer against the daemon's JSON (and its schema: the client validates),
the issue's independent values, and plot.temporal's figure."""

import numpy as np
import pytest
from PIL import Image

import aalab
from aalab import plot
from aalab import temporal as t


def test_builders_make_the_wire_form():
    assert t.temporal("halton23-8") == {"temporal": {"preset": "halton23-8"}}
    assert t.temporal("urp-like", alpha=0.2, cut_frames=16) == {"temporal": {
        "preset": "urp-like", "blend": {"kind": "exponential", "alpha": 0.2}, "cut_frames": 16}}
    assert t.temporal(jitter=t.halton(8), blend="box") == {"temporal": {
        "jitter": {"generator": "halton", "count": 8, "start": 1, "bases": [2, 3]},
        "blend": {"kind": "box"}}}
    assert t.temporal(jitter=np.array([[0.25, 0.25], [-0.25, -0.25]]), blend="exponential",
                      resolve="gaussian", frame_pattern="d3d-2x", jitter_range=1.5) == {
        "temporal": {"jitter": [[0.25, 0.25], [-0.25, -0.25]],
                     "blend": {"kind": "exponential", "alpha": 0.1},
                     "resolve": {"filter": {"name": "gaussian"}},
                     "frame_pattern": {"preset": "d3d-2x"}, "jitter_range": 1.5}}
    assert t.fsr2(2) == {"generator": "fsr2", "scale": 2.0}
    assert t.r2(4, start=0) == {"generator": "r2", "count": 4, "start": 0}
    assert t.positions("d3d-4x") == {"generator": "preset", "preset": "d3d-4x"}
    assert t.rgss4() == {"generator": "rgss4"}
    assert t.is_temporal(t.temporal("halton23-8"))
    assert t.is_temporal({"pattern": t.temporal("halton23-8"), "angles": [0]})
    assert not t.is_temporal({"preset": "rgss"}) and not t.is_temporal("halton23-8")
    for bad in (dict(), dict(preset="x", blend="box", alpha=0.1),
                dict(jitter=[[0, 0, 1]]), dict(jitter=5), dict(preset="x", blend="gauss")):
        with pytest.raises(aalab.AalabError) as e:
            t.temporal(**bad)
        assert e.value.field.startswith("pattern.temporal")


def test_evaluate_halton8_issue_values(client):
    r = client.evaluate(t.temporal("halton23-8"))
    assert isinstance(r, aalab.TemporalEvaluation)
    # The issue's independent evaluator: 0.482 worst phase, 0.459 mean over phases.
    assert r.e2 == pytest.approx(0.482, abs=5e-4)
    assert r.mean_phase_e2 == pytest.approx(0.459, abs=5e-4)
    assert r.phase_count == 8 and r.family == "T(8)" and r.preset["name"] == "halton23-8"
    assert r.e1.shape == (8, 1, r.angle_count) and r.f1.shape == (1, r.angle_count)
    assert r.after_cut.shape == (32,) and r.jitter.shape == (8, 2)
    # The typed arrays are the answer's numbers, and the worst phase is the maximum of W·E1.
    per_phase = (r.e1.max(axis=1) * r.weights).max(axis=1)
    np.testing.assert_allclose(per_phase, r.phase_e2, rtol=1e-12)
    assert r.phase_e2.max() == r.e2 and r.phase_e2[r.argmax.phase] == r.e2
    assert r.phase_e2.mean() == pytest.approx(r.mean_phase_e2, rel=1e-12)
    assert r.age_weight.sum() == pytest.approx(1, abs=1e-15)
    assert (r.f1.max(axis=0) * r.weights).max() == pytest.approx(r.f2, rel=1e-12)
    angles = r.phase_argmax_angles()
    assert angles[r.argmax.phase] == r.argmax.angle_deg
    assert r.newest_offset(3) == r.raw["jitter"][3]
    assert isinstance(r.frames_to_5pct, int) and 1 <= r.frames_to_5pct <= 32
    same = client.evaluate_temporal(jitter=t.halton(8), alpha=0.1)
    assert same.e2 == r.e2 and same.mean_phase_e2 == r.mean_phase_e2


def test_evaluate_options_and_box_blend(client):
    spatial = client.evaluate("d3d-4x").e2
    box = client.evaluate_temporal(jitter=t.positions("d3d-4x"), blend="box")
    assert box.e2 == spatial and box.f2 == 0  # docs/temporal.md: bit for bit
    r = client.evaluate_temporal("halton23-8", alpha=0.05, cut_frames=10, angles=[0, 45, 90],
                                 acuity="uniform")
    assert r.blend == {"kind": "exponential", "alpha": 0.05}
    assert list(r.angles) == [0, 45, 90] and len(r.after_cut) == 10
    assert list(r.weights) == [1, 1, 1]
    # a saved request dict evaluates too
    again = client.evaluate({"pattern": t.temporal("halton23-8", alpha=0.05), "angles": [0]},
                            angles=[0, 45, 90], acuity="uniform")
    assert again.e2 == r.e2
    with pytest.raises(aalab.AalabError) as e:
        client.evaluate(t.temporal(jitter=[[0, 0], [0.7, 0]]))
    assert e.value.field == "pattern.temporal.jitter[1]"


def test_plot_temporal(client, tmp_path):
    r = client.evaluate(t.temporal("halton23-8"))
    fig = plot.temporal(r)
    path = tmp_path / "temporal.png"
    fig.savefig(path, dpi=100)
    with Image.open(path) as im:
        assert im.size == (1300, 800)
        a = np.asarray(im.convert("L"))
    assert a.std() > 5 and (a < 128).mean() > 0.002
    axes = fig.axes
    assert len(axes) == 5 and [ax.name for ax in axes].count("polar") == 2
    # the sequence is numbered by frame: one label per offset
    assert sorted(tx.get_text() for tx in axes[0].texts) == sorted(str(i) for i in range(8))
    assert "0.4821" in axes[1].get_title() and "F2 0.1100" in axes[4].get_title()
    assert "26" in " ".join(tx.get_text() for tx in axes[2].get_legend().get_texts())
    big = plot.temporal(client.evaluate_temporal("fsr2-3x"), figsize=(8, 6), dpi=80)
    big.savefig(tmp_path / "fsr2.png")
    assert big._suptitle.get_text().startswith("fsr2-3x, exponential α 0.1")
    # a curve that does not settle within K: said in the title
    short = client.evaluate_temporal("halton23-8", cut_frames=8)
    assert short.frames_to_5pct is None
    fig = plot.temporal(short)
    fig.savefig(tmp_path / "short.png")
    assert fig.axes[2].get_title() == "after a cut: not within 5 % by k = 8"
    with pytest.raises(ValueError):
        plot.temporal(client.evaluate("rgss"))


def test_temporal_example(daemon, tmp_path):
    """docs/examples/temporal.py: every preset, the alpha sweep, its figures."""
    import csv
    import os
    import subprocess
    import sys
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "docs",
                          "examples", "temporal.py")
    out = subprocess.run([sys.executable, script, "--socket", daemon.socket_path, "--out",
                          str(tmp_path)], capture_output=True, text=True, timeout=240)
    assert out.returncode == 0, out.stdout + out.stderr
    with open(tmp_path / "temporal_presets.csv") as f:
        rows = {r["preset"]: r for r in csv.DictReader(f)}
    assert set(rows) == set(t.PRESETS)
    assert rows["fsr2-3x"]["phases"] == "72" and rows["halton23-8"]["frames_to_5pct"] == "26"
    with open(tmp_path / "temporal_alpha.csv") as f:
        sweep = list(csv.DictReader(f))
    assert [float(s["alpha"]) for s in sweep] == [0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0]
    # alpha 1: the newest frame alone, one effective sample
    assert float(sweep[-1]["effective_samples"]) == 1
    with Image.open(tmp_path / "temporal_alpha.png") as im:
        assert im.size == (960, 600)
    with Image.open(tmp_path / "temporal_halton23-8.png") as im:
        assert im.size == (1300, 800)
