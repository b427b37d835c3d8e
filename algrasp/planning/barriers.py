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

The shallow basins belong to the same bound: a drawn minimum less than 2ε deep may be
no minimum of the real f (:func:`shallow_basins`).
"""

from __future__ import annotations

import functools

import numpy as np

from algrasp.geometry.curves import FloatArray

IntArray = np.ndarray
SCAN_SIZE = 1 << 16
"""Largest r·n·m a :func:`first_reaching` answers by one comparison of every level with
every value (a few array passes, where the sparse table's ~4 log m small passes each
cost more than the arithmetic; the answers are the same indices)."""


def first_reaching(q: FloatArray, level: FloatArray, start: IntArray) -> IntArray:
    """For each i, the first j ≥ start[i] with q[j] ≥ level[i] (len(q) when none); with
    ``q`` (r, m) and ``level``, ``start`` (r, n) (``start`` may be (n,)), row by row.

    Small searches (r·n·m ≤ ``SCAN_SIZE``) compare everything at once, O(r·n·m); larger
    ones use binary lifting on a sparse table of block maxima: blocks wholly below the
    level are skipped, largest first. O(r·m log m) to build (one preallocated table,
    every row at once), O(r·n log m) to query."""
    q2 = np.atleast_2d(np.asarray(q, dtype=float))
    lv = np.atleast_2d(np.asarray(level, dtype=float))
    st = np.atleast_2d(np.asarray(start, dtype=np.intp))
    st = st if st.shape == lv.shape else np.broadcast_to(st, lv.shape)
    r, m = q2.shape
    out = _scan(q2, lv, np.arange(m) >= st[:, :, None]) if r * lv.shape[1] * m <= SCAN_SIZE else _lift(q2, lv, st)
    return out.reshape(np.shape(level))


def _scan(q: FloatArray, level: FloatArray, past_start: np.ndarray) -> IntArray:
    """:func:`first_reaching` by comparing every level with every value: ``q`` (r, m)
    against ``level`` (..., r, n) (leading axes: several level sets against the same
    rows, no copies of them), ``past_start`` (r, n, m) whether each value is at or past
    each search's start. (..., r, n) indices, m where none reaches: (…, m + 1) flags, the
    last column a sentinel that always reaches."""
    m = q.shape[1]
    hit = np.empty((*level.shape, m + 1), dtype=bool)
    np.greater_equal(q[:, None, :], level[..., None], out=hit[..., :m])
    hit[..., :m] &= past_start
    hit[..., m] = True
    return np.asarray(hit.argmax(axis=-1))


def _lift(q: FloatArray, level: FloatArray, start: IntArray) -> IntArray:
    """:func:`first_reaching` by binary lifting on a sparse table (row k: maxima of blocks
    of 2^k from each index, −∞ past the end), read through flat indices: four array
    passes per level, every position kept at most m (past the end: none found)."""
    r, m = q.shape
    w = m + 1
    levels = max(1, int(np.ceil(np.log2(max(m, 2)))) + 1)
    table = np.empty((levels, r, w))
    table[0, :, :m], table[0, :, m] = q, -np.inf
    for k in range(1, levels):
        half, prev, cur = 1 << (k - 1), table[k - 1], table[k]
        if half < w:
            np.maximum(prev[:, : w - half], prev[:, half:], out=cur[:, : w - half])
            cur[:, w - half:] = prev[:, w - half:]
        else:
            cur[...] = prev
    flat = table.reshape(levels, -1)
    base = (np.arange(r) * w)[:, None]
    pos = np.minimum(start, m) + base  # flat index of each search's position
    end = base + m
    below = np.empty(pos.shape, dtype=bool)
    for k in range(levels - 1, -1, -1):
        np.less(flat[k].take(pos), level, out=below)  # the block of 2^k from pos stays below
        np.add(pos, 1 << k, out=pos, where=below)
        np.minimum(pos, end, out=pos)
    return np.asarray(pos - base)


def barriers(x: FloatArray, T: float, node_values: FloatArray, cell_max: FloatArray, stall: float,
             eps: float) -> tuple[FloatArray, FloatArray]:
    """Right and left barriers (lifted θ, radians) of each cell [x_i, x_{i+1}).

    ``node_values`` (K, n): f̂ at every node in each of K copies (θ + kT, natural period
    K·T); ``cell_max`` (K, n): f̂'s maximum over each cell. The barrier of a cell is the
    farthest over the copies (conservative). +∞ / −∞ when none within one period. Every
    copy and both directions in one :func:`first_reaching` of 2K rows.
    """
    return barrier_sets(x, T, node_values, (cell_max,), stall, eps)[0]


def barrier_sets(x: FloatArray, T: float, node_values: FloatArray, cell_levels: tuple[FloatArray, ...],
                 stall: float, eps: float) -> list[tuple[FloatArray, FloatArray]]:
    """:func:`barriers` for each of several cell values (``cell_levels``, each (K, n) like
    ``cell_max``) over the same nodes, in one :func:`first_reaching` of 2K rows each."""
    K, n = node_values.shape
    L = len(cell_levels)
    ends = np.empty(n)
    ends[:-1], ends[-1] = x[1:], T
    # The nodes over two periods, lifted, then +∞: index 2n (none found) reads it.
    right_at = np.empty(2 * n + 1)
    np.add(x, 0.0, out=right_at[:n])
    np.add(x, T, out=right_at[n:2 * n])
    right_at[2 * n] = np.inf
    xs = right_at[:2 * n]
    if K == 1:
        vals, moved = np.concatenate([node_values, node_values], axis=1), cell_levels
    else:  # copy k's next copy (leftward searches compare with its cells)
        shifted = (np.arange(K) + 1) % K
        vals, moved = np.concatenate([node_values, node_values[shifted]], axis=1), tuple(c[shifted] for c in cell_levels)
    # Rightward from cell i (extended index i): first node j > i reaching the level.
    # Leftward: mirror the sequence (cell i's start is extended index n + i, lifted by −T).
    sx = stall * xs
    rows = np.concatenate([vals + sx, (vals - sx)[:, ::-1]])
    up, down, e2 = stall * ends, stall * xs[n:], 2.0 * eps
    level = np.concatenate([lv for c, d in zip(cell_levels, moved) for lv in (c + up + e2, d - down + e2)])
    m = 2 * n
    if L * rows.shape[0] * n * m <= SCAN_SIZE:  # first_reaching's own choice, without its argument checks
        found = _scan(rows, level.reshape(L, 2 * K, n), _past_start(n, K))
    else:
        start = np.empty((L, 2, K, n), dtype=np.intp)
        start[:, 0], start[:, 1] = np.arange(1, n + 1), np.arange(n - 1, -1, -1)
        found = _lift(rows if L == 1 else np.concatenate([rows] * L), level, start.reshape(-1, n))
    return _farthest(found.reshape(L, 2, K, n), right_at, T)


@functools.lru_cache(maxsize=64)
def _past_start(n: int, K: int) -> np.ndarray:
    """(2K, n, 2n) read-only: whether node j is at or past the start of cell i's search,
    K rightward rows (start i + 1) then K mirrored leftward rows (start n − 1 − i)."""
    j = np.arange(2 * n)
    right = j >= np.arange(1, n + 1)[:, None]
    left = j >= np.arange(n - 1, -1, -1)[:, None]
    out = np.concatenate([np.broadcast_to(right, (K, n, 2 * n)), np.broadcast_to(left, (K, n, 2 * n))])
    out.setflags(write=False)
    return out


def _farthest(found: IntArray, right_at: FloatArray, T: float) -> list[tuple[FloatArray, FloatArray]]:
    """The right and left barriers of each level from :func:`first_reaching` rows (L, 2, K, n)
    (per level K rightward, then K leftward, over the 2n lifted nodes, ``right_at`` with +∞
    after them): the farthest over the copies. Index 2n (none found) reads ±∞ from the
    slot past each table."""
    m = len(right_at) - 1
    left_at = np.empty(m + 1)
    np.subtract(right_at[m - 1::-1], T, out=left_at[:m])  # mirrored index j is node m − 1 − j
    left_at[m] = -np.inf
    right, left = right_at[found[:, 0]], left_at[found[:, 1]]
    if found.shape[2] == 1:
        return [(r[0], lf[0]) for r, lf in zip(right, left)]
    return list(zip(np.max(right, axis=1), np.min(left, axis=1)))


def shallow_basins(values: FloatArray, depth: float) -> np.ndarray:
    """Cells (cyclic sequence of f at cell starts) of a basin whose minimum lies less than
    ``depth`` below the lower of its two bounding maxima, up to that rim: the real f
    (within depth/2 of the drawn one) may have no minimum there. O(m).

    >>> shallow_basins(np.array([5, 4, 3, 2.9, 2.95, 2, 1, 2, 3, 4.0]), 0.1).astype(int).tolist()
    [0, 0, 0, 1, 1, 0, 0, 0, 0, 0]
    """
    return basin_cells(values, basins(values, depth))


def basin_cells(values: FloatArray, found: list[tuple[np.ndarray, float]]) -> np.ndarray:
    """:func:`shallow_basins` from the basins :func:`basins` found."""
    out = np.zeros(len(values), dtype=bool)
    for span, rim in found:
        out[span[values[span] <= rim]] = True  # the basin below its lower rim
    return out


def basin_rims(values: FloatArray, depth: float) -> list[float]:
    """The rim (the lower bounding maximum) of every shallow basin of :func:`shallow_basins`.

    >>> basin_rims(np.array([5, 4, 3, 2.9, 2.95, 2, 1, 2, 3, 4.0]), 0.1)
    [2.95]
    """
    return [rim for _, rim in basins(values, depth)]


def basins(values: FloatArray, depth: float) -> list[tuple[np.ndarray, float]]:
    """(cells from maximum to maximum, rim) of each basin shallower than ``depth``."""
    if depth <= 0.0:
        return []
    m = len(values)
    step = np.sign(np.concatenate([values[1:], values[:1]]) - values)
    nz = np.nonzero(step)[0]
    if len(nz) < 2:
        return []
    s = step[nz]
    turn = s != np.concatenate([s[-1:], s[:-1]])  # the sign changes at nz[k]: an extremum at its start index
    idx, kinds = nz[turn], s[turn]  # kinds +1: a minimum (f rises after it), −1: a maximum
    if len(idx) < 2:
        return []
    out = []
    at, f = idx.tolist(), values[idx].tolist()  # scalar work on floats: few extrema
    for k in np.nonzero(kinds > 0)[0].tolist():
        lo, hi = k - 1, (k + 1) % len(at)  # the maxima around minimum at[k]
        rim = min(f[lo], f[hi])
        if rim - f[k] < depth:
            out.append((np.arange(at[lo], at[hi] + (m if at[hi] < at[lo] else 0) + 1) % m, rim))
    return out
