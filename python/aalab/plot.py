"""Figures for papers, drawn with matplotlib: the pictures the dashboard shows.

Every function returns a :class:`matplotlib.figure.Figure` and does nothing else: figures are
made with ``matplotlib.figure.Figure`` (not pyplot), so no global figure list, style or
backend changes; nothing is shown. Save with ``fig.savefig("name.pdf")``; in a notebook the
returned figure displays itself. Pass ``ax=`` to draw into an axes of your own figure instead
(the function then returns ``ax.figure``).

Conventions (as in the dashboard): angles in degrees counter-clockwise from the x axis; pattern
coordinates in pixels, x right and y up, the pixel [-0.5, 0.5]² around its centre; run time in
seconds of the job's own clock; kernels told apart by dash pattern as well as colour, series by
marker shape, so figures read in black and white.
"""

from __future__ import annotations

import math
import re
from typing import Any, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
from matplotlib.figure import Figure

from .job import Job
from .results import DIFFERENCE_FULL_SCALE, Analysis, Evaluation, Render, Trace

# The dashboard's palette, dashes and markers (web/js/svg.js).
COLOURS = ["#1f5fbf", "#c2410c", "#15803d", "#7e22ce", "#a16207", "#be123c", "#0f766e", "#4b5563"]
DASHES: List[Any] = ["-", (0, (6, 3)), (0, (2, 3)), (0, (8, 3, 2, 3)), (0, (12, 4)), (0, (1, 2))]
MARKERS = ["o", "s", "^", "D", "X", "v", "*", "P"]
_EPS = 1e-9

Size = Tuple[float, float]


def _figure(ax: Any, figsize: Size, dpi: float, **subplot: Any) -> Tuple[Figure, Any]:
    if ax is not None:
        return ax.figure, ax
    fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
    return fig, fig.add_subplot(**subplot)


def polar(evaluation: Evaluation, weighted: bool = True, ax: Any = None,
          title: Optional[str] = None, figsize: Size = (5.0, 5.0), dpi: float = 100) -> Figure:
    """Per-angle error of each kernel on a polar plot: W(θ)·E1(θ) (or E1(θ) with
    ``weighted=False``), radius the error, angle the edge angle θ in degrees. E1 is even in
    θ + 180°, so the evaluated half-turn is drawn twice; E2, the maximum, is ringed.

    ``evaluation`` must come from ``Client.evaluate(..., detail=True)``.
    """
    if evaluation.per_angle is None:
        raise ValueError("the evaluation has no per-angle detail: evaluate(..., detail=True)")
    fig, ax = _figure(ax, figsize, dpi, projection="polar")
    if getattr(ax, "name", "") != "polar":
        raise ValueError("polar() needs a polar axes (projection='polar')")
    angles = np.asarray(evaluation.angles, dtype=float)
    values = np.asarray(evaluation.per_angle if weighted else evaluation.e1, dtype=float)
    order = np.argsort(angles)
    th = np.deg2rad(np.concatenate([angles[order], angles[order] + 180.0]))
    th = np.append(th, th[0] + 2 * math.pi)
    n = values.shape[0]
    for k in range(n):
        r = values[k][order]
        r = np.concatenate([r, r, r[:1]])
        ax.plot(th, r, color=COLOURS[k % len(COLOURS)], linestyle=DASHES[k % len(DASHES)],
                linewidth=1.5, label="kernel %d" % k if n <= 8 or k < 8 else None)
    label = "W(θ)·E1(θ)" if weighted else "E1(θ)"
    if weighted and evaluation.argmax.angle_deg is not None:
        a = math.radians(evaluation.argmax.angle_deg)
        ax.plot([a], [evaluation.e2], "o", markersize=12, markerfacecolor="none",
                markeredgecolor="black", markeredgewidth=1.5)
        ax.plot([a], [evaluation.e2], "o", markersize=3, color="black")
        where = ", kernel %d" % evaluation.argmax.kernel if n > 1 else ""
        ax.set_xlabel("max %.3f @ %g°%s" % (evaluation.e2, evaluation.argmax.angle_deg, where))
    ax.set_thetagrids(range(0, 360, 45), ["%d°" % d for d in range(0, 360, 45)])
    ax.set_rlabel_position(80)
    ax.set_ylim(0, None)
    ax.set_title(title if title is not None else "%s, %s" % (label, evaluation.family))
    if n > 1:
        ax.legend(loc="upper right", bbox_to_anchor=(1.12, 1.12), fontsize="small", frameon=False)
    return fig


def _kernels(p: Mapping[str, Any]) -> Tuple[List[List[List[float]]], bool]:
    """The reconstruction kernels of a wire pattern and whether it is the mirrored form."""
    if isinstance(p.get("mirrored"), list):
        m = p["mirrored"]
        return [m, [[-x, y, w] for x, y, w in m], [[x, -y, w] for x, y, w in m],
                [[-x, -y, w] for x, y, w in m]], True
    if isinstance(p.get("kernels"), list):
        return p["kernels"], False
    if isinstance(p.get("kernels_expanded"), list):
        return p["kernels_expanded"], False
    raise ValueError("pattern() needs a pattern with kernels, mirrored or kernels_expanded "
                     "(the daemon adds kernels_expanded to every pattern it returns: "
                     "Client.preset(name)['pattern'], Job.best_pattern)")


def _dots(p: Mapping[str, Any], kernel: int) -> List[Tuple[float, float, float, bool]]:
    """(x, y, w, primary) for the pixel and its eight neighbours, as the dashboard lays them
    out (web/js/pattern-geometry.js): neighbours are the mirrored pixel (mirrored form) or the
    same kernel repeated; a neighbour's dot on a centre dot is a shared sample, drawn once."""
    ks, mirrored = _kernels(p)
    centre = ks[0] if mirrored else ks[min(max(kernel, 0), len(ks) - 1)]
    dots = [(float(x), float(y), float(w), True) for x, y, w in centre]
    for j in (-1, 0, 1):
        for i in (-1, 0, 1):
            if not i and not j:
                continue
            sx = -1 if mirrored and i % 2 else 1
            sy = -1 if mirrored and j % 2 else 1
            for x, y, w in centre:
                X, Y = sx * x + i, sy * y + j
                if abs(X) > 1.5 + _EPS or abs(Y) > 1.5 + _EPS:
                    continue
                if any(abs(d[0] - X) < 1e-6 and abs(d[1] - Y) < 1e-6 for d in dots):
                    continue
                dots.append((X, Y, float(w), False))
    return dots


def pattern(p: Mapping[str, Any], kernel: int = 0, ax: Any = None, title: Optional[str] = None,
            figsize: Size = (4.5, 4.5), dpi: float = 100) -> Figure:
    """The pattern: the centre pixel (bold frame) and its eight neighbours, one dot per sample,
    dot **area proportional to |w|** (Hasselgren et al. Fig. 3), negative weights hollow and
    dashed. Coordinates in pixels, x right, y up, the centre pixel [-0.5, 0.5]².

    Args:
        p: a wire pattern with ``kernels``, ``mirrored`` or ``kernels_expanded`` (every pattern
            the daemon returns has the latter: ``Job.best_pattern``), or a document holding one
            under ``"pattern"`` (``Client.preset("flipquad")``, titled with its name).
        kernel: which kernel sits in the centre (kernels form); the mirrored form always shows
            its pixel with the mirrored neighbours.
    """
    if isinstance(p.get("pattern"), Mapping):  # a preset answer or an export document
        if title is None and p.get("name"):
            title = str(p["name"])
        p = p["pattern"]
    fig, ax = _figure(ax, figsize, dpi)
    for j in (-1, 0, 1):
        for i in (-1, 0, 1):
            centre = not i and not j
            ax.add_patch(_rect(i - 0.5, j - 0.5, centre))
    ax.plot([-0.06, 0.06], [0, 0], color="#999999", linewidth=0.8)
    ax.plot([0, 0], [-0.06, 0.06], color="#999999", linewidth=0.8)
    dots = _dots(p, kernel)
    wmax = max([abs(d[2]) for d in dots] + [1e-12])
    smax = 260.0 * (figsize[0] / 4.5) ** 2  # marker area in points² of the heaviest sample
    for primary in (False, True):  # neighbours first, centre dots on top
        for x, y, w, prim in dots:
            if prim != primary:
                continue
            s = max(30.0, smax * abs(w) / wmax)
            colour = COLOURS[0] if prim else "#8aa9db"
            if w < 0:
                ax.scatter([x], [y], s=s, facecolors="none", edgecolors=colour, linewidths=1.4,
                           linestyle="--", zorder=3)
            else:
                ax.scatter([x], [y], s=s, color=colour, zorder=3)
            if prim:
                ax.annotate(_fmt_weight(w), (x, y), xytext=(6, 5), textcoords="offset points",
                            fontsize="x-small")
    ax.set_xlim(-1.5, 1.5)
    ax.set_ylim(-1.5, 1.5)
    ax.set_aspect("equal")
    ax.set_xticks([-1.5, -0.5, 0.5, 1.5])
    ax.set_yticks([-1.5, -0.5, 0.5, 1.5])
    ax.set_xlabel("x (pixels)")
    ax.set_ylabel("y (pixels)")
    name = p.get("name") or p.get("preset") or p.get("family") or ""
    ax.set_title(title if title is not None else
                 ("%s, kernel %d" % (name, kernel) if len(_kernels(p)[0]) > 1
                  and not isinstance(p.get("mirrored"), list) else str(name)))
    return fig


def _rect(x: float, y: float, centre: bool) -> Any:
    from matplotlib.patches import Rectangle
    return Rectangle((x, y), 1, 1, fill=False, edgecolor="#333333" if centre else "#bbbbbb",
                     linewidth=1.6 if centre else 0.8, zorder=1)


def _fmt_weight(w: float) -> str:
    s = ("%.3f" % w).rstrip("0").rstrip(".") if abs(w) >= 0.01 else "%.2g" % w
    return s.replace("-", "−")


TraceLike = Union[Job, Trace]


def _trace_of(item: TraceLike) -> Tuple[np.ndarray, np.ndarray, Optional[str], int]:
    """Seconds, best E2, a label and how many of the points are the trace's own (the rest
    holds the last best to the job's end)."""
    if isinstance(item, Trace):
        xs, ys = np.asarray(item.seconds, float), np.asarray(item.best_e2, float)
        keep = np.isfinite(xs) & np.isfinite(ys)
        return xs[keep], ys[keep], None, int(keep.sum())
    if isinstance(item, Job):
        info = item.info
        t = Trace.from_answer(info.get("trace"))
        xs, ys = np.asarray(t.seconds, float), np.asarray(t.best_e2, float)
        keep = np.isfinite(xs) & np.isfinite(ys)
        xs, ys = xs[keep], ys[keep]
        o = np.argsort(xs, kind="stable")
        xs, ys = xs[o], ys[o]
        points = len(xs)
        # Hold the last best to the job's end, as the dashboard does (its own clock is not
        # known; wall-clock end - start bounds it).
        r = info.get("result") or {}
        end = r.get("seconds") if isinstance(r, dict) else None
        if end is None and info.get("finished") is not None and info.get("started") is not None:
            end = info["finished"] - info["started"]
        if len(xs) and end is not None and end > xs[-1]:
            xs, ys = np.append(xs, end), np.append(ys, ys[-1])
        label = info.get("label") or "job %d %s" % (item.job_id, info.get("family") or info["kind"])
        return xs, ys, label, points
    raise TypeError("trace() takes Jobs or Traces, not %s" % type(item).__name__)


def trace(items: Union[TraceLike, Sequence[TraceLike], Mapping[str, TraceLike]], log: bool = True,
          ax: Any = None, title: str = "Best E2 against run time", figsize: Size = (6.4, 4.0),
          dpi: float = 100) -> Figure:
    """Error against run time: the best E2 of each job (a step curve, one point per
    improvement, held to the job's end) against seconds of the job's own clock.

    Args:
        items: a Job or Trace, a list of them, or a mapping label -> Job/Trace.
        log: log-log axes (points at t <= 0 left out), else linear.
    """
    if isinstance(items, (Job, Trace)):
        items = [items]
    pairs = list(items.items()) if isinstance(items, Mapping) else [(None, it) for it in items]
    fig, ax = _figure(ax, figsize, dpi)
    for k, (label, it) in enumerate(pairs):
        xs, ys, own, points = _trace_of(it)
        keep = (xs > 0) & (ys > 0) if log else np.ones(len(xs), bool)
        if not keep.any():
            continue
        c = COLOURS[k % len(COLOURS)]
        ax.step(xs[keep], ys[keep], where="post", color=c, linestyle=DASHES[k % len(DASHES)],
                label=label or own or "trace %d" % k)
        mark = keep[:points]  # the trace's own points, not the hold to the job's end
        ax.plot(xs[:points][mark], ys[:points][mark], MARKERS[k % len(MARKERS)], color=c,
                markersize=3.5)
    if log:
        from matplotlib.ticker import FuncFormatter, LogLocator
        ax.set_xscale("log")
        ax.set_yscale("log")
        # E2 spans less than a decade: label 1-2-5 steps in plain numbers, not 2×10^-1.
        ax.yaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
        ax.yaxis.set_minor_locator(LogLocator(subs=(3.0, 4.0, 6.0, 7.0, 8.0, 9.0)))
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: "%g" % v))
        ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
    ax.set_xlabel("run time (s, job's own clock)")
    ax.set_ylabel("best E2")
    ax.grid(True, which="both", alpha=0.3)
    ax.set_title(title)
    if pairs:
        ax.legend(fontsize="small")
    return fig


_FAMILY_N = re.compile(r"^P\(\s*\d+\s*,\s*\d+\+?\s*,\s*([0-9.]+)\s*\)$")


def spp_of_family(family: str) -> Optional[float]:
    """n of a family P(s,r,n) (samples per pixel), None if it does not parse."""
    m = _FAMILY_N.match(family or "")
    return float(m.group(1)) if m else None


def _point(item: Any) -> Tuple[float, float, str]:
    """(samples per pixel, E2, label) of one item of e2_vs_spp."""
    if isinstance(item, Evaluation):
        return float(item.cost_spp), float(item.e2), item.family
    if isinstance(item, Job):
        info = item.info
        best = item.best_pattern or {}
        spp = best.get("cost_spp") or spp_of_family(info.get("family") or best.get("family", ""))
        if spp is None or item.best_e2 is None:
            raise ValueError("job %d has no best pattern yet" % item.job_id)
        return float(spp), float(item.best_e2), info.get("label") or "job %d" % item.job_id
    if isinstance(item, Mapping):
        return float(item["spp"]), float(item["e2"]), str(item.get("label", ""))
    if isinstance(item, (tuple, list)) and len(item) in (2, 3):
        if len(item) == 3:
            return float(item[1]), float(item[2]), str(item[0])
        return float(item[0]), float(item[1]), ""
    raise TypeError("e2_vs_spp() items are Evaluations, Jobs, (spp, e2), (label, spp, e2) or "
                    "{spp, e2, label}, not %s" % type(item).__name__)


def e2_vs_spp(series: Union[Mapping[str, Any], Sequence[Any]], ax: Any = None,
              title: str = "E2 against samples per pixel", annotate: bool = True,
              figsize: Size = (6.4, 4.0), dpi: float = 100) -> Figure:
    """E2 against samples per pixel (the pattern's cost n of P(s,r,n)) for several patterns or
    jobs, one marker shape per series.

    Args:
        series: a mapping label -> item or list of items (a list is one series, joined by a
            line in order of spp), or a list of items (each its own series). An item is an
            :class:`Evaluation`, a finished :class:`Job` (its best pattern), ``(spp, e2)``,
            ``(label, spp, e2)`` or ``{"spp", "e2", "label"}``.
        annotate: write each single-point series' label beside its point.
    """
    groups = list(series.items()) if isinstance(series, Mapping) else [(None, s) for s in series]
    fig, ax = _figure(ax, figsize, dpi)
    xs_all: List[float] = []
    for k, (label, items) in enumerate(groups):
        single = not isinstance(items, (list, tuple)) or (
            isinstance(items, tuple) and len(items) in (2, 3) and not isinstance(items[0], (Job, Evaluation, Mapping, tuple, list)))
        pts = [_point(items)] if single else [_point(it) for it in items]
        pts.sort(key=lambda p: p[0])
        name = label or (pts[0][2] if pts else "series %d" % k)
        c = COLOURS[k % len(COLOURS)]
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        xs_all += xs
        ax.plot(xs, ys, marker=MARKERS[k % len(MARKERS)], color=c,
                linestyle=DASHES[k % len(DASHES)] if len(pts) > 1 else "none", label=name)
        if annotate and len(pts) == 1:
            ax.annotate(name, (xs[0], ys[0]), xytext=(6, 4), textcoords="offset points",
                        fontsize="x-small")
    ax.set_xlabel("samples per pixel")
    ax.set_ylabel("E2")
    ax.grid(True, alpha=0.3)
    if xs_all:
        ax.set_xticks(sorted(set(xs_all)))
    ax.set_title(title)
    ax.legend(fontsize="small")
    return fig


def tiles(render: Render, title: Optional[str] = None, figsize: Size = (10.5, 3.9),
          dpi: float = 100) -> Figure:
    """The pattern's image, the reference and their difference side by side, with the
    difference scale (white = no deviation, black = 10 % of full scale or more, as the
    dashboard's difference image) and the render's RMSE, maximum deviation (0..255) and E2.

    ``render`` must come from ``Client.render(..., decode=True)`` with numpy and Pillow
    installed (decoded tiles)."""
    imgs = render.images
    if any(isinstance(imgs.get(k), (bytes, bytearray, type(None)))
           for k in ("pattern", "reference", "difference")):
        raise ValueError("the render's tiles are not decoded arrays (Client.render(decode=True) "
                         "with numpy and Pillow installed)")
    fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
    axes = fig.subplots(1, 3)
    for ax, key, name in zip(axes, ("pattern", "reference"), ("pattern", "reference")):
        ax.imshow(imgs[key], cmap="gray", vmin=0, vmax=255, interpolation="nearest")
        ax.set_title(name)
    d = axes[2].imshow(render.difference_percent(), cmap="gray_r", vmin=0,
                       vmax=DIFFERENCE_FULL_SCALE * 100, interpolation="nearest")
    axes[2].set_title("difference")
    for ax in axes:
        ax.set_xticks([])
        ax.set_yticks([])
    cb = fig.colorbar(d, ax=axes[2], fraction=0.046, pad=0.04)
    cb.set_label("|pattern − reference|, % of full scale")
    sc = render.scene
    fig.suptitle(title if title is not None else
                 "%s %d×%d, %s: RMSE %.3f, max dev. %.1f (0..255), E2 %.4f"
                 % (sc.get("name"), sc.get("width"), sc.get("height"),
                    render.pattern.get("family", ""), render.rmse, render.max_dev, render.e2))
    return fig


from .plot_temporal import temporal  # noqa: E402  (the Temporal view's figure, issue 30)

__all__ = ["polar", "pattern", "trace", "e2_vs_spp", "tiles", "spp_of_family", "temporal"]


def spectrum(analysis: Analysis, ax: Any = None, title: Optional[str] = None,
             figsize: Size = (10.0, 4.2), dpi: float = 100) -> Figure:
    """The periodogram of a point set (``Client.analyze``; docs/analysis.md): the 2-D P(k) as
    an image (log scale, DC removed) beside the radially averaged power with its anisotropy in
    dB. Frequencies are integers of the unit torus; the radial axis also marks sqrt(n)/2, where
    a well-spread set's power rises. With ``ax`` only the radial plot is drawn into it."""
    if analysis.power is None or analysis.radial is None:
        raise ValueError("the analysis has no spectrum: analyze(..., metrics=[..., 'spectrum'])")
    power = np.array(analysis.power, dtype=float)
    radius = (power.shape[0] - 1) // 2
    radial = np.asarray(analysis.radial, dtype=float)
    k = np.arange(len(radial))
    if ax is None:
        fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
        img_ax, rad_ax = fig.subplots(1, 2, width_ratios=[1, 1.4])
        shown = power.copy()
        shown[radius, radius] = np.nan  # P(0) = n would swamp the scale
        im = img_ax.imshow(np.log10(np.maximum(shown, 1e-3)), origin="lower", cmap="magma",
                           extent=(-radius - 0.5, radius + 0.5, -radius - 0.5, radius + 0.5))
        img_ax.set_xlabel("kx")
        img_ax.set_ylabel("ky")
        img_ax.set_title("log10 P(k)")
        fig.colorbar(im, ax=img_ax, shrink=0.8)
    else:
        fig, rad_ax = ax.figure, ax
    rad_ax.plot(k[1:], radial[1:], color=COLOURS[0], linewidth=1.5, label="radial power")
    rad_ax.axhline(1.0, color="0.6", linewidth=0.8)
    rad_ax.axvline(math.sqrt(analysis.points) / 2, color="0.6", linestyle=":", linewidth=0.8)
    rad_ax.set_xlabel("|k| (integer frequencies of the torus)")
    rad_ax.set_ylabel("mean P(k) over the annulus (linear)")
    rad_ax.set_xlim(0, len(radial) - 1)
    rad_ax.set_ylim(0, None)
    if analysis.anisotropy_db is not None:
        ani = rad_ax.twinx()
        ani.plot(k, np.asarray(analysis.anisotropy_db, dtype=float), color=COLOURS[1],
                 linestyle=DASHES[1], linewidth=1.0, label="anisotropy")
        ani.set_ylabel("anisotropy (dB)")
    nu = analysis.effective_nyquist
    rad_ax.set_title(title if title is not None else "%s, %d points%s" % (
        analysis.family, analysis.points,
        "" if nu is None or math.isnan(nu) else ", effective Nyquist %g" % nu))
    return fig


def pcf(analysis: Analysis, ax: Any = None, title: Optional[str] = None,
        figsize: Size = (6.0, 4.0), dpi: float = 100) -> Figure:
    """The pair correlation function g(r) of a point set (``Client.analyze``), r in units of
    PSA's packing distance (1: the spacing of the densest packing) when the analysis has the
    spacing, else of the unit torus; g = 1 is a Poisson set."""
    if analysis.pcf is None:
        raise ValueError("the analysis has no pair correlation: analyze(..., metrics=[..., 'pcf'])")
    fig, ax = _figure(ax, figsize, dpi)
    r = np.asarray(analysis.pcf_r, dtype=float)
    unit = (analysis.spacing or {}).get("packing_distance")
    ax.plot(r / unit if unit else r, np.asarray(analysis.pcf, dtype=float), color=COLOURS[0],
            linewidth=1.5)
    ax.axhline(1.0, color="0.6", linewidth=0.8)
    ax.set_xlabel("r / packing distance" if unit else "r (unit torus)")
    ax.set_ylabel("g(r) (linear)")
    ax.set_xlim(0, None)
    ax.set_ylim(0, None)
    ax.set_title(title if title is not None else "pair correlation, %s, %d points" % (
        analysis.family, analysis.points))
    return fig
