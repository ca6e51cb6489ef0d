"""Temporal antialiasing patterns (issue 30, docs/temporal.md): a TAA jitter sequence blended
into a history buffer, evaluated by ``POST /v1/evaluate`` as one kernel per phase.

Build the wire form with :func:`temporal` and the generator helpers, evaluate it with
``Client.evaluate`` (which answers a :class:`TemporalEvaluation` for a temporal pattern) or
``Client.evaluate_temporal``::

    import aalab
    from aalab import temporal as t
    c = aalab.Client()
    r = c.evaluate(t.temporal("halton23-8", alpha=0.05))
    print(r.e2, r.mean_phase_e2, r.f2, r.frames_to_5pct)
    r = c.evaluate(t.temporal(jitter=t.halton(16), blend="box"))

Offsets are in pixels from the pixel centre, x right and y up, in [-1/2, 1/2]² unless
``jitter_range`` widens it. In phase p the newest frame uses offset p; the frame j frames old
weighs ``age_weight[j]`` (α(1−α)^j / (1−(1−α)^N) for the exponential blend).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Dict, List, NamedTuple, Optional, Sequence, Union

from .errors import AalabError
from .results import array

try:
    import numpy as _np
except ImportError:  # pragma: no cover - exercised only without numpy
    _np = None

# The temporal presets of the daemon (proto/temporal_presets.c, docs/temporal.md §4).
PRESETS = ("halton23-8", "halton23-16", "fsr2-1.5x", "fsr2-1.7x", "fsr2-2x", "fsr2-3x",
           "urp-like", "filament-rgss4", "filament-halton8", "filament-halton16",
           "filament-halton32")


def halton(count: int, start: int = 1, bases: Sequence[int] = (2, 3)) -> Dict[str, Any]:
    """Halton(bases) at indices start .. start + count - 1, minus 1/2 (FSR2's from index 1)."""
    return {"generator": "halton", "count": int(count), "start": int(start),
            "bases": [int(b) for b in bases]}


def r2(count: int, start: int = 1) -> Dict[str, Any]:
    """Roberts' R2 sequence, (frac(1/2 + n/g), frac(1/2 + n/g²)) − 1/2, n = start ..."""
    return {"generator": "r2", "count": int(count), "start": int(start)}


def rgss4() -> Dict[str, Any]:
    """Filament's sRGSS4 table of 4 offsets."""
    return {"generator": "rgss4"}


def fsr2(scale: float) -> Dict[str, Any]:
    """FSR2's rule: Halton(2,3) from index 1 with (int)(8 scale²) phases (18/23/32/72 at
    1.5/1.7/2/3)."""
    return {"generator": "fsr2", "scale": float(scale)}


def positions(preset: str) -> Dict[str, Any]:
    """The sample positions of a one-kernel spatial preset, in its order, as the sequence."""
    return {"generator": "preset", "preset": str(preset)}


def _offsets(jitter: Any) -> Any:
    if isinstance(jitter, dict):
        return dict(jitter)
    if hasattr(jitter, "tolist"):
        jitter = jitter.tolist()
    out = []
    try:
        for o in jitter:
            if len(o) != 2:
                raise ValueError
            out.append([float(o[0]), float(o[1])])
    except (TypeError, ValueError):
        raise AalabError("invalid_field", "jitter: a generator dict or a sequence of [x, y] "
                         "offsets", "pattern.temporal.jitter") from None
    return out


def _blend(blend: Any, alpha: Optional[float]) -> Optional[Dict[str, Any]]:
    if isinstance(blend, dict):
        if alpha is not None:
            raise AalabError("invalid_field", "give alpha inside the blend dict or alone",
                             "pattern.temporal.blend")
        return dict(blend)
    if blend == "box":
        if alpha is not None:
            raise AalabError("invalid_field", "a box blend has no alpha",
                             "pattern.temporal.blend.alpha")
        return {"kind": "box"}
    if blend in (None, "exponential"):
        if alpha is None:
            return {"kind": "exponential", "alpha": 0.1} if blend else None
        return {"kind": "exponential", "alpha": float(alpha)}
    raise AalabError("invalid_field", "blend: 'exponential', 'box' or a dict",
                     "pattern.temporal.blend.kind")


def temporal(preset: Optional[str] = None, jitter: Any = None, alpha: Optional[float] = None,
             blend: Any = None, resolve: Any = None, frame_pattern: Any = None,
             jitter_range: Optional[float] = None,
             cut_frames: Optional[int] = None) -> Dict[str, Any]:
    """The wire form ``{"temporal": {...}}`` (proto/schemas/temporal.json).

    Args:
        preset: a temporal preset (:data:`PRESETS`); the other arguments override its keys.
        jitter: offsets (N x 2, pixels from the pixel centre) or a generator dict
            (:func:`halton`, :func:`r2`, :func:`rgss4`, :func:`fsr2`, :func:`positions`).
        alpha: the exponential blend's α in (0, 1] (the newest frame's weight).
        blend: ``"exponential"`` (default α 0.1), ``"box"`` (1/N each) or a blend dict.
        resolve: a per-frame resolve: a filter name (``"gaussian"``), a filter dict, or a
            resolve dict ``{"filter": ..., "radius": R}``.
        frame_pattern: the samples of every frame, any spatial pattern argument
            (:func:`aalab.as_pattern`); default one sample at the pixel centre.
        jitter_range: the jitter square's width in pixels (default 1).
        cut_frames: K of the after-cut curve (default 4 N).
    """
    if preset is None and jitter is None:
        raise AalabError("invalid_field", "a temporal pattern needs a preset or a jitter",
                         "pattern.temporal")
    t: Dict[str, Any] = {}
    if preset is not None:
        t["preset"] = str(preset)
    if jitter is not None:
        t["jitter"] = _offsets(jitter)
    b = _blend(blend, alpha)
    if b is not None:
        t["blend"] = b
    if resolve is not None:
        if isinstance(resolve, str):
            resolve = {"filter": {"name": resolve}}
        elif isinstance(resolve, dict) and "filter" not in resolve:
            resolve = {"filter": dict(resolve)}
        t["resolve"] = dict(resolve)
    if frame_pattern is not None:
        from .patterns import as_pattern
        t["frame_pattern"] = as_pattern(frame_pattern)
    if jitter_range is not None:
        t["jitter_range"] = float(jitter_range)
    if cut_frames is not None:
        t["cut_frames"] = int(cut_frames)
    return {"temporal": t}


def is_temporal(pattern: Any) -> bool:
    """True for a temporal wire form (or a request holding one under ``"pattern"``)."""
    if not isinstance(pattern, dict):
        return False
    if "temporal" in pattern:
        return True
    inner = pattern.get("pattern")
    return isinstance(inner, dict) and "temporal" in inner


class TemporalArgmax(NamedTuple):
    """Where the worst-phase E2 is attained: phase, output pixel (group) and angle (degrees)."""
    phase: int
    group: int
    angle_deg: Optional[float]


@dataclass(frozen=True)
class TemporalEvaluation:
    """E2 of a temporal pattern (``POST /v1/evaluate`` with ``{"temporal": ...}``).

    Attributes:
        e2: the worst phase's E2 (max over phases, groups and angles of W·E1).
        mean_phase_e2: mean over phases of each phase's E2.
        argmax: :class:`TemporalArgmax` (phase, group, angle_deg) of ``e2``.
        phase_count, group_count, angle_count: N, output pixels, angles.
        family, cost_spp: ``T(N)`` and samples per pixel of one frame.
        effective_samples: 1 / Σω², how many equal frames the blend is worth.
        angles: the angles in degrees; weights: W(θ) there.
        phase_e2: E2 per phase (N); age_weight: ω_j, the weight of the frame j frames old (N).
        e1: E1 per phase, group and angle (N x G x A), unweighted.
        f1: the flicker F1 per group and angle (G x A), unweighted; f2: max of W·F1;
            f2_argmax: ``{"group", "angle_deg"}``.
        after_cut: E2 after k = 1..K frames since a cut (K); frames_to_5pct: the first k from
            which every value is within 5 % of its phase's steady state (None: none up to K).
        jitter: the offsets evaluated (N x 2, pixels); blend, preset: as the daemon answered.
        raw: the answer as sent.
    """

    e2: float
    mean_phase_e2: float
    argmax: TemporalArgmax
    phase_count: int
    group_count: int
    angle_count: int
    family: str
    cost_spp: float
    effective_samples: float
    angles: Any
    weights: Any
    phase_e2: Any
    age_weight: Any
    e1: Any
    f1: Any
    f2: float
    f2_argmax: Optional[Dict[str, Any]]
    after_cut: Any
    frames_to_5pct: Optional[int]
    jitter: Any
    blend: Dict[str, Any]
    preset: Optional[Dict[str, Any]]
    raw: Dict[str, Any] = field(repr=False)

    @classmethod
    def from_answer(cls, d: Dict[str, Any]) -> "TemporalEvaluation":
        phases = sorted(d["phases"], key=lambda p: p["phase"])
        am = d.get("argmax") or {}
        return cls(e2=d["e2"], mean_phase_e2=d["mean_phase_e2"],
                   argmax=TemporalArgmax(am.get("phase", 0), am.get("group", 0),
                                         am.get("angle_deg")),
                   phase_count=d["phase_count"], group_count=d.get("group_count", 1),
                   angle_count=d["angle_count"], family=d.get("family", ""),
                   cost_spp=d.get("cost_spp"), effective_samples=d.get("effective_samples"),
                   angles=array(d["angles_deg"]), weights=array(d["weights"]),
                   phase_e2=array([p["e2"] for p in phases]),
                   age_weight=array([p["age_weight"] for p in phases]),
                   e1=array([p["e1"] for p in phases]), f1=array(d["f1"]), f2=d["f2"],
                   f2_argmax=d.get("f2_argmax"), after_cut=array(d["after_cut"]),
                   frames_to_5pct=d.get("frames_to_5pct"), jitter=array(d["jitter"]),
                   blend=d.get("blend") or {}, preset=d.get("preset"), raw=d)

    def newest_offset(self, phase: int) -> List[float]:
        """The offset of phase p's newest frame (offset p, docs/temporal.md §1)."""
        return list(self.raw["jitter"][phase])

    def phase_argmax_angles(self) -> List[Optional[float]]:
        """Per phase, the angle (degrees) of its largest W·E1 over groups and angles."""
        w = self.raw["weights"]
        angles = self.raw["angles_deg"]
        out: List[Optional[float]] = []
        for p in sorted(self.raw["phases"], key=lambda q: q["phase"]):
            best, arg = -1.0, None
            for row in p["e1"]:
                for i, v in enumerate(row):
                    if v is not None and v * w[i] > best:
                        best, arg = v * w[i], angles[i]
            out.append(arg)
        return out


Pattern = Union[str, Dict[str, Any]]

__all__ = ["temporal", "halton", "r2", "rgss4", "fsr2", "positions", "is_temporal", "PRESETS",
           "TemporalEvaluation", "TemporalArgmax"]
