"""Admission control: cheap work and expensive work wait in different lines.

Interactive requests run on two pools: ``fast`` (analyses, plans without optimisation or
validation) and ``slow`` (optimisation, Drake validation, CAD imports, figures, job
archives), so two expensive requests cannot delay a cheap one. Each pool admits at most
``workers + queue`` requests in flight and each client (API key, or address when there
are no keys) at most ``per_client`` in all; past that the request is refused at once
(503 / 429 with ``Retry-After``) instead of waiting behind work it cannot see.
"""

from __future__ import annotations

import hashlib
import threading
from collections import Counter
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

from algrasp.errors import TooManyRequestsError, UnavailableError


@dataclass
class Gate:
    """In-flight counts of one service: per pool and per client (thread-safe)."""

    capacity: dict[str, int]
    per_client: int
    retry_after_s: float = 2.0
    _pools: Counter[str] = field(default_factory=Counter)
    _clients: Counter[str] = field(default_factory=Counter)
    _lock: threading.Lock = field(default_factory=threading.Lock)

    @contextmanager
    def admit(self, pool: str, client: str) -> Iterator[None]:
        """Hold a place in ``pool`` for ``client`` while the body runs, or refuse."""
        with self._lock:
            if self._clients[client] >= self.per_client:
                raise TooManyRequestsError("client_limit", f"this client already has {self.per_client} requests in "
                                           "flight: wait for one to finish", self.retry_after_s)
            if self._pools[pool] >= self.capacity[pool]:
                raise UnavailableError("queue_full", f"the {pool} queue is full ({self.capacity[pool]} requests in "
                                       "flight): try again shortly", self.retry_after_s)
            self._pools[pool] += 1
            self._clients[client] += 1
        try:
            yield
        finally:
            with self._lock:
                self._pools[pool] -= 1
                self._clients[client] -= 1

    def load(self) -> dict[str, int]:
        """Requests in flight per pool."""
        with self._lock:
            return {p: self._pools[p] for p in self.capacity}


FAST_COST = 4_000
"""Estimated cost (segment-samples, see :func:`estimated_cost`) above which an analysis
or a plain plan goes to the slow pool: a 6,000-piece Bezier part analysed with 3,600
drawing samples must not hold the workers that answer cheap plans."""


def estimated_cost(part: Any, samples: int = 0) -> float:
    """A request's cost before any work, from its size alone: the part's pieces (a
    polygon's vertices, a Bezier's control points, the holes too) times the drawing
    samples per 360 asked for. O(pieces); never raises on a malformed document."""
    def pieces(boundary: Any) -> int:
        if not isinstance(boundary, list):
            return 0
        return sum(len(b["points"]) - 1 if isinstance(b, dict) and isinstance(b.get("points"), list) else 1 for b in boundary)

    if not isinstance(part, dict):
        return 0.0
    n = pieces(part.get("boundary")) + pieces(part.get("polygon"))
    holes = part.get("holes")
    n += sum(pieces(h) for h in holes) if isinstance(holes, list) else 0
    return float(n) * (1.0 + max(0, samples) / 360.0)


def client_id(key: str | None, address: str | None) -> str:
    """Who is asking: a hash of the (checked, normalised) bearer key — never the key
    itself —, else the address (no keys configured: a header cannot make a new client)."""
    if key:
        return key_owner(key)
    return f"addr:{address or 'unknown'}"


def key_owner(key: str) -> str:
    """The owner id of runs and jobs made with ``key`` (a hash: the key is never stored)."""
    return "key:" + hashlib.sha256(key.encode("utf-8", "replace")).hexdigest()[:16]
