"""Load benchmark of ``POST /v1/plans`` on loopback: the service runs in its own process
(uvicorn, default 2 workers), this script is the load generator (threads, keep-alive
connections). Prints requests per second and p50/p99 latency for cached and uncached
small parts (no validation). Targets: ≥ 300 req/s cached, p99 ≤ 100 ms uncached."""

from __future__ import annotations

import statistics
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

from algrasp.shapes import random_polygon, rectangle
from service.launch import start_server


def _load(url: str, bodies: list[dict[str, Any]], concurrency: int) -> tuple[float, list[float], dict[int, int]]:
    """Send every body once, ``concurrency`` at a time; (req/s, latencies s, status counts)."""
    import httpx

    lat: list[float] = []
    codes: dict[int, int] = {}
    lock = threading.Lock()
    it = iter(bodies)

    def worker() -> None:
        with httpx.Client(base_url=url, timeout=60) as c:
            while True:
                with lock:
                    body = next(it, None)
                if body is None:
                    return
                t0 = time.perf_counter()
                r = c.post("/v1/plans", json=body)
                dt = time.perf_counter() - t0
                with lock:
                    lat.append(dt)
                    codes[r.status_code] = codes.get(r.status_code, 0) + 1

    threads = [threading.Thread(target=worker) for _ in range(concurrency)]
    t0 = time.perf_counter()
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return len(bodies) / (time.perf_counter() - t0), lat, codes


def _report(title: str, rps: float, lat: list[float], codes: dict[int, int]) -> None:
    q = statistics.quantiles(lat, n=100)
    print(f"{title:<44} {rps:8.1f} req/s   p50 {1000 * q[49]:6.1f} ms   p99 {1000 * q[98]:6.1f} ms   statuses {codes}")


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        server = start_server(Path(tmp))
        try:
            small = {"part": rectangle(20.0, 8.0), "action": "squeeze"}
            _load(server.url, [small] * 50, 4)  # warm the workers and the cache
            for conc in (8, 16):
                _report(f"cached, concurrency {conc}", *_load(server.url, [small] * 3000, conc))
            for conc in (1, 2):
                parts: list[dict[str, Any]] = [{"part": random_polygon(8, seed=1000 * conc + i), "action": "squeeze"}
                                               for i in range(300)]
                _report(f"uncached 8-gon plans, concurrency {conc}", *_load(server.url, parts, conc))
            parts = [{"part": random_polygon(8, seed=90_000 + i), "action": "push_grasp", "optimise": True} for i in range(40)]
            _report("uncached push-grasp + optimise, concurrency 2", *_load(server.url, parts, 2))
        finally:
            server.kill()


if __name__ == "__main__":
    main()
