"""The one error hierarchy of algrasp.

Every error a user can cause derives from :class:`AlgraspError`; the CLI and the
service map these (and only these) to clean messages and exit codes / HTTP statuses.
Each subclass carries typed fields so callers never parse messages.
"""

from __future__ import annotations


class AlgraspError(Exception):
    """Base class of every error algrasp raises on purpose."""

    kind = "algrasp_error"
    http_status = 422
    """The HTTP status of this error (the request's fault unless a subclass says otherwise)."""
    exit_code = 2
    """The CLI's exit status for this error."""
    public_fields: tuple[str, ...] = ()
    """Typed fields a subclass reports in :meth:`to_dict` (those that are not None)."""

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.message = message

    def to_dict(self) -> dict[str, object]:
        """JSON-ready ``{"type": .., "message": ..}`` plus :attr:`public_fields`."""
        out: dict[str, object] = {"type": self.kind, "message": self.message}
        out.update({name: getattr(self, name) for name in self.public_fields if getattr(self, name) is not None})
        return out

    def __reduce__(self) -> tuple[object, ...]:
        # Subclasses take typed fields, not the message, so the default pickling
        # (``cls(*args)``) would fail when an error crosses a worker-process boundary.
        return (_rebuild, (type(self), self.message, dict(self.__dict__)))


def _rebuild(cls: type[AlgraspError], message: str, fields: dict[str, object]) -> AlgraspError:
    err = cls.__new__(cls)
    Exception.__init__(err, message)
    err.__dict__.update(fields)
    return err


class PartDocumentError(AlgraspError):
    """The part document is malformed or describes an invalid part.

    ``field`` is a JSON-path-like location (``boundary[3].radius``); ``segment_index``
    is the index of the offending segment when there is one.
    """

    kind = "part_document_error"
    public_fields = ("field", "segment_index")

    def __init__(self, field: str, problem: str, segment_index: int | None = None) -> None:
        super().__init__(f"{field}: {problem}")
        self.field = field
        self.problem = problem
        self.segment_index = segment_index


class LimitExceededError(PartDocumentError):
    """A document or request exceeds a configured size limit."""

    kind = "limit_exceeded"


class GeometryError(AlgraspError):
    """The exact geometry could not be computed to the required accuracy."""

    kind = "geometry_error"


class NotOrientableError(AlgraspError):
    """No plan of the requested kind can orient the part (``reason`` says why)."""

    kind = "not_orientable"
    public_fields = ("reason", "limits")

    def __init__(self, reason: str, message: str, limits: dict[str, object] | None = None) -> None:
        super().__init__(message)
        self.reason = reason
        self.limits = limits
        """The physics limits under which a plan exists (``algrasp.planning.limits``), if searched."""


class ConfigError(AlgraspError):
    """A configuration or request option is invalid (``field`` names it)."""

    kind = "config_error"
    public_fields = ("field",)

    def __init__(self, field: str, problem: str) -> None:
        super().__init__(f"{field}: {problem}")
        self.field = field
        self.problem = problem


class AmbiguousRequestError(ConfigError):
    """A request that can be read two ways — a header given twice — is refused, not
    guessed at (``field``: the header): HTTP 400."""

    kind = "ambiguous_request"
    http_status = 400


class SlowRequestError(AlgraspError):
    """A request body that did not arrive within the server's time for it (``limit_s``):
    HTTP 408, so a client trickling bytes cannot hold a connection."""

    kind = "request_timeout"
    http_status = 408
    public_fields = ("limit_s",)

    def __init__(self, limit_s: float) -> None:
        super().__init__(f"the request body did not arrive within {limit_s:g} s")
        self.limit_s = limit_s


class RecordError(AlgraspError):
    """A run record is missing, damaged or holds no such content (``record``: its file name)."""

    kind = "record_error"
    public_fields = ("record",)

    def __init__(self, record: str, message: str) -> None:
        super().__init__(message)
        self.record = record


class SimulationError(AlgraspError):
    """The physics engine could not simulate the part (``detail``: the engine's message)."""

    kind = "simulation_error"

    def __init__(self, detail: str, hint: str = "") -> None:
        super().__init__(f"the simulation failed: {detail}{'; ' + hint if hint else ''}")
        self.detail = detail


class TimeLimitError(AlgraspError):
    """A stage of a request ran past its time limit (``stage``, ``limit_s``)."""

    kind = "time_limit_exceeded"
    public_fields = ("stage", "limit_s")

    def __init__(self, stage: str, limit_s: float) -> None:
        super().__init__(f"{stage} took longer than its {limit_s:g} s time limit")
        self.stage = stage
        self.limit_s = limit_s


class UnavailableError(AlgraspError):
    """The service cannot take or finish the request now (full queues, a lost worker,
    storage faults); the same request may succeed later (``retry_after_s``)."""

    kind = "unavailable"
    http_status = 503
    exit_code = 3
    public_fields = ("reason", "retry_after_s")

    def __init__(self, reason: str, message: str, retry_after_s: float = 1.0) -> None:
        super().__init__(message)
        self.reason = reason
        self.retry_after_s = retry_after_s


class TooManyRequestsError(UnavailableError):
    """One client holds more requests in flight than its share (``retry_after_s``)."""

    kind = "too_many_requests"
    http_status = 429


class StorageError(UnavailableError):
    """The record directory or the database cannot be written (disk full, read-only):
    ``reason`` names which."""

    kind = "storage_error"
