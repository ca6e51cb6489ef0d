"""The client of one aalab daemon."""

from __future__ import annotations

import os
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple, Union

from . import schemas as _schemas
from .errors import AalabError
from .job import Job
from .patterns import as_pattern
from .results import Analysis, Enumeration, Evaluation, Render, decode_png
from .temporal import TemporalEvaluation, is_temporal
from .temporal import temporal as _temporal
from .transport import Transport, path_with_query, quote_segment

JOB_STATES = ("queued", "running", "done", "failed", "cancelled", "interrupted")
TEXT_EXPORTS = ("utk", "xyw", "csv")


def _filter(f: Any) -> Optional[Dict[str, Any]]:
    if f is None or isinstance(f, dict):
        return f
    if isinstance(f, str):
        return {"name": f}
    raise AalabError("invalid_field", "filter must be a name or a dict (filter.json)", "filter")


def _acuity(a: Any) -> Optional[Dict[str, Any]]:
    if a is None or isinstance(a, dict):
        return a
    if isinstance(a, str):
        return {"name": a}
    raise AalabError("invalid_field", "acuity must be a table name or a dict (acuity.json)",
                     "acuity")



def _error_doc(resp: Any) -> Any:
    """The body of an error answer: its JSON, or the first 200 bytes of a body that is not."""
    try:
        return resp.json()
    except AalabError:
        return resp.body[:200]

class Client:
    """A client of the aalab daemon over its Unix socket.

    Args:
        socket: the daemon's socket; None finds it as the ``aalab`` command does:
            ``$AALAB_SOCKET``, else ``$XDG_RUNTIME_DIR/aalab/aalabd.sock`` if a socket is
            there, else ``/tmp/aalab-UID/aalabd.sock`` (only without ``$XDG_RUNTIME_DIR`` and
            in a directory you own), else ``/run/aalab/aalabd.sock``.
        timeout: seconds to wait for a connection and for each answer (renders of large tiles
            take longest).
        validate: check every answer against its JSON Schema (``proto/schemas``; needs
            ``jsonschema``); a mismatch raises :class:`AalabError` code ``protocol``.
        retries: how often an answer 429/503 with ``Retry-After`` (per-user limits of
            evaluate and render, a full queue) is retried after the time it asks.

    Creating a client does not connect; nothing is shared between clients. Every method raises
    :class:`AalabError` with the daemon's code, message and field when the daemon refuses
    (:class:`aalab.DaemonUnreachable` when nothing answers).
    """

    def __init__(self, socket: Optional[Union[str, "os.PathLike[str]"]] = None,
                 timeout: float = 60.0, validate: bool = False, retries: int = 3) -> None:
        self._transport = Transport(os.fspath(socket) if socket is not None else None,
                                    timeout, retries)
        self.validate = bool(validate)

    @property
    def socket(self) -> str:
        """The socket path this client talks to."""
        return self._transport.socket_path

    def __repr__(self) -> str:
        return "aalab.Client(socket=%r)" % self.socket

    # -- plumbing -----------------------------------------------------------------------------

    def _call(self, method: str, path: str, body: Any = None, schema: Optional[str] = None,
              expect: Sequence[int] = (200,), timeout: Optional[float] = None) -> Any:
        resp = self._transport.request(method, path, body, timeout)
        if resp.status not in expect:
            doc = _error_doc(resp)
            if self.validate and isinstance(doc, dict) and "error" in doc:
                _schemas.default().validate("error.json", doc)
            raise AalabError.from_body(resp.status, doc)
        doc = resp.json()
        if self.validate and schema:
            _schemas.default().validate(schema, doc)
        return doc

    def _get_job(self, job_id: int) -> Dict[str, Any]:
        return self._call("GET", "/v1/jobs/%d" % job_id, schema="job.json")

    # -- catalogue ----------------------------------------------------------------------------

    def health(self) -> Dict[str, Any]:
        """``GET /v1/health``: version, uptime, workers, queue, jobs by state, job kinds."""
        return self._call("GET", "/v1/health", schema="health_response.json")

    def kinds(self) -> List[Dict[str, Any]]:
        """``GET /v1/kinds``: every job kind with its spec and result schemas and examples."""
        return self._call("GET", "/v1/kinds", schema="kinds_response.json")["kinds"]

    def presets(self) -> List[Dict[str, Any]]:
        """The built-in patterns: name, family, cost_spp (samples per pixel), source, note,
        published_e2 (E2 the papers report, None if none)."""
        return self._call("GET", "/v1/presets", schema="presets_response.json")["presets"]

    def preset(self, name: str) -> Dict[str, Any]:
        """One preset with its wire ``pattern`` and its ``e2`` and ``argmax`` with the default
        filter and acuity."""
        return self._call("GET", "/v1/presets/" + quote_segment(name),
                          schema="preset_response.json")

    def filters(self) -> List[Dict[str, Any]]:
        """The reference filters with their default parameters (``default`` marks the one used
        when none is given: Mitchell-Netravali B = C = 1/3)."""
        return self._call("GET", "/v1/filters", schema="filters_response.json")["filters"]

    def acuity_tables(self) -> List[Dict[str, Any]]:
        """The acuity tables: name, ``knots`` as [angle in degrees, weight W] pairs,
        ``folded`` (angles folded into [0, 45]), ``default_angles`` in degrees, ``default``."""
        return self._call("GET", "/v1/acuity", schema="acuity_response.json")["tables"]

    def usage(self) -> Dict[str, Any]:
        """``GET /v1/usage``: your store bytes, limit and job count."""
        return self._call("GET", "/v1/usage", schema="usage_response.json")

    # -- evaluation ---------------------------------------------------------------------------

    def evaluate(self, pattern: Any, filter: Any = None, acuity: Any = None,
                 angles: Optional[Iterable[float]] = None, detail: bool = False,
                 lp: Optional[float] = None) -> Union[Evaluation, TemporalEvaluation]:
        """E2 of a pattern (``POST /v1/evaluate``).

        A temporal pattern (``{"temporal": ...}``, :func:`aalab.temporal.temporal`) answers a
        :class:`~aalab.temporal.TemporalEvaluation` (per phase E2, F2, the after-cut curve);
        ``detail`` and ``lp`` do not apply to it.

        Args:
            pattern: a preset name, wire dict, Job, points or file (:mod:`aalab.patterns`);
                points without weights need a choice:
                ``evaluate(aalab.pattern(xy, weights="equal"))`` (or ``"filter"``).
            filter: reference filter, a name (``"mitchell"``) or a dict (``{"name":
                "mitchell", "B": 1/3, "C": 1/3}``); default Mitchell-Netravali B = C = 1/3.
            acuity: acuity table, a name (``"naiman"``, version 2, the default;
                ``"naiman-envelope"``, version 1; ``"uniform"``) or a dict with ``knots``
                ([angle in degrees, weight] pairs).
            angles: edge angles in degrees at which E2 is measured; default the acuity
                table's own set.
            detail: also return W(θ), E1(θ) and W·E1 per kernel and angle
                (:attr:`Evaluation.per_angle`, kernels x angles).
            lp: also compute the L_p norm of W·E1 (p >= 1).
        """
        temporal = is_temporal(pattern)
        if temporal and "temporal" not in pattern:
            pattern = pattern["pattern"]
        body: Dict[str, Any] = {"pattern": dict(pattern) if temporal else as_pattern(pattern)}
        if filter is not None:
            body["filter"] = _filter(filter)
        if acuity is not None:
            body["acuity"] = _acuity(acuity)
        if angles is not None:
            body["angles"] = [float(a) for a in (angles.tolist() if hasattr(angles, "tolist")
                                                 else angles)]
        if lp is not None:
            body["lp"] = float(lp)
        if detail:
            body["detail"] = True
        answer = self._call("POST", "/v1/evaluate", body, schema="evaluate_response.json")
        if "phases" in answer:
            return TemporalEvaluation.from_answer(answer)
        return Evaluation.from_answer(answer)

    def evaluate_temporal(self, preset: Optional[str] = None, jitter: Any = None,
                          alpha: Optional[float] = None, blend: Any = None, resolve: Any = None,
                          frame_pattern: Any = None, jitter_range: Optional[float] = None,
                          cut_frames: Optional[int] = None, filter: Any = None,
                          acuity: Any = None,
                          angles: Optional[Iterable[float]] = None) -> TemporalEvaluation:
        """E2 of a TAA jitter sequence under a blend (docs/temporal.md): the arguments of
        :func:`aalab.temporal.temporal`, then ``filter``, ``acuity`` and ``angles`` as for
        :meth:`evaluate`. ``evaluate_temporal("halton23-8", alpha=0.05)``."""
        t = _temporal(preset, jitter, alpha, blend, resolve, frame_pattern, jitter_range,
                      cut_frames)
        result = self.evaluate(t, filter=filter, acuity=acuity, angles=angles)
        assert isinstance(result, TemporalEvaluation)
        return result

    def analyze(self, pattern: Any, metrics: Optional[Iterable[str]] = None,
                radius: Optional[int] = None, pcf_bins: Optional[int] = None,
                pcf_r_max: Optional[float] = None, pcf_sigma: Optional[float] = None,
                set: Optional[Union[int, str]] = None) -> Analysis:
        """Point-set analysis of a pattern's tile on the unit torus (``POST /v1/analyze``,
        docs/analysis.md): discrepancies (CD, WD, MD, L2-star as roots with their squares,
        the exact L∞ star discrepancy), spacing against PSA's packing distance, the
        periodogram with its radial average, anisotropy, effective Nyquist frequency and
        oscillation, and the pair correlation function.

        Args:
            pattern: any pattern argument, as for :meth:`evaluate` (a point set of n >= 2).
            metrics: a subset of ``discrepancy``, ``star_discrepancy``, ``spacing``,
                ``spectrum``, ``pcf``; default all.
            radius: the periodogram's largest integer frequency (1..128, default 32).
            pcf_bins, pcf_r_max, pcf_sigma: the pair correlation's bins (default 64), largest
                distance (default 4 packing distances, at most 0.5) and kernel width (default
                the packing distance / 8).
            set: one set of a point file holding several (``#``-separated utk/xyw text, UTK
                .bin), or ``"all"``: every set (of one size), the figures averaged as pbrt's
                ``pspec`` does (the spectrum of the mean periodogram); each set's own figures
                are in ``raw["sets"]["per_set"]``.
        """
        body: Dict[str, Any] = {"pattern": as_pattern(pattern, set=set)}
        if metrics is not None:
            body["metrics"] = list(metrics)
        if radius is not None:
            body["spectrum"] = {"radius": int(radius)}
        pcf = {k: v for k, v in (("bins", pcf_bins), ("r_max", pcf_r_max),
                                  ("sigma", pcf_sigma)) if v is not None}
        if pcf:
            body["pcf"] = pcf
        return Analysis.from_answer(self._call("POST", "/v1/analyze", body,
                                               schema="analyze_response.json"))

    def enumerate_family(self, family: str, cost: Optional[float] = None) -> Enumeration:
        """Placement configurations of the mirrored family P(4,1+,n) at cost n samples per
        pixel (a multiple of 0.25): ``enumerate_family("P(4,1+,n)", 1.25)`` or
        ``enumerate_family("P(4,1+,1.25)")``."""
        body: Dict[str, Any] = {"family": family}
        if cost is not None:
            body["cost"] = float(cost)
        d = self._call("POST", "/v1/families/enumerate", body, schema="enumerate_response.json")
        return Enumeration(d["family"], d["cost"], d["configurations"], d["index"], d)

    # -- jobs ---------------------------------------------------------------------------------

    def submit(self, spec: Dict[str, Any]) -> Job:
        """Submits a job of any kind (``POST /v1/jobs``): ``spec`` is the whole body,
        ``{"kind": ..., ...}`` (docs/api.md, Job kinds; :meth:`kinds`). A ``"pattern"`` entry
        may be any pattern argument. Returns the queued :class:`Job`."""
        if not isinstance(spec, dict) or "kind" not in spec:
            raise AalabError("invalid_field", "a job spec is a dict with a \"kind\"", "kind")
        body = dict(spec)
        if "pattern" in body and not isinstance(body["pattern"], str):
            body["pattern"] = as_pattern(body["pattern"])
        if "patterns" in body:  # compare: preset names stay names
            body["patterns"] = [p if isinstance(p, str) else as_pattern(p)
                                for p in body["patterns"]]
        d = self._call("POST", "/v1/jobs", body, schema="job.json", expect=(202,))
        return Job(self, d["id"], summary=d)

    def optimize(self, family: Optional[str] = None, pattern: Any = None,
                 **options: Any) -> Job:
        """Submits an ``optimize`` job: multi-start descent minimising E2 for a ``family``
        (``"P(4,1+,2)"``, ``"P(16,16,4)"``) or from one ``pattern``.

        Options are the spec's fields (docs/api.md, optimize): ``seeds``, ``mode``
        (``weights``/``positions``/``both``), ``max_seconds`` (seconds of the job's own
        clock), ``max_iterations`` (steps per seed; without max_seconds the result is
        reproducible to the last bit), ``rng_seed``, ``method``, ``grid``, ``distributions``,
        ``filter``, ``acuity``, ``angles`` (degrees), ``objective`` (optimise for a scene:
        ``{"scene": name or {...}, "size": [w, h], "blend": 0..1}``; the result's
        ``scene_objective`` then gives the predicted RMSE on the scene and E2 beside the
        global-E2 optimum's), and the envelope's ``label``, ``priority``, ``visibility``,
        ``pinned``."""
        spec: Dict[str, Any] = {"kind": "optimize"}
        if family is not None:
            spec["family"] = family
        if pattern is not None:
            spec["pattern"] = as_pattern(pattern)
        if "filter" in options:
            options["filter"] = _filter(options["filter"])
        if "acuity" in options:
            options["acuity"] = _acuity(options["acuity"])
        spec.update(options)
        return self.submit(spec)

    def job(self, job_id: int) -> Job:
        """The job with this id (fetched on first use)."""
        return Job(self, int(job_id))

    def jobs(self, state: Optional[str] = None, kind: Optional[str] = None,
             limit: Optional[int] = None) -> List[Job]:
        """Jobs you can see, newest first (``GET /v1/jobs``), optionally only those in
        ``state`` (one of :data:`JOB_STATES`) or of ``kind``, at most ``limit`` (1..500). Each
        :class:`Job` carries its listed summary (family, label, best_e2) in ``.summary``."""
        path = path_with_query("/v1/jobs", {"state": state, "kind": kind, "limit": limit})
        d = self._call("GET", path, schema="jobs_list.json")
        return [Job(self, j["id"], summary=j) for j in d["jobs"]]

    # -- export -------------------------------------------------------------------------------

    def export(self, source: Any, fmt: str = "json",
               path: Optional[Union[str, "os.PathLike[str]"]] = None
               ) -> Union[Dict[str, Any], str, bytes]:
        """A pattern exported in ``fmt``: the best pattern of a job (a :class:`Job` or job id:
        ``GET /v1/patterns/{id}/export``) or any other pattern argument, a preset name, wire
        dict, points or file (``POST /v1/patterns/export``).

        Formats: ``json`` (aalab's pattern JSON), ``utk``, ``xyw``, ``csv`` (point-set text in
        the unit square of the whole tile, with the ``# aalab-pattern`` header line that makes
        a round trip exact: E2 equal to 1e-12 when read back), ``points-json`` (the same as
        ``{"aalab": {...}, "points": [...]}``), ``vulkan``, ``d3d12`` (programmable sample
        positions, or ``representable: false`` with a reason), ``metal`` (MTLSamplePosition
        list), ``bin`` (UTK's binary, the header as a trailer) and ``rps`` (PSA's float32
        points alone). JSON formats return a dict, text formats a str, bin and rps bytes. With
        ``path`` the answer is also written there, byte for byte."""
        job_id = getattr(source, "job_id", None)
        if job_id is None and isinstance(source, int) and not isinstance(source, bool):
            job_id = source
        if job_id is not None:
            resp = self._transport.request(
                "GET", path_with_query("/v1/patterns/%d/export" % int(job_id), {"format": fmt}))
        else:
            resp = self._transport.request("POST", "/v1/patterns/export",
                                           {"pattern": as_pattern(source), "format": fmt})
        if resp.status != 200:
            raise AalabError.from_body(resp.status, _error_doc(resp))
        ctype = resp.headers.get("content-type", "")
        out: Union[Dict[str, Any], str, bytes]
        if ctype.startswith("application/json"):
            out = resp.json()
            if self.validate and job_id is not None and fmt in ("json", "vulkan", "d3d12",
                                                                "metal"):
                _schemas.default().validate("export_response.json", out)
        elif ctype.startswith("application/octet-stream"):
            out = bytes(resp.body)  # bin, rps
        else:
            out = resp.body.decode("utf-8")
        if path is not None:
            with open(path, "wb") as f:
                f.write(resp.body)
        return out

    # -- rendering ----------------------------------------------------------------------------

    def render(self, pattern: Any, scene: Any = "siemens-star",
               size: Optional[Union[int, Tuple[int, int]]] = None, reference: Any = None,
               crop: Optional[Dict[str, Any]] = None, acuity: Any = None,
               visibility: Optional[str] = None, decode: bool = True) -> Render:
        """Renders one test tile with the pattern beside a supersampled reference
        (``POST /v1/render``) and fetches the three images.

        Args:
            pattern: any pattern argument (:mod:`aalab.patterns`).
            scene: a scene name (``siemens-star``, ``checkerboard``, ``rings``, ``sliver``,
                ``spiral``, ``half-plane``, ...) or a scene dict (width, height in pixels,
                zoom, angle in degrees, ...; docs/api.md, Rendering).
            size: ``(width, height)`` in pixels, or one number for a square (default 256²;
                at most ``--render-max-pixels``, 512², per request).
            reference: supersamples per pixel of the reference (a square: 16, 64, 256, 1024,
                4096) or a reference dict (spp, seed, filter).
            crop: ``{"x", "y", "width", "height", "scale"}``: magnified crops as well.
            acuity: acuity table for the pattern's E2.
            visibility: ``team`` (default) or ``private`` tiles.
            decode: fetch the PNG tiles and decode them into arrays (:class:`Render`).
        """
        sc: Dict[str, Any] = dict(scene) if isinstance(scene, dict) else {"name": scene}
        if size is not None:
            w, h = (size, size) if isinstance(size, int) else size
            sc["width"], sc["height"] = int(w), int(h)
        body: Dict[str, Any] = {"pattern": as_pattern(pattern), "scene": sc}
        if reference is not None:
            body["reference"] = reference if isinstance(reference, dict) else {"spp": int(reference)}
        if crop is not None:
            body["crop"] = crop
        if acuity is not None:
            body["acuity"] = _acuity(acuity)
        if visibility is not None:
            body["visibility"] = visibility
        d = self._call("POST", "/v1/render", body, schema="render_response.json")
        images: Dict[str, Any] = {}
        if decode:
            tiles = d["tiles"]
            for name in ("pattern", "reference", "difference"):
                images[name] = decode_png(self.tile(tiles[name]["id"]))
            for name, t in (tiles.get("crop") or {}).items():
                if name != "rect":
                    images["crop_" + name] = decode_png(self.tile(t["id"]))
        return Render(d["e2"], d["stats"], d["times"], d["scene"], d["pattern"], images, d)

    def tile(self, tile_id: str) -> bytes:
        """The PNG bytes of a stored tile (``GET /v1/tiles/{id}.png``)."""
        resp = self._transport.request("GET", "/v1/tiles/%s.png" % quote_segment(tile_id))
        if resp.status != 200:
            raise AalabError.from_body(resp.status, resp.json())
        if not resp.body.startswith(b"\x89PNG"):
            raise AalabError("protocol", "tile %s is not a PNG" % tile_id, "", resp.status)
        return resp.body
