"""The one error hierarchy of algrasp.

Every error a user can cause derives from :class:`AlgraspError`; the CLI and the
service map these (and only these) to clean messages and exit codes / HTTP statuses.
Each subclass carries typed fields so callers never parse messages.
"""

from __future__ import annotations


class AlgraspError(Exception):
    """Base class of every error algrasp raises on purpose."""

    kind = "algrasp_error"

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.message = message

    def to_dict(self) -> dict[str, object]:
        """JSON-ready ``{"type": .., "message": ..}`` (plus subclass fields)."""
        return {"type": self.kind, "message": self.message}


class PartDocumentError(AlgraspError):
    """The part document is malformed or describes an invalid part.

    ``field`` is a JSON-path-like location (``boundary[3].radius``); ``segment_index``
    is the index of the offending segment when there is one.
    """

    kind = "part_document_error"

    def __init__(self, field: str, problem: str, segment_index: int | None = None) -> None:
        super().__init__(f"{field}: {problem}")
        self.field = field
        self.problem = problem
        self.segment_index = segment_index

    def to_dict(self) -> dict[str, object]:
        out = super().to_dict()
        out["field"] = self.field
        if self.segment_index is not None:
            out["segment_index"] = self.segment_index
        return out


class LimitExceededError(PartDocumentError):
    """A document or request exceeds a configured size limit."""

    kind = "limit_exceeded"


class GeometryError(AlgraspError):
    """The exact geometry could not be computed to the required accuracy."""

    kind = "geometry_error"


class NotOrientableError(AlgraspError):
    """No plan of the requested kind can orient the part (``reason`` says why)."""

    kind = "not_orientable"

    def __init__(self, reason: str, message: str) -> None:
        super().__init__(message)
        self.reason = reason

    def to_dict(self) -> dict[str, object]:
        out = super().to_dict()
        out["reason"] = self.reason
        return out


class ConfigError(AlgraspError):
    """A configuration or request option is invalid (``field`` names it)."""

    kind = "config_error"

    def __init__(self, field: str, problem: str) -> None:
        super().__init__(f"{field}: {problem}")
        self.field = field
        self.problem = problem

    def to_dict(self) -> dict[str, object]:
        out = super().to_dict()
        out["field"] = self.field
        return out
