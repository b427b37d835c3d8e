"""Size limits for part documents and requests (one place, documented).

A document beyond these is refused with :class:`~algrasp.errors.LimitExceededError`
naming the limit, before any expensive work starts.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Limits:
    """Attributes:
        max_document_bytes: largest part file / request body read (bytes).
        max_segments: most segments in one loop (boundary or hole).
        max_total_segments: most segments over boundary and holes together.
        max_holes: most holes.
        max_bezier_degree: highest Bezier degree (root finding stays well conditioned).
        max_abs_coordinate: largest coordinate magnitude, in the part's unit.
    """

    max_document_bytes: int = 8_000_000
    max_segments: int = 20_000
    max_total_segments: int = 40_000
    max_holes: int = 1_000
    max_bezier_degree: int = 20
    max_abs_coordinate: float = 1e9


DEFAULT_LIMITS = Limits()
