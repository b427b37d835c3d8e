"""Service and batch settings: environment variables ``ALGRASP_*`` (pydantic-settings).

Every default is an embedded one (SQLite in ``logs/``, a local worker pool, records in
``logs/``), so ``algrasp serve`` needs no set-up. API keys come only from the
environment or a key file outside the repository.
"""

from __future__ import annotations

import hmac
from functools import cached_property
from pathlib import Path

from pydantic import Field, field_validator
from pydantic_settings import BaseSettings, SettingsConfigDict

from algrasp.errors import ConfigError
from algrasp.planning.physics import Physics, cell_from_text

_AGE_UNITS = {"": 1.0, "s": 1.0, "m": 60.0, "h": 3600.0, "d": 86400.0}
_BYTE_UNITS = {"": 1.0, "b": 1.0, "k": 1e3, "m": 1e6, "g": 1e9, "t": 1e12}


def parse_quantity(text: str, units: dict[str, float], name: str) -> float:
    """``"30d"`` → 2592000.0 with ``units`` mapping suffixes (lower case) to factors.

    >>> parse_quantity("1.5G", _BYTE_UNITS, "x")
    1500000000.0
    """
    t = str(text).strip().lower()
    unit = t.lstrip("0123456789.")
    number = t[: len(t) - len(unit)]
    try:
        value = float(number) * units[unit.strip()]
    except (ValueError, KeyError):
        raise ValueError(f"{name}: {text!r} is not a number with a unit ({', '.join(u for u in units if u)})") from None
    if not value >= 0 or value == float("inf"):
        raise ValueError(f"{name}: must be ≥ 0")
    return value


class Settings(BaseSettings):
    """Attributes (environment variable = ``ALGRASP_`` + upper-case name):
        log_dir: run records (MCAP) directory.
        cell: the cell's physics every request refines: ``default`` (a real cell's ranges),
            ``ideal`` (frictionless jaws, μ_s 0.3, 20 g, centred, exact parts) or a JSON
            object of physics keys (conventions §8).
        database_url: SQLAlchemy URL of the job/run store (default SQLite in ``log_dir``).
        api_keys: comma-separated bearer keys; empty and no ``api_keys_file``: no auth.
        api_keys_file: a file with one key per line (``#`` comments allowed).
        admin_keys: comma-separated bearer keys that may also read and cancel every
            other key's runs and jobs (each key otherwise sees only its own).
        scheduler: Dask scheduler address (``tcp://host:8786``); empty: local process pool.
        workers: local worker processes for plans and batch parts.
        sim_workers: Drake worker processes per validation.
        max_body_bytes: largest request body (bytes; the archive upload too).
        max_batch_parts: most parts in one job.
        batch_chunk: parts of a job sent to a worker in one task (fewer round trips to
            the pool; a chunk whose worker dies or runs out of time is retried part by part).
        max_samples: most validation samples per part.
        analysis_time_limit_s / plan_time_limit_s: per request, analysis alone / analysis+plan+optimisation.
        validation_time_limit_s: added to the plan limit when a validation is asked for.
        fast_workers: worker processes for cheap requests (analyses, plans without
            optimisation or validation), apart from the ``workers`` that take the rest.
        queue_depth: requests that may wait per pool beyond its workers (then 503).
        max_inflight_per_client: requests one client (API key or address) may have in
            flight (then 429).
        cache_bytes: bytes of responses kept in the same-input cache.
        max_response_bytes: largest response body (a plan's trajectory samples grow
            with ``gripper.sample_hz``); larger: 422 naming the option to lower.
        record_max_age: run records older than this are deleted (``30d``, ``12h``,
            ``90m``, ``3600s`` or seconds; ``0``: keep forever).
        record_max_bytes: the oldest records are deleted past this total (``5G``,
            ``500M``, bytes; ``0``: no limit).
        retention_period_s: how often retention runs (also once at start-up).
        shutdown_grace_s: on SIGTERM, how long requests in flight may finish before
            their workers are killed.
        keep_alive_s: an idle connection is closed after this.
        max_connections: connections (and requests) at once; past this: 503 at once.
        body_timeout_s: a request body that does not arrive whole within this is
            refused (408): a client trickling its body cannot hold a connection.
        header_timeout_s: a connection whose request line and headers have not arrived
            whole within this is closed (slow clients cannot hold connections).
        db_busy_timeout_s: how long a write waits for a locked SQLite database before
            the request is answered 503 (the job runner retries).
    """

    model_config = SettingsConfigDict(env_prefix="ALGRASP_", extra="ignore")

    log_dir: Path = Path("logs")
    cell: str = "default"
    database_url: str = ""
    api_keys: str = Field(default="", repr=False)
    api_keys_file: Path | None = None
    admin_keys: str = Field(default="", repr=False)
    scheduler: str = ""
    workers: int = Field(default=2, ge=1, le=64)
    sim_workers: int = Field(default=2, ge=1, le=64)
    max_body_bytes: int = Field(default=8_000_000, ge=1_000)
    max_batch_parts: int = Field(default=20_000, ge=1)
    batch_chunk: int = Field(default=8, ge=1, le=256)
    max_samples: int = Field(default=500, ge=1)
    analysis_time_limit_s: float = Field(default=20.0, gt=0)
    plan_time_limit_s: float = Field(default=60.0, gt=0)
    validation_time_limit_s: float = Field(default=1800.0, gt=0)
    fast_workers: int = Field(default=2, ge=1, le=64)
    queue_depth: int = Field(default=16, ge=0, le=10_000)
    max_inflight_per_client: int = Field(default=16, ge=1, le=10_000)
    cache_bytes: int = Field(default=64_000_000, ge=0)
    max_response_bytes: int = Field(default=16_000_000, ge=10_000)
    record_max_age: str = "30d"
    record_max_bytes: str = "5G"
    retention_period_s: float = Field(default=60.0, gt=0)
    shutdown_grace_s: int = Field(default=5, ge=0, le=3600)
    keep_alive_s: int = Field(default=5, ge=1, le=3600)
    max_connections: int = Field(default=1000, ge=10, le=1_000_000)
    body_timeout_s: float = Field(default=30.0, gt=0)
    header_timeout_s: float = Field(default=10.0, gt=0)
    db_busy_timeout_s: float = Field(default=2.0, ge=0, le=600)

    @field_validator("record_max_age")
    @classmethod
    def _age(cls, v: str) -> str:
        parse_quantity(v, _AGE_UNITS, "record_max_age")
        return v

    @field_validator("cell")
    @classmethod
    def _cell(cls, v: str) -> str:
        cell_from_text(v, "ALGRASP_CELL")
        return v

    @property
    def cell_physics(self) -> Physics:
        return cell_from_text(self.cell, "ALGRASP_CELL")

    @field_validator("record_max_bytes")
    @classmethod
    def _bytes(cls, v: str) -> str:
        parse_quantity(v, _BYTE_UNITS, "record_max_bytes")
        return v

    @property
    def record_max_age_s(self) -> float:
        return parse_quantity(self.record_max_age, _AGE_UNITS, "record_max_age")

    @property
    def record_max_total_bytes(self) -> float:
        return parse_quantity(self.record_max_bytes, _BYTE_UNITS, "record_max_bytes")

    @property
    def db_url(self) -> str:
        return self.database_url or f"sqlite:///{(self.log_dir / 'algrasp.db').resolve()}"

    @cached_property
    def keys(self) -> frozenset[str]:
        """The configured API keys, admin keys included (empty: authentication off).
        Keys configured but none given (``","``, a file of comments only) is an error:
        a typo must not turn authentication off."""
        keys = _split(self.api_keys) | self.admin_keys_set
        if self.api_keys_file is not None:
            try:
                lines = self.api_keys_file.read_text(encoding="utf-8").splitlines()
            except OSError as exc:
                raise ConfigError("ALGRASP_API_KEYS_FILE", f"cannot read {self.api_keys_file}: {exc.strerror}") from None
            keys |= {ln.strip() for ln in lines if ln.strip() and not ln.lstrip().startswith("#")}
        configured = self.api_keys.strip() or self.admin_keys.strip() or self.api_keys_file is not None
        if configured and not keys:
            raise ConfigError("ALGRASP_API_KEYS", "API keys are configured but none is given (an empty list or a key "
                              "file of comments only): give a key, or unset the variables to turn authentication off")
        return frozenset(keys)

    @cached_property
    def admin_keys_set(self) -> frozenset[str]:
        return _split(self.admin_keys)

    def is_admin(self, key: str) -> bool:
        """Whether ``key`` is an admin key (constant-time)."""
        return any(hmac.compare_digest(key.encode(), k.encode()) for k in self.admin_keys_set)


def _split(text: str) -> frozenset[str]:
    return frozenset(k.strip() for k in text.split(",") if k.strip())


def load_settings(**overrides: object) -> Settings:
    """Settings from the environment (and ``overrides``); a bad value is a ConfigError
    naming the environment variable, not a traceback."""
    from pydantic import ValidationError

    try:
        return Settings(**overrides)  # type: ignore[arg-type]
    except ValidationError as exc:
        e = exc.errors()[0]
        name = "ALGRASP_" + "_".join(str(x) for x in e["loc"]).upper()
        raise ConfigError(name, f"{e['msg']} (got {e.get('input')!r})") from None
