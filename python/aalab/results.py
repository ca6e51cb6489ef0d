"""Typed views of the daemon's answers. Each keeps the answer itself as ``raw``.

Arrays are numpy arrays when numpy is installed, nested lists otherwise (:func:`array`)."""

from __future__ import annotations

import io
from dataclasses import dataclass, field
from typing import Any, Dict, List, NamedTuple, Optional, Union

try:  # optional: arrays when present
    import numpy as _np
except ImportError:  # pragma: no cover - exercised only without numpy
    _np = None


def array(values: Any, dtype: Any = float) -> Any:
    """``numpy.asarray(values, dtype)`` when numpy is installed, else ``values`` unchanged.
    ``None`` entries become NaN in float arrays (the daemon writes non-finite numbers as null)."""
    if _np is None:
        return values
    if dtype is float:
        def fix(v: Any) -> Any:
            if isinstance(v, list):
                return [fix(x) for x in v]
            return float("nan") if v is None else v
        values = fix(values)
    return _np.asarray(values, dtype=dtype)


class Argmax(NamedTuple):
    """Where E2 is attained: kernel index (from 0) and edge angle in degrees."""
    kernel: int
    angle_deg: Optional[float]


@dataclass(frozen=True)
class Evaluation:
    """E2 of a pattern (``POST /v1/evaluate``).

    E2 is dimensionless: the maximum over kernels and edge angles θ of W(θ)·E1(θ), where E1 is
    the L2 distance between the kernel's step response and the reference filter's, W the
    acuity weight (docs/metric.md). Angles are in degrees, counter-clockwise from the x axis
    (x right, y up).

    Attributes:
        e2: the error (lower is better).
        argmax: :class:`Argmax` (kernel, angle_deg) where E2 is attained.
        family: P(s,r,n) of the pattern; cost_spp: samples per pixel n.
        kernel_count, angle_count: the evaluation's kernels and angles.
        mean: mean of W·E1 over kernels and angles (None if the daemon sent none).
        angles: the angles in degrees (detail only, else None).
        weight: W(θ) per kernel x angle (detail only).
        e1: E1(θ) per kernel x angle (detail only).
        per_angle: W(θ)·E1(θ) per kernel x angle (detail only; ``evaluate(detail=True)``).
        raw: the answer as sent.
    """

    e2: float
    argmax: Argmax
    family: str
    cost_spp: float
    kernel_count: int
    angle_count: int
    mean: Optional[float]
    angles: Any
    weight: Any
    e1: Any
    per_angle: Any
    raw: Dict[str, Any] = field(repr=False)

    @classmethod
    def from_answer(cls, d: Dict[str, Any]) -> "Evaluation":
        detail = d.get("detail")
        angles = weight = e1 = weighted = None
        if detail:
            rows = sorted(detail, key=lambda k: k["kernel"])
            angles = array([a["angle_deg"] for a in rows[0]["angles"]])
            weight = array([[a["weight"] for a in k["angles"]] for k in rows])
            e1 = array([[a["e1"] for a in k["angles"]] for k in rows])
            weighted = array([[a["weighted"] for a in k["angles"]] for k in rows])
        am = d.get("argmax") or {}
        return cls(e2=d["e2"], argmax=Argmax(am.get("kernel", 0), am.get("angle_deg")),
                   family=d.get("family", ""), cost_spp=d.get("cost_spp"),
                   kernel_count=d.get("kernel_count", 0), angle_count=d.get("angle_count", 0),
                   mean=d.get("mean"), angles=angles, weight=weight, e1=e1, per_angle=weighted,
                   raw=d)


@dataclass(frozen=True)
class Trace:
    """Error against run time of a job: one point per improvement of the best E2.

    Attributes:
        seconds: seconds of the job's own clock (time paused for other users' jobs excluded).
        iterations: descent steps so far; evaluations: E2 evaluations so far.
        best_e2: best E2 at that time (NaN where the daemon sent null).
    """

    seconds: Any
    iterations: Any
    evaluations: Any
    best_e2: Any
    raw: List[Dict[str, Any]] = field(repr=False)

    @classmethod
    def from_answer(cls, points: Optional[List[Dict[str, Any]]]) -> "Trace":
        pts = points or []
        return cls(seconds=array([p["seconds"] for p in pts]),
                   iterations=array([p["iterations"] for p in pts], int),
                   evaluations=array([p["evaluations"] for p in pts], int),
                   best_e2=array([p["best_e2"] for p in pts]), raw=pts)

    def __len__(self) -> int:
        return len(self.raw)


def decode_png(data: bytes) -> Any:
    """A gray PNG tile as a height x width ``uint8`` array (0 black, 255 white) when numpy and
    Pillow (or matplotlib, whose PNG reader is Pillow's) are installed; else the PNG bytes."""
    if _np is None:
        return data
    try:
        from PIL import Image
    except ImportError:
        try:
            from matplotlib import image as mimage
        except ImportError:
            return data
        a = mimage.imread(io.BytesIO(data), format="png")  # float in [0, 1]
        if a.ndim == 3:
            a = a[..., 0]
        return _np.rint(a * 255).astype(_np.uint8)
    with Image.open(io.BytesIO(data)) as im:
        return _np.asarray(im.convert("L"), dtype=_np.uint8)


# The difference tile maps |pattern - reference| on the 0..1 intensity scale to gray:
# 255 (white) for 0, 0 (black) for DIFFERENCE_FULL_SCALE or more (server/tiles/tile_render.c).
DIFFERENCE_FULL_SCALE = 0.1


@dataclass(frozen=True)
class Render:
    """A rendered test tile (``POST /v1/render``): the pattern's image, the supersampled
    reference and their difference, with statistics.

    Attributes:
        e2: E2 of the pattern.
        stats: ``rmse`` and ``max_dev`` (deviation from the reference on the 0..255 scale),
            ``pixels`` compared, ``histogram`` (256 counts of round(deviation)) and
            ``penalised_histogram`` (histogram[i]·i²/pixels, Hasselgren et al. Fig. 6-7).
        times: ``pattern_seconds`` and ``reference_seconds``, wall-clock seconds.
        scene: the scene as rendered (defaults filled in); pattern: family, samples per
            pixel, kernels, kernel size, border.
        images: ``{"pattern", "reference", "difference"}`` (and ``crop_*`` with a crop): each a
            height x width uint8 array, row 0 at the top (:func:`decode_png`), or the PNG bytes
            when numpy and Pillow are missing. The difference image is white for no deviation
            and black for a deviation of :data:`DIFFERENCE_FULL_SCALE` (10 %) of full scale or
            more.
        raw: the answer as sent.
    """

    e2: float
    stats: Dict[str, Any]
    times: Dict[str, Any]
    scene: Dict[str, Any]
    pattern: Dict[str, Any]
    images: Dict[str, Any]
    raw: Dict[str, Any] = field(repr=False)

    @property
    def rmse(self) -> float:
        return float(self.stats["rmse"])

    @property
    def max_dev(self) -> float:
        return float(self.stats["max_dev"])

    def difference_percent(self) -> Any:
        """The difference image as deviation in percent of full scale (0..10, clipped at 10),
        a float array (numpy and a PNG reader needed)."""
        img = self.images["difference"]
        if isinstance(img, (bytes, bytearray)):
            raise ValueError("the tiles were not decoded (numpy and Pillow are needed)")
        return (255.0 - img.astype(float)) / 255.0 * DIFFERENCE_FULL_SCALE * 100.0


@dataclass(frozen=True)
class Enumeration:
    """Placement configurations of a mirrored family P(4,1+,n) at one cost.

    Attributes:
        family: P(4,1+,n); cost: samples per pixel n.
        configurations: one dict each: ``corners`` (4 counts, cost 1/4 each), ``edges`` (4
            counts, cost 1/2 each), ``interior`` (cost 1 each), ``samples`` of the kernel and a
            ``label``.
        index: how the daemon numbers corners and edges.
    """

    family: str
    cost: Optional[float]
    configurations: List[Dict[str, Any]]
    index: str
    raw: Dict[str, Any] = field(repr=False)

    def __len__(self) -> int:
        return len(self.configurations)

    def __iter__(self):
        return iter(self.configurations)


Image = Union[bytes, Any]


@dataclass(frozen=True)
class Analysis:
    """Point-set figures of a pattern's tile on the unit torus (``POST /v1/analyze``;
    docs/analysis.md). Only the asked metrics are set, the rest are None.

    Attributes:
        points, tile, family: the point set's size, the tile T it was scaled by, P(s,r,n).
        discrepancy: dict of the roots (``centered``, ``wrap_around``, ``mixture``,
            ``l2_star``), their squares (``*_squared``; scipy returns the squares of CD, WD
            and MD) and ``star_linf``, the exact L∞ star discrepancy.
        spacing: dict of ``min_distance``, ``mean_nn_distance``, ``packing_distance`` and the
            two divided by it (``*_normalized``).
        power: the periodogram P(k), rows ky = -radius..radius, columns kx likewise.
        radial, anisotropy_db, annulus_count: per annulus |k| ~ 0..radius.
        effective_nyquist, oscillation: PSA's figures (null where undefined: NaN here).
        pcf_r, pcf: the pair correlation function at its bin centres.
        raw: the answer as sent.
    """

    points: int
    tile: int
    family: str
    discrepancy: Optional[Dict[str, Any]]
    spacing: Optional[Dict[str, Any]]
    radius: Optional[int]
    power: Any
    radial: Any
    anisotropy_db: Any
    annulus_count: Any
    effective_nyquist: Optional[float]
    oscillation: Optional[float]
    pcf_r: Any
    pcf: Any
    raw: Dict[str, Any] = field(repr=False)

    @classmethod
    def from_answer(cls, d: Dict[str, Any]) -> "Analysis":
        s = d.get("spectrum") or {}
        p = d.get("pcf") or {}
        nan = float("nan")
        return cls(points=d["points"], tile=d["tile"], family=d["family"],
                   discrepancy=d.get("discrepancy"), spacing=d.get("spacing"),
                   radius=s.get("radius"),
                   power=array(s["power"]) if "power" in s else None,
                   radial=array(s["radial"]) if "radial" in s else None,
                   anisotropy_db=array(s["anisotropy_db"]) if "anisotropy_db" in s else None,
                   annulus_count=array(s["annulus_count"], int) if "annulus_count" in s else None,
                   effective_nyquist=(nan if s.get("effective_nyquist") is None
                                      else s["effective_nyquist"]) if s else None,
                   oscillation=(nan if s.get("oscillation") is None else s["oscillation"])
                   if s else None,
                   pcf_r=array(p["r"]) if "r" in p else None,
                   pcf=array(p["g"]) if "g" in p else None,
                   raw=d)


class Spearman(NamedTuple):
    """Spearman's rank correlation of one point-set figure with E2 over a job's random patterns
    (ties as average ranks, as ``scipy.stats.spearmanr``): rho (NaN where undefined), n (patterns
    where both are finite) and the two-sided p-value of the t approximation (NaN with rho)."""

    rho: float
    n: int
    p_value: float


@dataclass(frozen=True)
class PointMetrics:
    """Point-set figures of every random pattern of a random-stats job (or of one table3 row)
    and their rank correlation with E2 (the spec's ``metrics``; point_metrics.json).

    Attributes:
        metrics: the figures' names, in the spec's order (``POST /v1/analyze``'s names).
        spearman: name -> :class:`Spearman`.
        e2: each random pattern's E2, in pattern order (table3: every seed's, in seed order).
        values: name -> the figure per pattern, aligned with ``e2`` (NaN where undefined).
        spectrum_radius: periodogram radius of the spectral figures.
        raw: the block as sent.
    """

    metrics: List[str]
    spearman: Dict[str, Spearman]
    e2: Any
    values: Dict[str, Any]
    spectrum_radius: int
    raw: Dict[str, Any] = field(repr=False)

    @classmethod
    def from_answer(cls, d: Dict[str, Any]) -> "PointMetrics":
        nan = float("nan")
        rho = {e["metric"]: Spearman(nan if e["rho"] is None else float(e["rho"]), int(e["n"]),
                                     nan if e["p_value"] is None else float(e["p_value"]))
               for e in d["spearman"]}
        cols = d["patterns"]
        return cls(metrics=list(d["metrics"]), spearman=rho, e2=array(cols["e2"]),
                   values={m: array(cols[m]) for m in d["metrics"]},
                   spectrum_radius=int(d["spectrum_radius"]), raw=d)

    def rows(self) -> List[Dict[str, Any]]:
        """One dict per figure: ``metric``, ``rho``, ``n``, ``p_value`` (e.g. for pandas)."""
        return [dict(metric=m, rho=self.spearman[m].rho, n=self.spearman[m].n,
                     p_value=self.spearman[m].p_value) for m in self.metrics]
