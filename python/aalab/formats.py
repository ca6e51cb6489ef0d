"""Point-set files: read and write UTK, ``x y [w]`` text, CSV and JSON point sets, UTK's binary
``.bin`` and PSA's raw float32 ``.rps``, and files holding several sets.

One coordinate convention for every format: points in the unit square [0, 1)² of the **whole
tile** (UTK's convention): x to the right, y along the tile's y axis, one point per sample. A
tile of T x T pixels maps file point (u, v) to tile coordinates (T·u, T·v), pixel (i, j)
covering [i, i+1] x [j, j+1] (docs/api.md, Patterns). Weights, where a file has them, are the
third number (``w``).

Formats (the daemon's ``{"points": ...}`` pattern form reads the same):

- ``utk``: UTK ``.dat`` text, one point ``x y`` per line; blank lines and lines starting with
  ``#`` are ignored.
- ``xyw``: ``x y`` or ``x y w`` per line (the same comment rule), every line the same arity.
- ``csv``: a header line naming the columns ``x``, ``y`` and optionally ``w`` in any order
  (another column is an error naming it), then one row per point; ``#`` lines before the
  header are comments.
- ``json``: an array of points, each ``[x, y]``, ``[x, y, w]`` or ``{"x":.., "y":.., "w":..}``,
  or an object ``{"aalab": {...}, "points": [...]}``.
- ``bin``: UTK's binary file (utk-team/utk, ``include/utk/utils/PointsetIO.hpp``): the magic
  ``UTK!`` (0x214B5455), a dtype byte (4 float, 5 double; aalab reads these two), 3 reserved
  bytes, then m (sets), N (points per set) and d (dimension, 2 here) as little-endian u32,
  then the values. aalab writes double and m = 1 and puts its header after the data as a
  trailer line (UTK's reader stops at the data's end).
- ``rps``: PSA's raw little-endian float32 ``x y`` pairs (nodag/psa, ``src/point.cpp``); no
  header, so no weights or tile: read it back with ``tile``, ``kernel`` and ``weights``.

Several sets in one file: ``utk`` and ``xyw`` text separated by ``#`` lines (UTK's and pbrt's
``pspec`` convention: a ``#`` line after a point starts the next set; concatenated aalab
exports are such files), ``bin`` with m > 1. ``set=i`` reads set i (from 0); the daemon's
``POST /v1/analyze`` also takes ``set="all"`` (:meth:`aalab.Client.analyze`).

aalab's own exports put what an exact round trip needs into a leading comment line that other
tools ignore, ``# aalab-pattern {JSON}`` (in JSON files: the ``"aalab"`` member): tile, kernel
size, border, per-kernel weights (for a pattern with no tile form, the wire form itself). Such
a file read back gives the same pattern, E2 equal to 1e-12; it is kept in
:attr:`PointSet.meta` and passed to the daemon unchanged by :meth:`PointSet.to_pattern`.
Without it, the options of :meth:`PointSet.to_pattern` (tile, kernel, weights) decide.
"""

from __future__ import annotations

import base64
import csv
import io
import json
import math
import os
import re
import struct
from dataclasses import dataclass
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple, Union

from .errors import AalabError

FORMATS = ("utk", "xyw", "csv", "json", "bin", "rps")
BINARY_FORMATS = ("bin", "rps")  # bytes: sent to the daemon as base64
SET_FORMATS = ("utk", "xyw", "bin")  # may hold several sets
UTK_MAGIC = 0x214B5455
HEADER_PREFIX = "# aalab-pattern "
WEIGHT_CHOICES = ("file", "filter", "equal")

# File name suffix -> format (read and write guess from it).
SUFFIXES = {".dat": "utk", ".utk": "utk", ".txt": "xyw", ".xyw": "xyw", ".pts": "xyw",
            ".csv": "csv", ".json": "json", ".bin": "bin", ".rps": "rps"}

# A decimal number as C's strtod reads it, without nan, inf, hex or Python's "1_000".
_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")

PathLike = Union[str, "os.PathLike[str]"]


class FormatError(AalabError):
    """A point file that does not parse: ``field`` is ``pattern.points.text`` (or
    ``pattern.points.data[i]`` for points given as data), the message names the line."""

    def __init__(self, message: str, field: str = "pattern.points.text") -> None:
        super().__init__("invalid_field", message, field)


@dataclass(frozen=True)
class PointSet:
    """Points of one tile in the unit square, with optional weights.

    Attributes:
        points: list of ``(x, y)`` in [0, 1)² of the whole tile (see the module docstring);
            :attr:`xy` gives them as an N x 2 numpy array.
        weights: one weight per point, or None when the file has none.
        meta: the ``# aalab-pattern`` header (or JSON ``"aalab"`` member), None if absent.
        format: the format read (``utk``, ``xyw``, ``csv``, ``json``).
        text: the file's text as read (sent to the daemon unchanged), None for point sets
            built from arrays.
        data: a binary file's bytes as read (``bin``, ``rps``; sent base64), else None.
        set: the set read from a file holding several (sent with the file), None for the
            whole file.
    """

    points: Tuple[Tuple[float, float], ...]
    weights: Optional[Tuple[float, ...]] = None
    meta: Optional[Dict[str, Any]] = None
    format: str = "json"
    text: Optional[str] = None
    data: Optional[bytes] = None
    set: Optional[int] = None

    def __len__(self) -> int:
        return len(self.points)

    @property
    def xy(self) -> Any:
        """The points as an N x 2 float array (numpy needed)."""
        import numpy as np
        return np.asarray(self.points, dtype=float).reshape(-1, 2)

    @property
    def w(self) -> Any:
        """The weights as a float array, None without weights (numpy needed)."""
        import numpy as np
        return None if self.weights is None else np.asarray(self.weights, dtype=float)

    def to_pattern(self, tile: Optional[int] = None, kernel: Optional[int] = None,
                   weights: Optional[str] = None, border: Optional[bool] = None
                   ) -> Dict[str, Any]:
        """The daemon's pattern form ``{"points": {...}}`` for these points.

        Args:
            tile: T, the tile is T x T pixels; points are scaled by T (default 1).
            kernel: K, each kernel reads K x K pixels (default 1).
            border: samples on the boundary of a kernel's block are read too (the ``+`` of
                P(s,r+,n); default false).
            weights: ``"file"`` (the file's w per point; the default), ``"filter"`` (each
                kernel's samples weighted by the evaluation's reference filter) or
                ``"equal"``. Without weights in the file and without an aalab header, choose
                ``"filter"`` or ``"equal"``: ``"file"`` is then an error naming
                ``pattern.points.weights``.

        Options left None are not sent (the daemon's defaults, or the file's aalab header,
        apply; stated options must agree with the header). Points read from a file are sent as
        the file's text, so the daemon parses exactly what was read.
        """
        if weights is not None and weights not in WEIGHT_CHOICES:
            raise AalabError("invalid_field", "weights must be one of %s" % ", ".join(WEIGHT_CHOICES),
                             "pattern.points.weights")
        if weights in (None, "file") and self.weights is None and self.meta is None:
            raise AalabError("invalid_field", "the points have no weights; choose filter or equal",
                             "pattern.points.weights")
        if self.data is not None:
            body: Dict[str, Any] = {"format": self.format,
                                    "base64": base64.b64encode(self.data).decode("ascii")}
        elif self.text is not None:
            body = {"format": self.format, "text": self.text}
        else:
            data: List[List[float]] = [list(p) for p in self.points]
            if self.weights is not None:
                data = [[x, y, w] for (x, y), w in zip(self.points, self.weights)]
            body = {"format": "json", "data": data}
        for k, v in (("set", self.set), ("tile", tile), ("kernel", kernel), ("border", border),
                     ("weights", weights)):
            if v is not None:
                body[k] = v
        return {"points": body}


def guess_format(path: PathLike) -> str:
    """The format a file name suggests (``.dat`` utk, ``.txt``/``.xyw`` xyw, ``.csv``,
    ``.json``); raises :class:`AalabError` for other suffixes."""
    suffix = os.path.splitext(os.fspath(path))[1].lower()
    try:
        return SUFFIXES[suffix]
    except KeyError:
        raise AalabError("invalid_field", "%s: cannot tell the point format from the suffix "
                         "%r; pass fmt= (one of %s)" % (os.fspath(path), suffix, ", ".join(FORMATS)),
                         "format") from None


MAX_POINTS = 4096  # points of one file (one tile), the daemon's limit
_BLANKS = " \t\r\f\v"


def _lines(text: str, line0: int = 0):
    """(1-based line number, line without surrounding blanks), every line; the first is
    line0 + 1 (a set of a longer file)."""
    for n, raw in enumerate(text.split("\n"), line0 + 1):
        yield n, raw.strip(_BLANKS)


class _Header:
    """The aalab header: once, before the first point (the daemon's rule)."""

    def __init__(self) -> None:
        self.meta: Optional[Dict[str, Any]] = None
        self.line = 0

    def comment(self, line: str, n: int, points: int) -> None:
        if not line.startswith(HEADER_PREFIX):
            return
        if self.meta is not None:
            raise FormatError("line %d: a second aalab-pattern header (the first is on line %d; "
                              "several sets in one file? choose one with set)" % (n, self.line))
        if points:
            raise FormatError("line %d: the aalab-pattern header must come before the points" % n)
        try:
            meta = json.loads(line[len(HEADER_PREFIX):])
        except ValueError as e:
            raise FormatError("line %d: the aalab-pattern header is not a JSON object: %s"
                              % (n, e)) from None
        if not isinstance(meta, dict):
            raise FormatError("line %d: the aalab-pattern header is not a JSON object" % n)
        self.meta, self.line = meta, n


def _token(tok: str, where: str, column: str = "") -> float:
    col = column + ": " if column else ""
    if not _NUMBER.match(tok) or not math.isfinite(float(tok)):
        raise FormatError("%s: %s'%s' is not a number" % (where, col, tok[:24] +
                                                           ("..." if len(tok) > 24 else "")))
    return float(tok)


def _parse_plain(text: str, fmt: str, line0: int = 0) -> PointSet:
    utk = fmt == "utk"
    expect = "2 numbers (x y)" if utk else "2 or 3 numbers (x y [w])"
    header = _Header()
    pts: List[Tuple[float, float]] = []
    ws: List[float] = []
    arity, arity_line = 0, 0
    for n, line in _lines(text, line0):
        if not line:
            continue
        if line.startswith("#"):
            header.comment(line, n, len(pts))
            continue
        toks = line.split()
        if len(toks) > 3:
            raise FormatError("line %d: expected %s" % (n, expect))
        v = [_token(t, "line %d" % n) for t in toks]
        if len(v) < 2 or (utk and len(v) != 2):
            raise FormatError("line %d: expected %s" % (n, expect))
        if arity and len(v) != arity:
            raise FormatError("line %d: %d numbers, but line %d has %d (every line gives x y, "
                              "or every line x y w)" % (n, len(v), arity_line, arity))
        if not arity:
            arity, arity_line = len(v), n
        if len(pts) == MAX_POINTS:
            raise FormatError("line %d: more than %d points" % (n, MAX_POINTS))
        pts.append((v[0], v[1]))
        if len(v) == 3:
            ws.append(v[2])
    if not pts:
        raise FormatError("no points (one point per line: x y)")
    return PointSet(tuple(pts), tuple(ws) if arity == 3 else None, header.meta, fmt, text)


def _csv_fields(line: str) -> List[str]:
    out = []
    for f in line.split(","):
        f = f.strip(_BLANKS)
        if len(f) >= 2 and f[0] == '"' and f[-1] == '"':
            f = f[1:-1]
        out.append(f)
    return out


# As the C codec (proto/pointset_parse.c): a line splits into at most this many fields, beyond
# which it says "more than".
_CSV_MAX_COLUMNS = 8


def _parse_csv(text: str) -> PointSet:
    header = _Header()
    cols: List[str] = []
    head_line = 0
    pts: List[Tuple[float, float]] = []
    ws: List[float] = []
    for n, line in _lines(text):
        if not line:
            continue
        if line.startswith("#"):
            header.comment(line, n, len(pts))
            continue
        f = _csv_fields(line)
        if not cols:
            if len(f) > _CSV_MAX_COLUMNS:
                raise FormatError("line %d: more than %d columns (the columns are x, y and "
                                  "optionally w)" % (n, _CSV_MAX_COLUMNS))
            for c in f:
                name = c.lower()
                if name not in ("x", "y", "w"):
                    raise FormatError("line %d: unknown column '%s' (the columns are x, y and "
                                      "optionally w, named in a header line)" % (n, c[:24]))
                if name in cols:
                    raise FormatError("line %d: column %s twice" % (n, name))
                cols.append(name)
            if "x" not in cols or "y" not in cols:
                raise FormatError("line %d: the header line must name columns x and y" % n)
            head_line = n
            continue
        if len(f) != len(cols):
            many = len(f) > _CSV_MAX_COLUMNS
            count = _CSV_MAX_COLUMNS if many else len(f)
            raise FormatError("line %d: %s%d field%s, but the header (line %d) names %d"
                              % (n, "more than " if many else "", count,
                                 "" if count == 1 else "s", head_line, len(cols)))
        v = {c: _token(x, "line %d" % n, c) for c, x in zip(cols, f)}
        if len(pts) == MAX_POINTS:
            raise FormatError("line %d: more than %d points" % (n, MAX_POINTS))
        pts.append((v["x"], v["y"]))
        if "w" in v:
            ws.append(v["w"])
    if not cols:
        raise FormatError("no header line: a CSV point set starts with x,y or x,y,w")
    if not pts:
        raise FormatError("no points (one point per line: x,y after a header line)")
    return PointSet(tuple(pts), tuple(ws) if "w" in cols else None, header.meta, "csv", text)


def _points_from_data(data: Any, field: str, by_index: bool
                      ) -> Tuple[List[Tuple[float, float]], Optional[List[float]]]:
    """Points of a JSON array, checked as the daemon does: errors name ``field[i]`` (by_index,
    the ``data`` key) or ``field`` with ``point i:`` in the message (a JSON text)."""
    if not isinstance(data, list):
        raise FormatError("must be an array of points ([x, y], [x, y, w] or {\"x\",\"y\",\"w\"})",
                          field)
    if len(data) > MAX_POINTS:
        raise FormatError("more than %d points" % MAX_POINTS, field)
    pts: List[Tuple[float, float]] = []
    ws: List[float] = []
    has_w = False
    for i, p in enumerate(data):
        f, where = ("%s[%d]" % (field, i), "") if by_index else (field, "point %d: " % i)
        if isinstance(p, list):
            if len(p) not in (2, 3):
                raise FormatError("%sa point is [x, y] or [x, y, w]" % where, f)
            vals = dict(zip("xyw", p))
        elif isinstance(p, dict):
            for k in p:
                if k not in ("x", "y", "w"):
                    raise FormatError("%sunknown key '%s' (a point has x, y and optionally w)"
                                      % (where, str(k)[:40]), f)
            if "x" not in p or "y" not in p:
                raise FormatError("%sa point needs x and y" % where, f)
            vals = dict(p)
        else:
            raise FormatError("%sa point is [x, y], [x, y, w] or {\"x\":..,\"y\":..,\"w\":..}"
                              % where, f)
        for k in ("x", "y", "w"):
            v = vals.get(k)
            if k in vals and (isinstance(v, bool) or not isinstance(v, (int, float))
                              or not math.isfinite(v)):
                raise FormatError("%s%s must be a finite number" % (where, k), f)
        w_here = "w" in vals
        if i == 0:
            has_w = w_here
        elif w_here != has_w:
            raise FormatError("%s%s (give w for every point or for none)"
                              % (where, "has w but point 0 has not" if w_here
                                 else "has no w but point 0 has"), f)
        pts.append((float(vals["x"]), float(vals["y"])))
        if w_here:
            ws.append(float(vals["w"]))
    if not pts:
        raise FormatError("no points", field)
    return pts, (ws if has_w else None)


def _parse_json(text: str) -> PointSet:
    try:
        doc = json.loads(text, object_pairs_hook=_no_duplicates)
    except ValueError as e:
        line = getattr(e, "lineno", 1)
        raise FormatError("line %d: not valid JSON: %s" % (line, getattr(e, "msg", e))) from None
    meta = None
    data = doc
    field = "pattern.points.text"
    if isinstance(doc, dict):
        for k in doc:
            if k not in ("aalab", "points"):
                # As the daemon's proto_check_keys: the field names the key.
                raise FormatError("unknown field", field + "." + k)
        if "points" not in doc:
            raise FormatError("the object form needs points", field + ".points")
        meta = doc.get("aalab")
        if meta is not None and not isinstance(meta, dict):
            raise FormatError("must be an object", field + ".aalab")
        data = doc["points"]
    pts, ws = _points_from_data(data, field, False)
    return PointSet(tuple(pts), tuple(ws) if ws is not None else None, meta, "json", text)


def _no_duplicates(pairs: List[Tuple[str, Any]]) -> Dict[str, Any]:
    d: Dict[str, Any] = {}
    for k, v in pairs:
        if k in d:
            raise ValueError("duplicate key %r" % k)
        d[k] = v
    return d


def _split_sets(text: str) -> List[Tuple[int, str]]:
    """UTK's sets of a text: (the line before the set's first, its text). A ``#`` line after a
    point starts the next set; sets without points do not count (proto/pointset_parse.c)."""
    lines = text.split("\n")
    sets: List[Tuple[int, str]] = []
    start, has_points = 0, False
    for i, raw in enumerate(lines):
        line = raw.strip(_BLANKS)
        if not line:
            continue
        if line.startswith("#"):
            if has_points:
                sets.append((start, "\n".join(lines[start:i]) + "\n"))
                start, has_points = i, False
            continue
        has_points = True
    if has_points:
        sets.append((start, "\n".join(lines[start:])))
    return sets


def _check_format(fmt: str) -> None:
    if fmt not in FORMATS:
        raise AalabError("invalid_field", "format must be one of %s" % ", ".join(FORMATS),
                         "pattern.points.format")


def count_sets(content: Union[str, bytes], fmt: str) -> int:
    """The number of sets in a file's text or bytes (1 for csv, json, rps)."""
    _check_format(fmt)
    if fmt == "bin":
        return _parse_bin(bytes(content), 0, count_only=True)  # type: ignore[return-value]
    if fmt not in SET_FORMATS:
        return 1
    return len(_split_sets(content if isinstance(content, str) else content.decode("utf-8")))


def loads(text: str, fmt: str, set: Optional[int] = None) -> PointSet:
    """Parses the text of a point file in format ``fmt`` (one of :data:`FORMATS`; bin and rps
    go to :func:`loads_bytes`). ``set``: one set of a utk or xyw file holding several.

    Raises :class:`FormatError` naming the line (``line 3: expected 2 or 3 numbers``) or the
    point (``points[3]``)."""
    _check_format(fmt)
    if fmt in BINARY_FORMATS:
        return loads_bytes(text.encode("latin-1") if isinstance(text, str) else text, fmt, set)
    if set is not None:
        if fmt not in SET_FORMATS:
            raise FormatError("a %s file holds one set; set is for utk, xyw and bin files" % fmt,
                              "pattern.points.set")
        sets = _split_sets(text)
        if not 0 <= set < len(sets):
            raise FormatError("is %d but the file holds %d set%s ('#' lines separate them; sets "
                              "count from 0)" % (set, len(sets), "" if len(sets) == 1 else "s"),
                              "pattern.points.set")
        line0, part = sets[set]
        ps = _parse_plain(part, fmt, line0)
        return PointSet(ps.points, ps.weights, ps.meta, fmt, text, None, set)
    if fmt == "csv":
        return _parse_csv(text)
    if fmt == "json":
        return _parse_json(text)
    return _parse_plain(text, fmt)


_BASE64_FIELD = "pattern.points.base64"
_DTYPES = ("int32", "int64", "uint32", "uint64", "float", "double")


def _binary_points(data: bytes, offset: int, n: int, size: int) -> List[Tuple[float, float]]:
    vals = struct.unpack_from("<%d%s" % (2 * n, "f" if size == 4 else "d"), data, offset)
    pts = []
    for i in range(n):
        x, y = vals[2 * i], vals[2 * i + 1]
        if not (math.isfinite(x) and math.isfinite(y)):
            bad = y if math.isfinite(x) else x
            raise FormatError("point %d: %s is not a finite number (%s)"
                              % (i, "y" if math.isfinite(x) else "x", _c_g(bad)), _BASE64_FIELD)
        pts.append((x, y))
    return pts


def _c_g(v: float) -> str:
    """C's %g of a non-finite double."""
    return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")


def _parse_bin(data: bytes, set: Optional[int], count_only: bool = False) -> Any:
    F = _BASE64_FIELD
    if len(data) < 20:
        raise FormatError("truncated: %d bytes, but UTK's header alone is 20 (magic, dtype, m, N, "
                          "d)" % len(data), F)
    magic, dtype, m, n, d = struct.unpack_from("<IB3xIII", data)
    if magic != UTK_MAGIC:
        raise FormatError("bytes 0-3: magic is 0x%08X, not UTK's 0x%08X (\"UTK!\")"
                          % (magic, UTK_MAGIC), F)
    if dtype not in (4, 5):
        raise FormatError("byte 4: dtype is %d (%s); aalab reads float (4) and double (5)"
                          % (dtype, _DTYPES[dtype] if dtype < 6 else "unknown"), F)
    if d != 2:
        raise FormatError("bytes 16-19: dimension d is %d; aalab reads 2-D point sets only" % d, F)
    if m == 0 or n == 0:
        raise FormatError("no points: the header says m = %d sets of N = %d" % (m, n), F)
    if n > MAX_POINTS:
        raise FormatError("bytes 12-15: N is %d points per set, more than %d" % (n, MAX_POINTS), F)
    size = 4 if dtype == 4 else 8
    per_set = n * 2 * size
    total, after = m * per_set, len(data) - 20
    what = "m = %d sets of N = %d points of d = 2 %s (%d bytes of data), but %d bytes follow it" \
        % (m, n, _DTYPES[dtype], total, after)
    if after < total:
        raise FormatError("truncated: the header says " + what, F)
    meta = None
    if after > total:
        trailer = data[20 + total:]
        if not trailer.startswith(HEADER_PREFIX.encode()):
            raise FormatError("count mismatch: the header says " + what, F)
        try:
            meta = json.loads(trailer[len(HEADER_PREFIX):].rstrip(b"\n").decode("utf-8"))
        except ValueError:
            meta = None
        if not isinstance(meta, dict):
            raise FormatError("the aalab-pattern trailer after the data is not a JSON object", F)
    if count_only:
        return m
    if set is None and m != 1:
        raise FormatError("the file holds %d sets (UTK's m); choose one with set" % m,
                          "pattern.points.set")
    which = 0 if set is None else set
    if which >= m:
        raise FormatError("is %d but the file holds %d set%s (sets count from 0)"
                          % (which, m, "" if m == 1 else "s"), "pattern.points.set")
    return _binary_points(data, 20 + which * per_set, n, size), meta


def loads_bytes(data: bytes, fmt: str, set: Optional[int] = None) -> PointSet:
    """Parses a binary point file (``bin`` or ``rps``) as the daemon does; errors name
    ``pattern.points.base64`` (or ``pattern.points.set``) with the byte or point at fault."""
    data = bytes(data)
    if fmt == "bin":
        pts, meta = _parse_bin(data, set)
        return PointSet(tuple(pts), None, meta, "bin", None, data, set)
    if fmt != "rps":
        raise AalabError("invalid_field", "loads_bytes reads bin or rps", "pattern.points.format")
    if set not in (None, 0):
        raise FormatError("is %d but an rps file holds one set" % set, "pattern.points.set")
    if len(data) % 8:
        raise FormatError("truncated: %d bytes is not a whole number of points (8 bytes each: x "
                          "and y as little-endian float32)" % len(data), _BASE64_FIELD)
    if not data:
        raise FormatError("no points (an empty file)", _BASE64_FIELD)
    if len(data) // 8 > MAX_POINTS:
        raise FormatError("%d points, more than %d" % (len(data) // 8, MAX_POINTS), _BASE64_FIELD)
    return PointSet(tuple(_binary_points(data, 0, len(data) // 8, 4)), None, None, "rps", None,
                    data, set)


def read(path: PathLike, fmt: Optional[str] = None, *, text: Optional[str] = None,
         set: Optional[int] = None) -> PointSet:
    """Reads a point file; ``fmt`` defaults to the suffix's format (:func:`guess_format`).
    ``text``: the file's contents when the caller has already read them; ``set``: one set of a
    file holding several. Errors name the file and the line."""
    fmt = fmt or guess_format(path)
    try:
        if fmt in BINARY_FORMATS:
            with open(path, "rb") as fb:
                return loads_bytes(fb.read(), fmt, set)
        if text is None:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        return loads(text, fmt, set)
    except FormatError as e:
        raise FormatError("%s: %s" % (os.fspath(path), e.message), e.field) from None


def read_sets(path: PathLike, fmt: Optional[str] = None) -> List[PointSet]:
    """Every set of a file holding several (utk, xyw, bin), each as :func:`read` with set=i."""
    fmt = fmt or guess_format(path)
    with open(path, "rb") as f:
        raw = f.read()
    n = count_sets(raw if fmt == "bin" else raw.decode("utf-8"), fmt)
    return [read(path, fmt, set=i) for i in range(n)]


def _fmt_num(v: float) -> str:
    return repr(float(v))  # the shortest text that reads back to the same double


def _finite(v: Any, what: str, field: str) -> float:
    try:
        f = float(v)
    except (TypeError, ValueError):
        f = float("nan")
    if isinstance(v, bool) or not math.isfinite(f):
        raise AalabError("invalid_field", "%s: not a finite number" % what, field)
    return f


def _as_rows(points: Any, weights: Any) -> Tuple[List[Tuple[float, float]], Optional[List[float]]]:
    """Points (and weights) given as a PointSet, an array or a sequence, checked: finite
    numbers, 2 or 3 per point, the same on every point, weights (if given) one per point."""
    if isinstance(points, PointSet):
        rows: List[Any] = [list(p) for p in points.points]
        if weights is None and points.weights is not None:
            weights = points.weights
    else:
        rows = points.tolist() if hasattr(points, "tolist") else list(points)
    pts: List[Tuple[float, float]] = []
    ws: List[float] = []
    for i, r in enumerate(rows):
        r = list(r) if isinstance(r, (list, tuple)) or hasattr(r, "tolist") else [r]
        if len(r) not in (2, 3):
            raise AalabError("invalid_field", "point %d: expected (x, y) or (x, y, w)" % i,
                             "points[%d]" % i)
        v = [_finite(x, "point %d" % i, "points[%d]" % i) for x in r]
        if i and (len(v) == 3) != bool(ws):
            raise AalabError("invalid_field", "point %d: every point needs a weight if one has"
                             % i, "points[%d]" % i)
        pts.append((v[0], v[1]))
        if len(v) == 3:
            ws.append(v[2])
    if not pts:
        raise AalabError("invalid_field", "no points", "points")
    if weights is not None:
        w = weights.tolist() if hasattr(weights, "tolist") else list(weights)
        if len(w) != len(pts):
            raise AalabError("invalid_field", "%d weights for %d points" % (len(w), len(pts)),
                             "weights")
        return pts, [_finite(x, "weight %d" % i, "weights[%d]" % i) for i, x in enumerate(w)]
    return pts, (ws or None)


def dumps(points: Any, fmt: str, weights: Optional[Sequence[float]] = None,
          meta: Optional[Dict[str, Any]] = None) -> str:
    """The text of a point file.

    Args:
        points: a :class:`PointSet`, an N x 2 (or N x 3 with weights) array, or a sequence of
            ``(x, y)`` / ``(x, y, w)``, in the unit square of the whole tile.
        fmt: ``utk``, ``xyw``, ``csv`` or ``json``.
        weights: one per point (overrides a third column); UTK has no weight column, so
            weights there need ``meta`` to carry them or are refused.
        meta: the ``# aalab-pattern`` header (JSON: the ``"aalab"`` member); for a
            :class:`PointSet` its own meta is kept unless given.

    Numbers are written with the fewest digits that read back to the same double.
    """
    if fmt not in FORMATS:
        raise AalabError("invalid_field", "format must be one of %s" % ", ".join(FORMATS),
                         "format")
    if fmt in BINARY_FORMATS:
        raise AalabError("invalid_field", "%s is bytes: use dumps_bytes" % fmt, "format")
    if meta is None and isinstance(points, PointSet):
        meta = points.meta
    pts, ws = _as_rows(points, weights)
    if fmt == "json":
        data = [[x, y, w] for (x, y), w in zip(pts, ws)] if ws is not None else \
            [[x, y] for x, y in pts]
        doc: Any = {"aalab": meta, "points": data} if meta is not None else data
        return json.dumps(doc, allow_nan=False) + "\n"
    out = io.StringIO()
    if meta is not None:
        out.write(HEADER_PREFIX + json.dumps(meta, separators=(",", ":"), allow_nan=False) + "\n")
    if fmt == "utk":
        if ws is not None and meta is None:
            raise AalabError("invalid_field", "UTK files have no weight column: write xyw, csv "
                             "or json, or drop the weights", "format")
        for x, y in pts:
            out.write("%s %s\n" % (_fmt_num(x), _fmt_num(y)))
    elif fmt == "xyw":
        for i, (x, y) in enumerate(pts):
            out.write(" ".join(_fmt_num(v) for v in ((x, y, ws[i]) if ws is not None else (x, y)))
                      + "\n")
    else:
        w = csv.writer(out, lineterminator="\n")
        w.writerow(["x", "y", "w"] if ws is not None else ["x", "y"])
        for i, (x, y) in enumerate(pts):
            w.writerow([_fmt_num(v) for v in ((x, y, ws[i]) if ws is not None else (x, y))])
    return out.getvalue()


def dumps_bytes(points: Any, fmt: str, meta: Optional[Dict[str, Any]] = None) -> bytes:
    """The bytes of a binary point file: ``bin`` (UTK's header, float64, m = 1, ``meta`` as the
    aalab-pattern trailer after the data) or ``rps`` (float32 pairs, nothing else: no weights,
    no header, numbers rounded to float32). Weights are refused unless ``meta`` carries them
    (bin)."""
    if meta is None and isinstance(points, PointSet):
        meta = points.meta
    pts, ws = _as_rows(points, None)
    if fmt == "rps":
        if ws is not None or meta is not None:
            raise AalabError("invalid_field", "rps files hold float32 x y only: drop the weights "
                             "and the header", "format")
        return struct.pack("<%df" % (2 * len(pts)), *[v for p in pts for v in p])
    if fmt != "bin":
        raise AalabError("invalid_field", "dumps_bytes writes bin or rps", "format")
    if ws is not None and meta is None:
        raise AalabError("invalid_field", "UTK's bin has no weight column: write xyw, csv or "
                         "json, or drop the weights", "format")
    out = struct.pack("<IB3xIII", UTK_MAGIC, 5, 1, len(pts), 2)
    out += struct.pack("<%dd" % (2 * len(pts)), *[v for p in pts for v in p])
    if meta is not None:
        out += (HEADER_PREFIX + json.dumps(meta, separators=(",", ":"), allow_nan=False)
                + "\n").encode("utf-8")
    return out


def write(path: PathLike, points: Any, fmt: Optional[str] = None,
          weights: Optional[Sequence[float]] = None, meta: Optional[Dict[str, Any]] = None) -> str:
    """Writes a point file (:func:`dumps`, bin and rps :func:`dumps_bytes`); ``fmt`` defaults
    to the suffix's format. Returns the path written."""
    fmt = fmt or guess_format(path)
    if fmt in BINARY_FORMATS:
        if weights is not None:
            raise AalabError("invalid_field", "%s files have no weight column" % fmt, "format")
        with open(path, "wb") as f:
            f.write(dumps_bytes(points, fmt, meta))
        return os.fspath(path)
    text = dumps(points, fmt, weights=weights, meta=meta)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return os.fspath(path)


def data_points(points: Iterable[Any]) -> List[List[float]]:
    """Points given as an array or sequence, checked, as the JSON ``data`` list of the daemon's
    points form (``[x, y]`` or ``[x, y, w]`` each)."""
    pts, ws = _as_rows(points, None)
    if ws is not None:
        return [[x, y, w] for (x, y), w in zip(pts, ws)]
    return [[x, y] for x, y in pts]
