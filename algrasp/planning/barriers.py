"""Where a part cannot get past: the energy bound of conventions §7's dead band.

A squeeze (push) only ever lowers the real f (d or r), and the real part moves only
where its slope beats the stall threshold s, so moving from θ0 to θ lowers it by more
than s·|θ − θ0|. The real f is within ε (the drawing's value error) of the drawn f̂, so
the part never reaches a θ with

    f̂(θ) + s·|θ − θ0| ≥ f̂(θ0) + 2ε.

That is the first such node on each side of a cell: the *barriers*. They bound how far
a part drifts through a long region of uncertain slope (a tessellated arc whose facets'
slopes are all within σ), which slope rules alone cannot. With ε = 0 the barrier is
never before the slope rules' own stop. Vectorised range-maximum search, O(n log n).
"""

from __future__ import annotations

import numpy as np

from algrasp.geometry.curves import FloatArray

IntArray = np.ndarray


def first_reaching(q: FloatArray, level: FloatArray, start: IntArray) -> IntArray:
    """For each i, the first j ≥ start[i] with q[j] ≥ level[i] (len(q) when none); with
    ``q`` (r, m) and ``level``, ``start`` (r, n) (``start`` may be (n,)), row by row.

    Binary lifting on a sparse table of block maxima: blocks wholly below the level are
    skipped, largest first. O(r·m log m) to build (one preallocated table, every row at
    once), O(r·n log m) to query."""
    q2 = np.atleast_2d(np.asarray(q, dtype=float))
    lv = np.atleast_2d(np.asarray(level, dtype=float))
    st = np.broadcast_to(np.atleast_2d(np.asarray(start, dtype=np.intp)), lv.shape)
    r, m = q2.shape
    levels = max(1, int(np.ceil(np.log2(max(m, 2)))) + 1)
    table = np.full((levels, r, m + 1), -np.inf)
    table[0, :, :m] = q2
    for k in range(1, levels):
        half, prev, cur = 1 << (k - 1), table[k - 1], table[k]
        cur[...] = prev
        if half < m + 1:
            np.maximum(prev[:, : m + 1 - half], prev[:, half:], out=cur[:, : m + 1 - half])
    pos = np.minimum(st, m)
    rows = np.arange(r)[:, None]
    for k in range(levels - 1, -1, -1):
        block = table[k][rows, np.minimum(pos, m)]
        skip = (block < lv) & (pos < m)
        pos = np.where(skip, pos + (1 << k), pos)
    out: IntArray = np.minimum(pos, m).reshape(np.shape(level))
    return out


def barriers(x: FloatArray, T: float, node_values: FloatArray, cell_max: FloatArray, stall: float,
             eps: float) -> tuple[FloatArray, FloatArray]:
    """Right and left barriers (lifted θ, radians) of each cell [x_i, x_{i+1}).

    ``node_values`` (K, n): f̂ at every node in each of K copies (θ + kT, natural period
    K·T); ``cell_max`` (K, n): f̂'s maximum over each cell. The barrier of a cell is the
    farthest over the copies (conservative). +∞ / −∞ when none within one period. Every
    copy and both directions in one :func:`first_reaching` of 2K rows.
    """
    K, n = node_values.shape
    ends = np.append(x[1:], T)
    j = np.arange(2 * n)
    lift = (j // n) * T
    xs = x[j % n] + lift
    ks = np.arange(K)[:, None]
    vals = node_values[(ks + j // n) % K, j % n]  # (K, 2n): copy k's nodes over two periods
    # Rightward from cell i (extended index i): first node j > i reaching the level.
    # Leftward: mirror the sequence (cell i's start is extended index n + i, lifted by −T).
    q = np.concatenate([vals + stall * xs, (vals - stall * xs)[:, ::-1]])
    level = np.concatenate([cell_max + stall * ends + 2.0 * eps, cell_max[(np.arange(K) + 1) % K] - stall * (x + T) + 2.0 * eps])
    start = np.concatenate([np.broadcast_to(np.arange(1, n + 1), (K, n)),
                            np.broadcast_to((2 * n - 1) - (n + np.arange(n)), (K, n))])
    found = first_reaching(q, level, start)
    jr, jl = found[:K], found[K:]
    right = np.max(np.where(jr < 2 * n, xs[np.minimum(jr, 2 * n - 1)], np.inf), axis=0)
    left = np.min(np.where(jl < 2 * n, xs[(2 * n - 1) - np.minimum(jl, 2 * n - 1)] - T, -np.inf), axis=0)
    return right, left
