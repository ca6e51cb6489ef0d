"""The temporal figure (``aalab.plot.temporal``): a TAA jitter sequence and its evaluation, the
pictures of the dashboard's Temporal view (web/js/views/temporal.js). Conventions as in
:mod:`aalab.plot`."""

from __future__ import annotations

import math
from typing import Any, Optional, Tuple

import numpy as np
from matplotlib.figure import Figure

from .temporal import TemporalEvaluation

# The dashboard's palette and dashes (web/js/svg.js; aalab.plot has the same).
_COLOURS = ["#1f5fbf", "#c2410c", "#15803d", "#7e22ce", "#a16207", "#be123c", "#0f766e",
            "#4b5563"]

Size = Tuple[float, float]


def _sequence(ax: Any, r: TemporalEvaluation) -> None:
    """The offsets in the pixel, numbered by frame (0 first), joined in frame order."""
    j = np.asarray(r.jitter, dtype=float).reshape(-1, 2)
    half = max(0.5, float(np.abs(j).max()) if j.size else 0.5)
    ax.add_patch(_square(half))
    ax.plot(np.append(j[:, 0], j[:1, 0]), np.append(j[:, 1], j[:1, 1]), color="0.75",
            linewidth=0.8, zorder=1)
    worst = r.argmax.phase
    n = len(j)
    for f, (x, y) in enumerate(j):
        newest = f == worst
        ax.plot([x], [y], "o", color=_COLOURS[1] if newest else _COLOURS[0],
                markersize=7 if newest else 5, zorder=3)
        if n <= 64:  # numbers beyond that would only be ink
            ax.annotate(str(f), (x, y), textcoords="offset points", xytext=(4, 4),
                        fontsize=8 if n <= 32 else 6, color="0.15")
    ax.plot([0], [0], "+", color="0.4", markersize=8)
    ax.set_xlim(-half - 0.05, half + 0.05)
    ax.set_ylim(-half - 0.05, half + 0.05)
    ax.set_aspect("equal")
    ax.set_xlabel("x offset (pixels)")
    ax.set_ylabel("y offset (pixels)")
    ax.set_title("sequence, %d frames (worst phase's newest in orange)" % n, fontsize="medium")


def _square(half: float) -> Any:
    from matplotlib.patches import Rectangle
    return Rectangle((-half, -half), 2 * half, 2 * half, fill=False, edgecolor="0.3",
                     linewidth=1.0)


def _phases(ax: Any, r: TemporalEvaluation) -> None:
    e2 = np.asarray(r.phase_e2, dtype=float)
    p = np.arange(len(e2))
    colours = [_COLOURS[1] if i == r.argmax.phase else _COLOURS[0] for i in p]
    ax.bar(p, e2, color=colours, width=0.8)
    ax.axhline(r.mean_phase_e2, color="0.2", linestyle=(0, (6, 3)), linewidth=1.0,
               label="mean %.4f" % r.mean_phase_e2)
    ax.set_xlabel("phase (newest frame)")
    ax.set_ylabel("E2 of the phase")
    ax.set_ylim(0, max(e2.max() * 1.15, 1e-9) if e2.size else 1)
    if len(e2) <= 16:
        ax.set_xticks(p)
    ax.set_title("E2 per phase: worst %.4f (phase %d)" % (r.e2, r.argmax.phase),
                 fontsize="medium")
    ax.legend(loc="lower right", fontsize="small", frameon=False)


def _polar(ax: Any, r: TemporalEvaluation, which: str) -> None:
    """W·E1 of every phase (worst bold) or W·F1, max over groups, over the full turn."""
    angles = np.asarray(r.angles, dtype=float)
    w = np.asarray(r.weights, dtype=float)
    order = np.argsort(angles)
    th = np.deg2rad(np.concatenate([angles[order], angles[order] + 180.0]))
    th = np.append(th, th[0] + 2 * math.pi)

    def ring(values: Any) -> Any:
        v = np.asarray(values, dtype=float)[order]
        return np.concatenate([v, v, v[:1]])

    if which == "e1":
        e1 = np.asarray(r.e1, dtype=float).max(axis=1)  # phases x angles
        for p in range(e1.shape[0]):
            worst = p == r.argmax.phase
            ax.plot(th, ring(w * e1[p]), color=_COLOURS[1] if worst else _COLOURS[0],
                    linewidth=1.8 if worst else 0.6, alpha=1.0 if worst else 0.5,
                    zorder=3 if worst else 2)
        a = r.argmax.angle_deg
        if a is not None:
            ax.plot([math.radians(a)], [r.e2], "o", markersize=11, markerfacecolor="none",
                    markeredgecolor="black")
        ax.set_title("W·E1 per phase (worst orange): E2 %.4f" % r.e2, fontsize="medium")
    else:
        f1 = np.asarray(r.f1, dtype=float).max(axis=0)
        ax.plot(th, ring(w * f1), color=_COLOURS[2], linewidth=1.8)
        arg = (r.f2_argmax or {}).get("angle_deg")
        if arg is not None:
            ax.plot([math.radians(arg)], [r.f2], "o", markersize=11, markerfacecolor="none",
                    markeredgecolor="black")
        ax.set_title("flicker W·F1: F2 %.4f" % r.f2, fontsize="medium")
    ax.set_thetagrids(range(0, 360, 45), ["%d°" % d for d in range(0, 360, 45)])
    ax.set_rlabel_position(80)
    ax.set_ylim(0, None)


def _after_cut(ax: Any, r: TemporalEvaluation) -> None:
    curve = np.asarray(r.after_cut, dtype=float)
    k = np.arange(1, len(curve) + 1)
    ax.plot(k, curve, color=_COLOURS[0], linewidth=1.5, marker="o", markersize=3,
            label="E2 after k frames")
    ax.axhline(r.e2, color="0.3", linestyle=(0, (6, 3)), linewidth=1.0,
               label="steady state, worst phase")
    ax.axhspan(r.e2 * 0.95, r.e2 * 1.05, color="0.85", zorder=0)
    if r.frames_to_5pct is not None:
        ax.axvline(r.frames_to_5pct, color=_COLOURS[1], linestyle=(0, (2, 3)), linewidth=1.2,
                   label="within 5 %% from k = %d" % r.frames_to_5pct)
    ax.set_xlabel("frames since the cut (k)")
    ax.set_ylabel("E2")
    ax.set_xlim(0.5, len(curve) + 0.5)
    ax.set_ylim(0, None)
    ax.set_title("after a cut%s" % ("" if r.frames_to_5pct is not None else
                                    ": not within 5 %% by k = %d" % len(curve)),
                 fontsize="medium")
    ax.legend(loc="upper right", fontsize="small", frameon=False)


def temporal(result: TemporalEvaluation, title: Optional[str] = None,
             figsize: Size = (13.0, 8.0), dpi: float = 100) -> Figure:
    """A temporal evaluation (``Client.evaluate`` of a ``{"temporal": ...}`` pattern): the
    jitter sequence with frame numbers, E2 per phase (the worst in orange, the mean dashed),
    the W·E1 polar of every phase beside the flicker W·F1 polar (angles in degrees, E1 even in
    θ + 180°, so the half-turn is drawn twice) and the E2 after k frames since a cut with the
    ±5 % band around the steady state."""
    if not isinstance(result, TemporalEvaluation):
        raise ValueError("temporal() needs a TemporalEvaluation: Client.evaluate of a "
                         "{'temporal': ...} pattern")
    fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
    gs = fig.add_gridspec(2, 6)
    _sequence(fig.add_subplot(gs[0, 0:2]), result)
    _phases(fig.add_subplot(gs[0, 2:4]), result)
    _after_cut(fig.add_subplot(gs[0, 4:6]), result)
    _polar(fig.add_subplot(gs[1, 0:3], projection="polar"), result, "e1")
    _polar(fig.add_subplot(gs[1, 3:6], projection="polar"), result, "f1")
    blend = result.blend or {}
    how = ("box" if blend.get("kind") == "box" else "exponential α %g" % blend.get("alpha", 0))
    name = (result.preset or {}).get("name") or result.family
    fig.suptitle(title if title is not None else
                 "%s, %s: E2 %.4f (worst phase), mean %.4f, F2 %.4f, %.1f effective samples"
                 % (name, how, result.e2, result.mean_phase_e2, result.f2,
                    result.effective_samples or 0))
    return fig


__all__ = ["temporal"]
