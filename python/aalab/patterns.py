"""What the package accepts as a pattern, turned into the daemon's wire form.

A pattern argument may be:

- a preset name (``"rgss"``; ``Client.presets()`` lists them);
- a dict in one of the wire forms of docs/api.md (``{"preset": ..}``, ``{"kernels": ..}``,
  ``{"mirrored": ..}``, ``{"tile": ..}``, ``{"points": ..}``, ``{"job": ID}``), passed on
  unchanged; a document holding one under ``"pattern"`` (an export, an evaluate request, a
  preset answer) gives its pattern;
- a :class:`~aalab.Job` (its best pattern, resolved by the daemon) or a
  :class:`~aalab.formats.PointSet`;
- points: an N x 2 or N x 3 (x, y, w) numpy array or sequence, in the unit square of the whole
  tile (:mod:`aalab.formats`), sent as the daemon's ``{"points": ...}`` form;
- a path (``os.PathLike``, or a string with a ``/`` or a point-file suffix: ``.dat``, ``.txt``,
  ``.xyw``, ``.pts``, ``.csv``, ``.json``): a JSON pattern file (a pattern, an evaluate request,
  an export) or a point file in one of :data:`aalab.formats.FORMATS`.

Wire-form coordinates are in pixels, x to the right and y up; ``kernels`` samples are relative
to the output point (the pixel is [-0.5, 0.5]²), ``mirrored`` to the pixel centre, ``tile``
samples lie in [0, T)². Point files use the unit square of the whole tile instead.
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Optional

from . import formats
from .errors import AalabError

# "temporal" passes through as the daemon's (a jitter sequence: the evaluate, predict, render and
# analyze routes, the exports, compare and the temporal job kinds take it; docs/temporal.md).
WIRE_KEYS = ("preset", "kernels", "mirrored", "tile", "points", "job", "temporal")


def _looks_like_path(s: str) -> bool:
    return os.sep in s or "/" in s or os.path.splitext(s)[1].lower() in formats.SUFFIXES


def _from_file(path: str, tile: Optional[int], kernel: Optional[int],
               weights: Optional[str], fmt: Optional[str], which: Any = None) -> Dict[str, Any]:
    if not os.path.exists(path):
        raise AalabError("invalid_field", "%s: no such file" % path, "pattern")
    fmt = fmt or formats.guess_format(path)
    text = None
    if fmt == "json":
        with open(path, encoding="utf-8") as f:
            text = f.read()
        try:
            doc = json.loads(text)
        except ValueError as e:
            raise AalabError("invalid_field", "%s: not JSON: %s" % (path, e), "pattern") from None
        if isinstance(doc, dict) and not (set(doc) <= {"aalab", "points"} and
                                          isinstance(doc.get("points"), list)):
            return as_pattern(doc)  # a wire pattern, an evaluate request or an export
    # set "all" (analyze): checked here on set 0, the daemon reads every set
    return formats.read(path, fmt, text=text, set=0 if which == "all" else which).to_pattern(
        tile, kernel, weights)


def as_pattern(pattern: Any, tile: Optional[int] = None, kernel: Optional[int] = None,
               weights: Optional[str] = None, fmt: Optional[str] = None,
               set: Any = None) -> Dict[str, Any]:
    """The wire form of any accepted pattern argument (module docstring).

    ``tile``, ``kernel`` and ``weights`` apply to points (arrays, point sets and point files;
    see :meth:`aalab.formats.PointSet.to_pattern`), ``fmt`` names a point file's format when
    its suffix does not, ``set`` picks one set of a file holding several (``"all"``: every
    set, for :meth:`aalab.Client.analyze`). Raises :class:`AalabError` (code
    ``invalid_field``, field ``pattern``...) for anything else."""
    if set is not None:
        wire = as_pattern(pattern, tile, kernel, weights, fmt, None) if not (
            isinstance(pattern, (str, os.PathLike)) and _looks_like_path(os.fspath(pattern))) \
            else _from_file(os.fspath(pattern), tile, kernel, weights, fmt, set)
        if "points" not in wire:
            raise AalabError("invalid_field", "set is for point files holding several sets",
                             "pattern.points.set")
        wire["points"] = dict(wire["points"], set=set)
        return wire
    if isinstance(pattern, formats.PointSet):
        return pattern.to_pattern(tile, kernel, weights)
    job_id = getattr(pattern, "job_id", None)
    if job_id is not None:
        return {"job": int(job_id)}
    if isinstance(pattern, dict):
        if any(k in pattern for k in WIRE_KEYS):
            return dict(pattern)
        inner = pattern.get("pattern")
        if isinstance(inner, (dict, str)):
            return as_pattern(inner)
        raise AalabError("invalid_field", "a pattern dict needs one of the keys %s"
                         % ", ".join(WIRE_KEYS), "pattern")
    if isinstance(pattern, os.PathLike):
        return _from_file(os.fspath(pattern), tile, kernel, weights, fmt)
    if isinstance(pattern, str):
        if _looks_like_path(pattern):
            return _from_file(pattern, tile, kernel, weights, fmt)
        if not pattern:
            raise AalabError("invalid_field", "empty pattern name", "pattern")
        return {"preset": pattern}
    if hasattr(pattern, "tolist") or isinstance(pattern, (list, tuple)):
        try:
            data = formats.data_points(pattern)
        except AalabError as e:
            raise AalabError(e.code, e.message, "pattern.points.data" +
                             e.field[len("points"):] if e.field.startswith("points") else e.field)
        ps = formats.PointSet(tuple((p[0], p[1]) for p in data),
                              tuple(p[2] for p in data) if data and len(data[0]) == 3 else None)
        return ps.to_pattern(tile, kernel, weights)
    raise AalabError("invalid_field", "cannot use a %s as a pattern (a preset name, a wire dict, "
                     "a Job, points or a file path)" % type(pattern).__name__, "pattern")
