"""Free ends joined across small gaps (`algrasp.io.cad.arrange` steps 2 and 4): to the
corner of another outline they stop short of, and to each other."""

from __future__ import annotations

import numpy as np

from algrasp.io.cad.faces import Edge, Union


def snap_to_corners(ends: np.ndarray, allowance: np.ndarray, tight: float, uf: Union, end_of: np.ndarray,
                     seg_of: np.ndarray) -> int:
    """Join each free end to the nearest corner (a point where two or more ends already
    meet) of another entity within its gap allowance: a line stopping 0.001 short of a
    rectangle's corner. `close_gaps` joins free ends only to each other and an end at a
    corner is no interior to split. ``ends`` holds entity i's ends at 2i, 2i + 1; O(pairs)."""
    roots = np.array([uf.find(x) for x in range(len(ends))])
    degree = np.bincount(roots, minlength=len(ends))[roots]
    keep = (degree[end_of] == 1) & (end_of // 2 != seg_of)
    e = np.repeat(end_of[keep], 2)
    k = np.stack([2 * seg_of[keep], 2 * seg_of[keep] + 1], axis=1).ravel()
    dist = np.linalg.norm(ends[e] - ends[k], axis=1)
    ok = (degree[k] >= 2) & (dist > tight) & (dist <= allowance[e])
    done: set[int] = set()
    for _, a, b in sorted(zip(dist[ok].tolist(), e[ok].tolist(), k[ok].tolist())):
        if a not in done:
            done.add(a)
            uf.join(a, b)
    return len(done)


def close_gaps(edges: list[Edge], ends: np.ndarray, allowance: np.ndarray, uf: Union) -> list[str]:
    """Join pairs of free ends (nearest first) whose gap is within both ends' allowance."""
    from scipy.spatial import cKDTree

    count: dict[int, int] = {}
    for e in edges:
        for x in (e.u, e.v):
            count[uf.find(x)] = count.get(uf.find(x), 0) + 1
    free = [x for e in edges for x in (e.u, e.v) if x < len(ends) and count[uf.find(x)] == 1]
    if len(free) < 2:
        return []
    pts = ends[free]
    tree = cKDTree(pts)
    pairs = sorted((float(np.linalg.norm(pts[a] - pts[b])), a, b)
                   for a, b in tree.query_pairs(float(np.max(allowance[free]))))
    done: set[int] = set()
    gaps = []
    for d, a, b in pairs:
        ea, eb = free[a], free[b]
        if a in done or b in done or ea // 2 == eb // 2 or d > min(allowance[ea], allowance[eb]):
            continue
        done |= {a, b}
        uf.join(ea, eb)
        gaps.append(d)
    if not gaps:
        return []
    return [f"{len(gaps)} gap(s) closed between entities that should meet (largest {max(gaps):.3g}, "
            f"judged against the lengths of the chains meeting there)"]
