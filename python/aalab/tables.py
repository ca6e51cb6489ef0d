"""Each job kind's result as a table: columns and rows as ``aalab job ID --csv`` prints them,
converted to a pandas DataFrame (:meth:`ResultTable.to_frame`, pandas from Debian's
python3-pandas, used where installed) or an HTML table for Jupyter (``_repr_html_``, no pandas
needed)."""

from __future__ import annotations

import html
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Sequence, Tuple

# Column name -> key in the result's row objects, per kind: the client's --csv columns (every
# name unique ASCII, issue 34).
_ROWS: Dict[str, Tuple[str, Sequence[Tuple[str, str]]]] = {
    "optimize": ("per_seed", (("seed", "seed"), ("distribution", "distribution"),
                              ("initial_e2", "initial_e2"), ("e2", "e2"),
                              ("iterations", "iterations"))),
    "compare": ("rows", (("name", "name"), ("family", "family"),
                         ("spp", "samples_per_pixel"), ("e2", "e2"), ("rmse", "rmse"),
                         ("predicted", "predicted_rmse"), ("max_dev", "max_dev"),
                         ("render_seconds", "render_seconds"),
                         ("pixels_sampled", "pixels_sampled"))),
    "animation": ("frames", (("frame", "frame"), ("rmse", "rmse"), ("max_dev", "max_dev"),
                             ("pixels_recomputed", "pixels_recomputed"),
                             ("pattern_sampled", "pattern_sampled"),
                             ("reference_supersampled", "reference_supersampled"),
                             ("pattern_seconds", "pattern_seconds"),
                             ("reference_seconds", "reference_seconds"))),
    "reference-convergence": ("rows", (("spp", "spp"), ("rmse", "rmse"),
                                       ("max_dev", "max_dev"), ("seconds", "seconds"),
                                       ("supersampled", "supersampled"),
                                       ("samples", "samples"))),
    "temporal-optimize": ("per_seed", (("seed", "seed"), ("start", "start"),
                                       ("initial_score", "initial_score"), ("score", "score"),
                                       ("e2", "e2"), ("f2", "f2"))),
    "temporal-render": ("phases", (("phase", "phase"), ("e2", "e2"), ("rmse", "rmse"),
                                   ("max_dev", "max_dev"), ("predicted_rmse", "predicted_rmse"),
                                   ("ratio", "ratio"))),
}

_TABLE3_COLUMNS = ("min", "avg", "max", "opt_w", "opt_wp")


@dataclass(frozen=True)
class ResultTable:
    """A job result as a table: ``columns`` (unique ASCII names), ``rows`` (lists of values,
    None where the daemon sent null), the job's ``kind`` and a one-line ``caption``."""

    kind: str
    columns: List[str]
    rows: List[List[Any]]
    caption: str = ""

    def records(self) -> List[Dict[str, Any]]:
        """The rows as dicts, column name -> value."""
        return [dict(zip(self.columns, r)) for r in self.rows]

    def to_frame(self) -> Any:
        """A ``pandas.DataFrame`` with these columns (numbers as floats or ints, null as NaN).
        Raises ImportError saying how to install pandas when it is missing."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - exercised only without pandas
            raise ImportError("to_frame() needs pandas: apt-get install python3-pandas "
                              "(or use .records() / .rows)") from e
        frame = pd.DataFrame(self.rows, columns=self.columns)
        frame.attrs["kind"] = self.kind
        frame.attrs["caption"] = self.caption
        return frame

    def _repr_html_(self) -> str:
        head = "".join("<th>%s</th>" % html.escape(c) for c in self.columns)
        body = "".join("<tr>%s</tr>" % "".join(
            "<td>%s</td>" % html.escape(_cell(v)) for v in r) for r in self.rows)
        cap = "<caption>%s</caption>" % html.escape(self.caption) if self.caption else ""
        return ('<table class="aalab-result" data-kind="%s">%s<thead><tr>%s</tr></thead>'
                "<tbody>%s</tbody></table>" % (html.escape(self.kind), cap, head, body))

    def __len__(self) -> int:
        return len(self.rows)


def _cell(v: Any) -> str:
    if v is None:
        return "—"
    if isinstance(v, float):
        return "%.6g" % v
    return str(v)


def _config_label(c: Dict[str, Any]) -> str:
    return "c%s e%s i%s" % ("".join(str(x) for x in c.get("corners", [])),
                            "".join(str(x) for x in c.get("edges", [])), c.get("interior", ""))


def result_table(kind: str, result: Optional[Dict[str, Any]]) -> ResultTable:
    """The table of a kind's result (kinds/<kind>.result.json). A kind without a table of its
    own (sleep, or a kind newer than this package) gives key,value rows of its top-level
    numbers and strings. ``result`` None (a job not done): no rows."""
    r = result or {}
    if kind in _ROWS:
        key, cols = _ROWS[kind]
        rows = [[x.get(k) for _, k in cols] for x in r.get(key) or []]
        caption = {"optimize": "E2 per seed (job E2 %s)" % _cell(r.get("e2")),
                   "compare": "error against samples per pixel",
                   "animation": "error per frame (0..255)",
                   "reference-convergence": "reference error against samples per pixel",
                   "temporal-optimize": "score per seed (best sequence %s: E2 %s, F2 %s)"
                   % (r.get("family", "?"), _cell(r.get("e2")), _cell(r.get("f2"))),
                   "temporal-render": "steady-state error per phase against the edge model's "
                   "prediction (worst phase %s; %s frames to 5 %%)"
                   % (_cell((r.get("steady") or {}).get("worst_phase")),
                      _cell(r.get("frames_to_5pct")))}[kind]
        return ResultTable(kind, [c for c, _ in cols], rows, caption)
    if kind == "family-sweep":
        cols = ["rank", "configuration", "corners", "edges", "interior", "family", "e2"]
        rows = [[x.get("rank"), _config_label(x.get("config") or {}),
                 sum((x.get("config") or {}).get("corners", [])),
                 sum((x.get("config") or {}).get("edges", [])),
                 (x.get("config") or {}).get("interior"),
                 (x.get("best") or {}).get("family"), x.get("e2")]
                for x in r.get("ranked") or []]
        return ResultTable(kind, cols, rows, "configurations of cost %s ranked by E2"
                           % _cell(r.get("cost")))
    if kind == "random-stats":
        rnd = r.get("random") or {}
        cols = ["family", "distribution", "count", "min", "avg", "max", "opt_w", "opt_wp"]
        rows = [[r.get("family"), r.get("distribution"), r.get("count"), rnd.get("min"),
                 rnd.get("avg"), rnd.get("max"), (r.get("opt_w") or {}).get("e2"),
                 (r.get("opt_wp") or {}).get("e2")]] if r else []
        return ResultTable(kind, cols, rows, "Laine & Aila Table 3 row")
    if kind == "table3":
        cols = ["distribution"]
        for c in _TABLE3_COLUMNS:
            cols += [c, c + "_sd", c + "_paper"]
        rows = []
        for row in r.get("rows") or []:
            vals: List[Any] = [row.get("distribution")]
            for c in _TABLE3_COLUMNS:
                col = (row.get("columns") or {}).get(c) or {}
                vals += [col.get("mean"), col.get("sd"), col.get("paper")]
            rows.append(vals)
        return ResultTable(kind, cols, rows, "Table 3 of %s: mean and sd over %d seeds, the "
                           "paper's value" % (r.get("family", "?"), len(r.get("seeds") or [])))
    rows = [[k, v] for k, v in r.items() if isinstance(v, (int, float, str, bool)) or v is None]
    return ResultTable(kind, ["key", "value"], rows, "%s result" % kind)
