"""``algrasp serve`` and ``algrasp batch``: the service and batch jobs from the command line."""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import asdict
from importlib import resources
from pathlib import Path
from typing import Any

from algrasp.errors import ConfigError

EXAMPLE = "bracket.json"
"""Planned once at start-up: orientable by push-grasp in the default (real) cell, which
the paper's 5 mm pie (``pie-20.json``) is not (its constant-width arc is not certain rest
under a manufacturing tolerance)."""


def example_part() -> dict[str, Any]:
    """The part document of :data:`EXAMPLE` (bundled with the package)."""
    doc: dict[str, Any] = json.loads(resources.files("algrasp").joinpath("examples", EXAMPLE).read_text())
    return doc


def cmd_serve(args: argparse.Namespace) -> int:
    try:
        import uvicorn
    except ImportError:
        raise ConfigError("serve", "the service needs its extra: pip install 'algrasp[service]'") from None

    from service.app import create_app
    from service.settings import load_settings

    warmup = None if args.no_example else example_part()
    url = f"http://{args.host}:{args.port}"
    settings = load_settings()
    app = create_app(settings, warmup=warmup, url=url)
    # A stop (SIGTERM) waits at most shutdown_grace_s for requests in flight, then their
    # workers are killed; idle and slow connections are closed after keep_alive_s, and
    # past max_connections new ones get 503 at once instead of queueing in the kernel; a
    # request head that has not arrived within header_timeout_s closes the connection.
    from service.protocol import with_header_timeout

    uvicorn.run(app, host=args.host, port=args.port, log_level=args.log_level,
                timeout_graceful_shutdown=settings.shutdown_grace_s, timeout_keep_alive=settings.keep_alive_s,
                limit_concurrency=settings.max_connections, http=with_header_timeout(settings.header_timeout_s))
    return 0


def _options(args: argparse.Namespace) -> dict[str, Any]:
    from service.fixture import FENCE_OPTIONS, DesignOptions, check_fence_options

    profile = None
    if args.gripper:
        from optimisation.profile import load_profile

        profile = load_profile(args.gripper).to_dict()
    if args.validate_samples < 0:
        raise ConfigError("--validate-samples", "must be ≥ 0")
    from algrasp.cli import model_from_args

    model = model_from_args(args).to_options()
    from algrasp.planning.cells import parse_cells

    parse_cells(args.sim_physics)
    opts = DesignOptions(args.min_margin_deg, args.validate_samples, args.seed, None, profile,
                         model["exact"], model.get("physics"), args.sim_physics, args.fences, args.fence_friction,
                         args.limits, **{k: getattr(args, k) for k in FENCE_OPTIONS[1:]})
    check_fence_options(opts, "--fences")
    return asdict(opts)


def cmd_batch(args: argparse.Namespace) -> int:
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from service.catalogue import catalogue_hash, read_catalogue
    from service.executor import make_executor
    from service.jobs import JobRunner, RunnerConfig
    from service.settings import load_settings
    from service.store import Store

    settings = load_settings(**({"scheduler": args.scheduler} if args.scheduler else {}), workers=args.workers)
    entries = read_catalogue(Path(args.source), settings.max_batch_parts, settings.max_body_bytes * 100)
    options = _options(args)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    store = Store(args.database or f"sqlite:///{(out / 'batch.db').resolve()}")
    h = catalogue_hash(entries, options)
    job_id = store.find_job(h) or store.create_job(options, entries, h)
    before = store.progress(job_id)
    assert before is not None
    if before["pending"] < before["total"]:
        print(f"resuming job {job_id}: {before['total'] - before['pending']} of {before['total']} parts already finished")
    executor = make_executor(settings.scheduler, settings.workers, wait_for_workers_s=args.wait_for_workers_s)
    limit = settings.plan_time_limit_s + (settings.validation_time_limit_s if options["samples"] else 0.0)
    record_dir = str(Path(args.record_dir) if args.record_dir else settings.log_dir)
    t0 = time.perf_counter()
    with Progress(TextColumn(f"[bold]{executor.name}[/] parts"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn()) as bar:
        task = bar.add_task("parts", total=before["total"], completed=before["total"] - before["pending"])
        runner = JobRunner(store, executor, RunnerConfig.for_workers(record_dir, args.sim_workers, limit, settings.workers,
                                                                    settings.batch_chunk),
                           on_progress=lambda _j, n, _t: bar.update(task, completed=n))
        try:
            runner.run(job_id)
        finally:
            executor.shutdown()
    wall = time.perf_counter() - t0
    return _report(store, job_id, out, before["pending"], wall)


def _report(store: Any, job_id: str, out: Path, ran: int, wall: float) -> int:
    from service.fixture import catalogue_spec
    from service.reports import write_reports

    progress = store.progress(job_id)
    results = store.results(job_id)
    write_reports(out, results, progress)
    spec = catalogue_spec(results)
    print(f"job {job_id}: {spec['oriented']} of {spec['parts']} parts oriented; {ran} parts computed in {wall:.1f} s"
          + (f" ({60 * ran / wall:.1f} parts/min)" if ran and wall > 0 else ""))
    print(f"gripper: jaw opening {spec['jaw_opening_mm'] or 0:.2f} mm, jaw length {spec['jaw_length_mm'] or 0:.2f} mm, "
          f"push stroke {spec['push_stroke_mm'] or 0:.2f} mm, cycle ≤ {spec['max_cycle_time_s'] or 0:.2f} s")
    for p in spec["not_oriented"][:20]:
        print(f"  not oriented: {p['name']}: {p['why']}")
    print(f"report: {out / 'report.md'} (also results.jsonl, summary.csv, gripper_spec.json)")
    return 0


def add_commands(sub: Any) -> None:
    p = sub.add_parser("serve", help="run the HTTP service (FastAPI on uvicorn)")
    p.add_argument("--host", default="127.0.0.1")
    p.add_argument("--port", type=int, default=8000)
    p.add_argument("--no-example", action="store_true", help="do not plan the bundled example part at start-up")
    p.add_argument("--log-level", default="info", choices=["critical", "error", "warning", "info", "debug"])
    p.set_defaults(func=cmd_serve)
    p = sub.add_parser("batch", help="fixture design for a catalogue of parts (directory or zip/tar archive)")
    p.add_argument("source", metavar="CATALOGUE_DIR|ARCHIVE")
    p.add_argument("--out", required=True, metavar="DIR", help="reports and the job database (re-running resumes)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler (tcp://host:8786); default: local worker pool")
    p.add_argument("--workers", type=int, default=2, help="local worker processes")
    p.add_argument("--wait-for-workers-s", type=float, default=30.0, metavar="S",
                   help="with --scheduler: wait this long for a first Dask worker, then stop (default 30)")
    p.add_argument("--sim-workers", type=int, default=1, help="Drake processes per validation")
    p.add_argument("--database", metavar="URL", help="SQLAlchemy URL of the job store (default sqlite in --out)")
    p.add_argument("--min-margin-deg", type=float, default=0.0)
    p.add_argument("--validate-samples", type=int, default=0, help="Drake samples per part (0: no validation)")
    p.add_argument("--sim-physics", default="nominal", metavar="nominal|corners|random|KEY=VALUE,...",
                   help="which cells of the physics ranges validation simulates (as for algrasp validate)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--gripper", metavar="PROFILE.yaml|json")
    g = p.add_argument_group("conveyor fences (with --fences: every part's fence design, as algrasp fences)")
    g.add_argument("--fences", action="store_true", help="also design conveyor fences for every part (conventions §9)")
    from algrasp.cli_fences import fence_design_options

    fence_design_options(g, tail=False)
    g.add_argument("--fence-min-margin-deg", type=float, metavar="M", help="every fence angle may be off by M degrees "
                   "(default --min-margin-deg, at least 1)")
    p.add_argument("--limits", choices=("none", "headline", "all"), default="headline",
                   help="physics limits per part: headline (default) the largest jaw friction with a plan and every "
                   "limit with a refusal; none no search (fastest screen of a catalogue); all every limit")
    from algrasp.cli import model_options

    model_options(p)
    p.add_argument("--record-dir", metavar="DIR", help="run records (default $ALGRASP_LOG_DIR or logs/)")
    p.set_defaults(func=cmd_batch)
