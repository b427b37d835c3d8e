"""Analysis time (parse + validate + exact hull + d/r extrema + transfer functions).

Targets (issue 2): 1,000-vertex polygon ≤ 20 ms; 50 cubic Bezier segments ≤ 50 ms.
Prints the median of several runs and how time grows with size.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from typing import Any

from algrasp.geometry.part import load_part
from algrasp.planning.analysis import analyse_part
from algrasp.testing import shapes


def median_ms(doc: dict[str, Any], repeats: int = 7) -> float:
    analyse_part(load_part(doc))  # warm caches and imports
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        analyse_part(load_part(doc))
        times.append(time.perf_counter() - t)
    return 1000 * statistics.median(times)


def series(title: str, make: Callable[[int], dict[str, Any]], sizes: list[int]) -> None:
    print(title)
    prev = None
    for n in sizes:
        ms = median_ms(make(n))
        growth = "" if prev is None else f"  (x{ms / prev[1]:.2f} for x{n / prev[0]:.1f} size)"
        print(f"  n = {n:5d}: {ms:8.2f} ms{growth}")
        prev = (n, ms)


def main() -> None:
    print(f"1,000-vertex random polygon: {median_ms(shapes.random_polygon(1000, 1)):.2f} ms (target ≤ 20 ms)")
    print(f"50 cubic Bezier segments:    {median_ms(shapes.bezier_blob(50, 2)):.2f} ms (target ≤ 50 ms)")
    series("random polygons", lambda n: shapes.random_polygon(n, 1), [100, 250, 500, 1000, 2000, 4000])
    series("cubic Bezier blobs", lambda n: shapes.bezier_blob(n, 2), [10, 25, 50, 100, 200])


if __name__ == "__main__":
    main()
