"""The one error hierarchy of algrasp.

Every error a user can cause derives from :class:`AlgraspError`; the CLI and the
service map these (and only these) to clean messages and exit codes / HTTP statuses.
Each subclass carries typed fields so callers never parse messages; ``to_dict()`` is the
error document (``{"type": kind, "message": ..., **fields}``) the service answers with.
"""

from __future__ import annotations

from collections.abc import Callable


class AlgraspError(Exception):
    """Base class of every error algrasp raises on purpose.

    Attributes
    ----------
    message : str
        What went wrong, for a person (also ``str(err)``).
    kind : str
        The error document's ``type``.
    http_status : int
        The HTTP status of this error: 422 (the request's fault) unless a subclass says otherwise.
    exit_code : int
        The CLI's exit status for this error: 2 unless a subclass says otherwise.
    public_fields : tuple of str
        Typed fields a subclass reports in :meth:`to_dict` (those that are not None).

    Examples
    --------
    >>> err = AlgraspError("it went wrong")
    >>> err.to_dict(), err.http_status, err.exit_code
    ({'type': 'algrasp_error', 'message': 'it went wrong'}, 422, 2)
    """

    kind = "algrasp_error"
    http_status = 422
    exit_code = 2
    public_fields: tuple[str, ...] = ()

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

    Attributes
    ----------
    field : str
        A JSON-path-like location (``boundary[3].radius``).
    problem : str
        What is wrong there (the message is ``"field: problem"``).
    segment_index : int or None
        The index of the offending segment when there is one.
    http_status, exit_code : int
        422 and 2.

    Examples
    --------
    >>> err = PartDocumentError("boundary[3].radius", "must be positive", 3)
    >>> str(err), err.segment_index, sorted(err.to_dict())
    ('boundary[3].radius: must be positive', 3, ['field', 'message', 'segment_index', 'type'])
    """

    kind = "part_document_error"
    public_fields = ("field", "segment_index")

    def __init__(self, field: str, problem: str, segment_index: int | None = None) -> None:
        super().__init__(f"{field}: {problem}")
        self.field = field
        self.problem = problem
        self.segment_index = segment_index


class LimitExceededError(PartDocumentError):
    """A document or request exceeds a configured size limit.

    Attributes
    ----------
    field, problem, segment_index
        As :class:`PartDocumentError`.
    http_status, exit_code : int
        422 and 2.

    Examples
    --------
    >>> err = LimitExceededError("boundary", "more than 100000 segments")
    >>> err.to_dict()["type"], isinstance(err, PartDocumentError)
    ('limit_exceeded', True)
    """

    kind = "limit_exceeded"


class GeometryError(AlgraspError):
    """The exact geometry could not be computed to the required accuracy.

    Attributes
    ----------
    message : str
        Which computation failed.
    http_status, exit_code : int
        422 and 2.

    Examples
    --------
    >>> GeometryError("the hull did not close").to_dict()
    {'type': 'geometry_error', 'message': 'the hull did not close'}
    """

    kind = "geometry_error"


class NotOrientableError(AlgraspError):
    """No plan of the requested kind can orient the part (``reason`` says why).

    Attributes
    ----------
    reason : str
        Why, as a word: ``constant_width``, ``no_step``, ``dead_band``, ``margin_too_large``,
        ``uncertain``, ``verification_failed``, ``no_fence_design`` (conveyor fences).
    limits : dict or None
        The physics limits under which a plan exists (``algrasp.planning.limits``), if searched;
        for fences ``fence_friction_max``, the friction under which a design exists. A
        planner may leave the search pending (``search``: a function giving the message
        with the limits, and the limits): it runs when ``limits``, ``message``, ``str``,
        ``to_dict`` or pickling first needs it, so a caller that only catches the refusal
        does not pay for it.
    search : callable or None
        The pending search, ``() -> (message, limits)``; None once run (or when none).
    http_status, exit_code : int
        422 and 2.

    Examples
    --------
    >>> err = NotOrientableError("constant_width", "the part has constant width")
    >>> err.reason, err.limits, err.to_dict()["type"]
    ('constant_width', None, 'not_orientable')
    """

    kind = "not_orientable"
    public_fields = ("reason", "limits")

    def __init__(self, reason: str, message: str, limits: dict[str, object] | None = None,
                 search: Callable[[], tuple[str, dict[str, object]]] | None = None) -> None:
        self._search = search
        super().__init__(message)
        self.reason = reason
        self._limits = limits

    @property
    def message(self) -> str:
        """What went wrong; with a pending limit search, the sentence naming the limits
        (the search runs on first access of ``message``, ``limits``, ``str`` or ``to_dict``)."""
        self._settle()
        return self._message

    @message.setter
    def message(self, value: str) -> None:
        self._message = value

    @property
    def limits(self) -> dict[str, object] | None:
        """The physics limits (searched on first access when the search was left pending)."""
        self._settle()
        return self._limits

    @property
    def limits_pending(self) -> bool:
        """Whether the limit search has not run yet (reading ``limits`` runs it)."""
        return self._search is not None

    def _settle(self) -> None:
        search, self._search = self._search, None
        if search is not None:
            self._message, self._limits = search()

    def __str__(self) -> str:
        return self.message

    def __reduce__(self) -> tuple[object, ...]:
        self._settle()  # the search holds the analysis and planner: run it before crossing a process
        return super().__reduce__()


class ConfigError(AlgraspError):
    """A configuration or request option is invalid (``field`` names it).

    Attributes
    ----------
    field : str
        The option (``min_margin_deg``, ``physics.jaw_friction``).
    problem : str
        What is wrong with it (the message is ``"field: problem"``).
    http_status, exit_code : int
        422 and 2.

    Examples
    --------
    >>> err = ConfigError("samples", "expected a whole number ≥ 1, got 0")
    >>> err.field, str(err)
    ('samples', 'samples: expected a whole number ≥ 1, got 0')
    """

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
    """The physics engine could not simulate the part.

    Attributes
    ----------
    detail : str
        The engine's message; the error's message adds the hint given, if any.
    http_status, exit_code : int
        422 and 2.

    Examples
    --------
    >>> str(SimulationError("contact solver diverged", "try a smaller time step"))
    'the simulation failed: contact solver diverged; try a smaller time step'
    """

    kind = "simulation_error"

    def __init__(self, detail: str, hint: str = "") -> None:
        super().__init__(f"the simulation failed: {detail}{'; ' + hint if hint else ''}")
        self.detail = detail


class TimeLimitError(AlgraspError):
    """A stage of a request ran past its time limit.

    Attributes
    ----------
    stage : str
        The stage (``import``, ``analysis``, ``plan``, …).
    limit_s : float
        Its time limit (seconds).
    http_status, exit_code : int
        422 and 2.

    Examples
    --------
    >>> TimeLimitError("plan", 2.0).to_dict()
    {'type': 'time_limit_exceeded', 'message': 'plan took longer than its 2 s time limit', 'stage': 'plan', 'limit_s': 2.0}
    """

    kind = "time_limit_exceeded"
    public_fields = ("stage", "limit_s")

    def __init__(self, stage: str, limit_s: float) -> None:
        super().__init__(f"{stage} took longer than its {limit_s:g} s time limit")
        self.stage = stage
        self.limit_s = limit_s


class UnavailableError(AlgraspError):
    """The service cannot take or finish the request now (full queues, a lost worker,
    storage faults); the same request may succeed later.

    Attributes
    ----------
    reason : str
        Why, as a word: ``queue_full``, ``no_workers``, ``worker_lost`` (its worker died),
        ``pool_lost`` (lost with a wedged or broken worker pool), ``shutting_down``, ``scheduler``.
    retry_after_s : float
        When to try again (seconds; the HTTP ``Retry-After`` header).
    http_status, exit_code : int
        503 and 3.

    Examples
    --------
    >>> err = UnavailableError("queue_full", "the queue is full", retry_after_s=5.0)
    >>> err.to_dict()["retry_after_s"], err.http_status, err.exit_code
    (5.0, 503, 3)
    """

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
    """The record directory or the database cannot be written (disk full, read-only).

    Attributes
    ----------
    reason : str
        Which: ``records`` or ``database``.
    retry_after_s : float
        When to try again (seconds).
    http_status, exit_code : int
        503 and 3.

    Examples
    --------
    >>> err = StorageError("records", "the record directory is full")
    >>> err.reason, err.to_dict()["type"], err.http_status
    ('records', 'storage_error', 503)
    """

    kind = "storage_error"
