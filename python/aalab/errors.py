"""The one exception type of the package."""

from __future__ import annotations

from typing import Any, Mapping, Optional


class AalabError(Exception):
    """An error from the daemon, or a local check that fails the same way.

    Attributes:
        code: the daemon's machine-readable code (``invalid_field``, ``out_of_range``,
            ``not_found``, ``conflict``, ``too_many_requests``, ... — docs/api.md, Errors), or
            for failures found before anything reached the daemon: ``unreachable`` (no daemon
            answers on the socket), ``timeout``, ``protocol`` (an answer that is not the
            daemon's JSON), ``invalid_field`` (a local input check, e.g. a point file).
        message: what went wrong, for people.
        field: JSON path of the offending input (``pattern.kernels[0][1][2]``, ``filter.B``,
            ``pattern.points.text``), ``""`` if none.
        status: the HTTP status of the answer, ``None`` when no answer was involved.
        job: the job id when the error is a failed job's error (``Job.wait``), else ``None``.
    """

    def __init__(self, code: str, message: str, field: str = "", status: Optional[int] = None,
                 job: Optional[int] = None) -> None:
        self.code = code
        self.message = message
        self.field = field or ""
        self.status = status
        self.job = job
        super().__init__(str(self))

    def __str__(self) -> str:
        where = " (field %s)" % self.field if self.field else ""
        head = "HTTP %d %s" % (self.status, self.code) if self.status else self.code
        job = "job %d: " % self.job if self.job is not None else ""
        return "%s%s: %s%s" % (job, head, self.message, where)

    @classmethod
    def from_body(cls, status: int, body: Any) -> "AalabError":
        """From an error document ``{"error": {"code", "message", "field"}}``; anything else
        becomes a ``protocol`` error that quotes the start of the body."""
        err = body.get("error") if isinstance(body, Mapping) else None
        if isinstance(err, Mapping) and isinstance(err.get("code"), str):
            return cls(err["code"], str(err.get("message", "")), str(err.get("field") or ""),
                       status)
        return cls("protocol", "HTTP %d without an error document: %.200r" % (status, body), "",
                   status)


class DaemonUnreachable(AalabError, ConnectionError):
    """No daemon answers on the socket (also a :class:`ConnectionError`)."""
