"""Exact split of a NURBS curve into rational Bezier segments (Boehm knot insertion in
homogeneous coordinates): every knot in the domain is raised to multiplicity p, after
which each non-empty knot span's p + 1 control points are its Bezier control points.

Pure numpy; O(k·n·p) for k inserted knots and n control points.
"""

from __future__ import annotations

import numpy as np

from algrasp.errors import PartDocumentError

FloatArray = np.ndarray


def _insert(U: FloatArray, Q: FloatArray, p: int, u: float, right_end: bool) -> tuple[FloatArray, FloatArray]:
    """Insert knot ``u`` once: knots (m+1,), homogeneous control points (n, 3). The span
    is the one starting at or before u (ending at u for the domain's right end)."""
    k = int(np.searchsorted(U, u, side="left" if right_end else "right")) - 1
    new = np.empty((len(Q) + 1, Q.shape[1]))
    new[: k - p + 1] = Q[: k - p + 1]
    for i in range(k - p + 1, k + 1):
        alpha = (u - U[i]) / (U[i + p] - U[i])
        new[i] = (1.0 - alpha) * Q[i - 1] + alpha * Q[i]
    new[k + 1:] = Q[k:]
    return np.insert(U, k + 1, u), new


def nurbs_to_beziers(degree: int, control: FloatArray, weights: FloatArray, knots: FloatArray,
                     field: str = "spline") -> list[tuple[FloatArray, FloatArray]]:
    """Rational Bezier segments ``(points (p+1, 2), weights (p+1,))`` of a NURBS curve
    of ``degree`` p with ``control`` (n, 2), ``weights`` (n,) and ``knots`` (n+p+1,)."""
    p, n = int(degree), len(control)
    U = np.asarray(knots, float)
    if p < 1 or n < p + 1 or len(U) != n + p + 1 or np.any(np.diff(U) < 0) or np.any(np.asarray(weights) <= 0):
        raise PartDocumentError(field, f"invalid NURBS: degree {p}, {n} control points, {len(U)} knots (need n + p + 1, "
                                "non-decreasing) and positive weights")
    w = np.asarray(weights, float)
    Q = np.column_stack([np.asarray(control, float) * w[:, None], w])
    a, b = U[p], U[n]
    for u in np.unique(U[(a <= U) & (b >= U)]):
        for _ in range(p - int(np.sum(u == U))):
            U, Q = _insert(U, Q, p, float(u), u == b)
    out = []
    for i in range(p, len(U) - p - 1):
        if U[i] < U[i + 1] and a <= U[i] and U[i + 1] <= b:
            H = Q[i - p: i + 1]
            out.append((H[:, :2] / H[:, 2:], H[:, 2].copy()))
    return out
