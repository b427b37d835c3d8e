"""The energy barriers (algrasp/planning/barriers.py) against brute force: the sparse-
table search of every copy and both directions at once equals a plain scan per cell."""

from __future__ import annotations

import numpy as np
import pytest

from algrasp.planning.barriers import _lift, _scan, barriers, first_reaching


def _first(q: np.ndarray, level: float, start: int) -> int:
    return next((j for j in range(max(start, 0), len(q)) if q[j] >= level), len(q))


def _barriers_brute(x: np.ndarray, T: float, vals: np.ndarray, cell_max: np.ndarray, s: float,
                    eps: float) -> tuple[np.ndarray, np.ndarray]:
    """Per copy k and cell i: the first node to the right (left) within one period whose
    value plus (minus) s·θ reaches the cell's maximum plus s·(its end) and 2ε."""
    K, n = vals.shape
    ends = np.append(x[1:], T)
    right, left = np.full(n, -np.inf), np.full(n, np.inf)
    for k in range(K):
        for i in range(n):
            r = np.inf
            for j in range(i + 1, 2 * n):  # node j of the lifted sequence, copy (k + j//n) % K
                th = x[j % n] + (j // n) * T
                if vals[(k + j // n) % K, j % n] + s * th >= cell_max[k, i] + s * ends[i] + 2 * eps:
                    r = th
                    break
            right[i] = max(right[i], r)
            lo = -np.inf
            for j in range(n + i, -1, -1):  # leftward from cell i's start (lifted by one period)
                th = x[j % n] + (j // n) * T
                if vals[(k + j // n) % K, j % n] - s * th >= cell_max[(k + 1) % K, i] - s * (x[i] + T) + 2 * eps:
                    lo = th - T
                    break
            left[i] = min(left[i], lo)
    return right, left


@pytest.mark.parametrize("seed", range(40))
def test_barriers_equal_a_scan_of_every_cell(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n, K = int(rng.integers(1, 25)), int(rng.integers(1, 5))
    x = np.concatenate([[0.0], np.sort(rng.uniform(0.0, 1.0, n - 1))])
    vals = rng.normal(size=(K, n))
    cell_max = vals + rng.uniform(0.0, 0.3, size=(K, n))
    s, eps, T = float(rng.uniform(0.0, 2.0)), float(rng.uniform(0.0, 0.2)), 1.0
    got, want = barriers(x, T, vals, cell_max, s, eps), _barriers_brute(x, T, vals, cell_max, s, eps)
    assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1])


def test_first_reaching_rows_equal_a_scan() -> None:
    rng = np.random.default_rng(1)
    q, level = rng.normal(size=(3, 37)), rng.normal(size=(3, 11)) + 1.0
    start = rng.integers(0, 40, size=(3, 11))
    got = first_reaching(q, level, start)
    assert got.tolist() == [[_first(q[r], level[r, i], start[r, i]) for i in range(11)] for r in range(3)]
    assert first_reaching(q[0], level[0], start[0]).tolist() == got[0].tolist()


@pytest.mark.parametrize("seed", range(4))
def test_both_searches_equal_a_scan(seed: int) -> None:
    """The comparison of everything (small searches) and the sparse table (large ones)."""
    rng = np.random.default_rng(seed)
    r, m, n = 2, int(rng.integers(1, 300)), 17
    q, level = rng.normal(size=(r, m)), rng.normal(size=(r, n)) + 1.0
    start = rng.integers(0, m + 3, size=(r, n))
    want = [[_first(q[i], level[i, j], start[i, j]) for j in range(n)] for i in range(r)]
    assert _scan(q, level, np.arange(m) >= start[:, :, None]).tolist() == want
    assert _lift(q, level, start).tolist() == want
