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
    """For each i, the first j ≥ start[i] with q[j] ≥ level[i] (len(q) when none).

    Binary lifting on a sparse table of block maxima: blocks wholly below the level are
    skipped, largest first. O(m log m) to build, O(n log m) to query."""
    m = len(q)
    levels = max(1, int(np.ceil(np.log2(max(m, 2)))) + 1)
    table = [np.append(q, -np.inf)]
    for k in range(1, levels):
        prev = table[-1]
        half = 1 << (k - 1)
        shifted = np.append(prev[half:], np.full(half, -np.inf))
        table.append(np.maximum(prev, shifted[: len(prev)]))
    pos = np.minimum(np.asarray(start, dtype=np.intp), m)
    for k in range(levels - 1, -1, -1):
        block = table[k][np.minimum(pos, m)]
        skip = (block < level) & (pos < m)
        pos = np.where(skip, pos + (1 << k), pos)
    return np.minimum(pos, m)


def barriers(x: FloatArray, T: float, node_values: FloatArray, cell_max: FloatArray, stall: float,
             eps: float) -> tuple[FloatArray, FloatArray]:
    """Right and left barriers (lifted θ, radians) of each cell [x_i, x_{i+1}).

    ``node_values`` (K, n): f̂ at every node in each of K copies (θ + kT, natural period
    K·T); ``cell_max`` (K, n): f̂'s maximum over each cell. The barrier of a cell is the
    farthest over the copies (conservative). +∞ / −∞ when none within one period.
    """
    K, n = node_values.shape
    ends = np.append(x[1:], T)
    j = np.arange(2 * n)
    lift = (j // n) * T
    xs = x[j % n] + lift
    right = np.full(n, -np.inf)
    left = np.full(n, np.inf)
    for k in range(K):
        vals = node_values[(k + j // n) % K, j % n]
        # Rightward from cell i (extended index i): first node j > i reaching the level.
        q = vals + stall * xs
        jr = first_reaching(q, cell_max[k] + stall * ends + 2.0 * eps, np.arange(1, n + 1))
        right = np.maximum(right, np.where(jr < 2 * n, xs[np.minimum(jr, 2 * n - 1)], np.inf))
        # Leftward: mirror the sequence (cell i's start is extended index n + i, lifted by −T).
        qm = (vals - stall * xs)[::-1]
        start = (2 * n - 1) - (n + np.arange(n))
        jl = first_reaching(qm, cell_max[(k + 1) % K] - stall * (x + T) + 2.0 * eps, start)
        left = np.minimum(left, np.where(jl < 2 * n, xs[(2 * n - 1) - np.minimum(jl, 2 * n - 1)] - T, -np.inf))
    return right, left
