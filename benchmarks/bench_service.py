"""Load benchmark of ``POST /v1/plans`` on loopback: the service runs in its own process
(uvicorn, default 2 workers), this script is the load generator (threads, keep-alive
connections). Prints requests per second and p50/p99 latency for cached and uncached
small parts (no validation). Targets: ≥ 300 req/s cached, p99 ≤ 100 ms uncached.

Issue 18: cheap plans while two expensive requests are in flight (target p99 ≤ 1 s), and
the server's memory (RSS of the server process and its workers) before and after 10,000
distinct requests: bounded by the byte-bounded cache, not by the number of requests."""

from __future__ import annotations

import statistics
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

from algrasp.testing.shapes import random_polygon, rectangle
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


def _cheap_beside_expensive(url: str) -> None:
    """Two push-grasp + optimise plans on a sliver part keep the slow pool busy while
    cheap plans are sent one at a time."""
    sliver = {"name": "sliver", "boundary": [[0, 0], [40, 0], [40.3, 0.2], [0, 0.25]]}
    busy = [{"part": {**sliver, "name": f"s{k}"}, "action": "push_grasp", "optimise": True,
             "gripper": {"sample_hz": 500 + k}} for k in range(8)]
    load = threading.Thread(target=_load, args=(url, busy, 2))
    load.start()
    time.sleep(0.5)
    parts = [{"part": rectangle(10.0 + i / 100, 4.0), "action": "squeeze"} for i in range(200)]
    rps, lat, codes = _load(url, parts, 1)
    load.join()
    _report("cheap plans beside 2 expensive, concurrency 1", rps, lat, codes)


def _rss_mb(pid: int) -> float:
    import psutil

    procs = [psutil.Process(pid), *psutil.Process(pid).children(recursive=True)]
    return sum(p.memory_info().rss for p in procs) / 1e6


def _memory(server: Any) -> None:
    """Server memory before and after 10,000 distinct (uncached) analyses."""
    before = _rss_mb(server.proc.pid)
    t0 = time.perf_counter()
    for start in range(0, 10_000, 2_000):
        parts = [{"part": rectangle(5.0 + (start + i) / 1000, 2.0), "action": "squeeze"} for i in range(2_000)]
        _load(server.url, parts, 4)
        print(f"  after {start + 2_000:>6} distinct requests: server + workers RSS {_rss_mb(server.proc.pid):8.1f} MB")
    print(f"10,000 distinct requests in {time.perf_counter() - t0:.1f} s: RSS {before:.1f} → "
          f"{_rss_mb(server.proc.pid):.1f} MB")


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
            _cheap_beside_expensive(server.url)
            _memory(server)
        finally:
            server.kill()


if __name__ == "__main__":
    main()
