"""A job on the daemon (``POST /v1/jobs``) and how to follow it."""

from __future__ import annotations

import html
import sys
import time
from typing import TYPE_CHECKING, Any, Dict, Optional, Union

from .errors import AalabError
from .results import PointMetrics, Trace
from .tables import ResultTable, result_table

if TYPE_CHECKING:  # pragma: no cover
    from .client import Client

ENDED = frozenset(("done", "failed", "cancelled", "interrupted"))


class Job:
    """One job, by id. Nothing is cached until the job has ended: while it is queued or
    running, each of :attr:`state`, :attr:`result`, :attr:`best_pattern`, :attr:`best_e2`,
    :attr:`trace` and :attr:`info` asks the daemon (``GET /v1/jobs/{id}``); once it has ended,
    the last answer is kept.

    A ``Job`` is also a pattern argument: ``client.evaluate(job)`` evaluates its best pattern
    (the daemon resolves ``{"job": ID}``).
    """

    def __init__(self, client: "Client", job_id: int,
                 summary: Optional[Dict[str, Any]] = None) -> None:
        self._client = client
        self.job_id = int(job_id)
        self.summary: Optional[Dict[str, Any]] = summary
        """The job as listed (``jobs()``) or as answered at submission, without spec, best,
        trace and result."""
        self._info: Optional[Dict[str, Any]] = None

    @property
    def id(self) -> int:
        return self.job_id

    def __repr__(self) -> str:
        known = self._info or self.summary or {}
        if "kind" not in known or "state" not in known:
            # client.job(ID) knows only the id: ask once, so the repr says what the job is
            # even before an attribute was read (a daemon that cannot answer leaves "?").
            try:
                known = self.refresh()
            except Exception:  # noqa: BLE001 - a repr must not raise
                pass
        return "<aalab.Job %d %s %s>" % (self.job_id, known.get("kind", "?"),
                                         known.get("state", "?"))

    def table(self) -> ResultTable:
        """The kind's result as a table (columns as ``aalab job ID --csv``); no rows before
        the job is done."""
        info = self.info
        return result_table(info.get("kind", "?"), info.get("result"))

    def to_frame(self) -> Any:
        """The kind's result as a ``pandas.DataFrame`` (python3-pandas): optimize a row per
        seed, family-sweep per configuration, random-stats one Table 3 row, table3 per
        distribution (mean, sd and paper per column), compare per pattern, animation per frame,
        reference-convergence per level, temporal-optimize per seed, temporal-render per phase
        (rendered RMSE beside the edge model's prediction)."""
        return self.table().to_frame()

    def _repr_html_(self) -> str:
        """Jupyter: the job's id, kind and state, then its result table."""
        info = self.info
        head = "<p><b>aalab job %d</b> %s, %s</p>" % (
            self.job_id, html.escape(str(info.get("kind", "?"))),
            html.escape(str(info.get("state", "?"))))
        return head + self.table()._repr_html_()

    def refresh(self) -> Dict[str, Any]:
        """Fetches the job (``GET /v1/jobs/{id}``, job.json) and returns it."""
        self._info = self._client._get_job(self.job_id)
        return self._info

    @property
    def info(self) -> Dict[str, Any]:
        """The whole job document (job.json): kind, state, progress (0..1), created/started/
        finished (Unix seconds), spec, best, trace, result, error..."""
        if self._info is not None and self._info.get("state") in ENDED:
            return self._info
        return self.refresh()

    @property
    def state(self) -> str:
        """``queued``, ``running``, ``done``, ``failed``, ``cancelled`` or ``interrupted``."""
        return self.info["state"]

    @property
    def kind(self) -> str:
        return (self._info or self.summary or self.info)["kind"]

    @property
    def progress(self) -> float:
        """Fraction done, 0..1."""
        return float(self.info.get("progress") or 0.0)

    @property
    def result(self) -> Optional[Dict[str, Any]]:
        """The kind's result once done (kinds/<kind>.result.json), None before."""
        return self.info.get("result")

    @property
    def error(self) -> Optional[AalabError]:
        """Why a failed job failed, as an :class:`AalabError` (code, message, field), else
        None."""
        e = self.info.get("error")
        if not e:
            return None
        return AalabError(e.get("code", "internal"), e.get("message", ""), e.get("field", ""),
                          job=self.job_id)

    @property
    def best_pattern(self) -> Optional[Dict[str, Any]]:
        """The best pattern so far in wire form (pattern.json, with ``family``, ``cost_spp``,
        ``form`` and ``kernels_expanded``), None if none yet."""
        best = self.info.get("best")
        p = best.get("pattern") if isinstance(best, dict) else None
        # An encoded pattern only: animation's best names its pattern's family and cost.
        return p if isinstance(p, dict) and "form" in p else None

    @property
    def best_e2(self) -> Optional[float]:
        """E2 of the best pattern so far (None when the kind has none)."""
        best = self.info.get("best")
        if isinstance(best, dict) and best.get("e2") is not None:
            return float(best["e2"])
        v = self.info.get("best_e2")
        return None if v is None else float(v)

    @property
    def trace(self) -> Trace:
        """Best E2 against run time (:class:`~aalab.results.Trace`)."""
        return Trace.from_answer(self.info.get("trace"))

    @property
    def point_metrics(self) -> Union[None, PointMetrics, Dict[str, PointMetrics]]:
        """The point-set figures per random pattern and their Spearman rho with E2, when the
        spec of a random-stats or table3 job asked for ``metrics`` (docs/analysis.md):
        a :class:`~aalab.results.PointMetrics` for random-stats, a dict distribution ->
        :class:`~aalab.results.PointMetrics` for table3; None otherwise or before the job is
        done."""
        r = self.result
        if not isinstance(r, dict):
            return None
        if isinstance(r.get("point_metrics"), dict):
            return PointMetrics.from_answer(r["point_metrics"])
        rows = {row["distribution"]: PointMetrics.from_answer(row["point_metrics"])
                for row in r.get("rows") or [] if isinstance(row.get("point_metrics"), dict)}
        return rows or None

    def wait(self, progress: bool = True, timeout: Optional[float] = None, poll: float = 0.25,
             raise_on_failure: bool = True) -> "Job":
        """Waits until the job has ended and returns it.

        Args:
            progress: draw a progress bar on stderr (tqdm, where it is installed).
            timeout: give up after this many seconds (:class:`AalabError` code ``timeout``;
                the job goes on); None waits as long as it takes.
            poll: seconds between two ``GET /v1/jobs/{id}``.
            raise_on_failure: a ``failed`` job raises its error (:class:`AalabError` with the
                job's code, message and field, ``.job`` set); ``cancelled`` and
                ``interrupted`` return normally (check :attr:`state`).

        Ctrl-C (KeyboardInterrupt) stops the waiting, not the job.
        """
        if poll <= 0:
            raise ValueError("poll must be positive seconds")
        deadline = None if timeout is None else time.monotonic() + timeout
        bar = self._bar() if progress else None
        try:
            while True:
                info = self.refresh()
                if bar is not None:
                    bar.n = round(100 * float(info.get("progress") or 0.0), 1)
                    e2 = info.get("best_e2")
                    if e2 is None and isinstance(info.get("best"), dict):
                        e2 = info["best"].get("e2")
                    bar.set_postfix_str(info["state"] + ("" if e2 is None else
                                                         ", best E2 %.6f" % e2), refresh=False)
                    bar.refresh()
                if info["state"] in ENDED:
                    break
                if deadline is not None and time.monotonic() >= deadline:
                    raise AalabError("timeout", "job %d still %s after %.1f s"
                                     % (self.job_id, info["state"], timeout), job=self.job_id)
                time.sleep(poll if deadline is None else
                           max(0.0, min(poll, deadline - time.monotonic())))
        finally:
            if bar is not None:
                bar.close()
        if raise_on_failure and self._info["state"] == "failed":
            err = self.error
            raise err if err else AalabError("internal", "job failed", job=self.job_id)
        return self

    def _bar(self) -> Any:
        try:
            from tqdm import tqdm
        except ImportError:
            return None
        return tqdm(total=100, desc="job %d" % self.job_id, unit="%", file=sys.stderr,
                    bar_format="{desc}: {percentage:3.0f}%|{bar}| {elapsed}{postfix}")

    def cancel(self) -> str:
        """Asks the job to stop (``DELETE /v1/jobs/{id}``); it ends ``cancelled`` at its next
        check. Returns the state when the request was accepted. Cancelling a finished job is
        an :class:`AalabError` with code ``conflict``."""
        d = self._client._call("DELETE", "/v1/jobs/%d" % self.job_id,
                               schema="job_delete_response.json", expect=(200, 202))
        self._info = None
        return d["state"]

    def purge(self) -> None:
        """Deletes the finished job from the store (``DELETE /v1/jobs/{id}?purge=1``)."""
        self._client._call("DELETE", "/v1/jobs/%d?purge=1" % self.job_id,
                           schema="job_delete_response.json")

    def pin(self, pinned: bool = True) -> None:
        """Exempts the job from the retention of finished jobs (or not)."""
        self._info = self._client._call("PATCH", "/v1/jobs/%d" % self.job_id,
                                        {"pinned": bool(pinned)}, schema="job.json")

    def export(self, fmt: str = "json", path: Optional[str] = None) -> Union[Dict[str, Any], str]:
        """The job's best pattern exported (``GET /v1/patterns/{id}/export``).

        ``fmt``: ``json`` (the pattern document), ``utk``, ``xyw``, ``csv`` (point-set text in
        the unit square of the whole tile, with the ``# aalab-pattern`` header for an exact
        round trip), ``points-json``, ``vulkan``, ``d3d12`` (:meth:`Client.export`). JSON
        formats return a dict, text formats a str; with ``path`` the answer is also written
        there.
        """
        return self._client.export(self, fmt, path)
