"""Service and batch settings: environment variables ``ALGRASP_*`` (pydantic-settings).

Every default is an embedded one (SQLite in ``logs/``, a local worker pool, records in
``logs/``), so ``algrasp serve`` needs no set-up. API keys come only from the
environment or a key file outside the repository.
"""

from __future__ import annotations

from functools import cached_property
from pathlib import Path

from pydantic import Field
from pydantic_settings import BaseSettings, SettingsConfigDict

from algrasp.errors import ConfigError


class Settings(BaseSettings):
    """Attributes (environment variable = ``ALGRASP_`` + upper-case name):
        log_dir: run records (MCAP) directory.
        database_url: SQLAlchemy URL of the job/run store (default SQLite in ``log_dir``).
        api_keys: comma-separated bearer keys; empty and no ``api_keys_file``: no auth.
        api_keys_file: a file with one key per line (``#`` comments allowed).
        scheduler: Dask scheduler address (``tcp://host:8786``); empty: local process pool.
        workers: local worker processes for plans and batch parts.
        sim_workers: Drake worker processes per validation.
        max_body_bytes: largest request body (bytes; the archive upload too).
        max_batch_parts: most parts in one job.
        max_samples: most validation samples per part.
        analysis_time_limit_s / plan_time_limit_s: per request, analysis alone / analysis+plan+optimisation.
        validation_time_limit_s: added to the plan limit when a validation is asked for.
        cache_entries: responses kept in the same-input cache.
    """

    model_config = SettingsConfigDict(env_prefix="ALGRASP_", extra="ignore")

    log_dir: Path = Path("logs")
    database_url: str = ""
    api_keys: str = Field(default="", repr=False)
    api_keys_file: Path | None = None
    scheduler: str = ""
    workers: int = Field(default=2, ge=1, le=64)
    sim_workers: int = Field(default=2, ge=1, le=64)
    max_body_bytes: int = Field(default=8_000_000, ge=1_000)
    max_batch_parts: int = Field(default=2_000, ge=1)
    max_samples: int = Field(default=500, ge=1)
    analysis_time_limit_s: float = Field(default=20.0, gt=0)
    plan_time_limit_s: float = Field(default=60.0, gt=0)
    validation_time_limit_s: float = Field(default=1800.0, gt=0)
    cache_entries: int = Field(default=4096, ge=0)

    @property
    def db_url(self) -> str:
        return self.database_url or f"sqlite:///{(self.log_dir / 'algrasp.db').resolve()}"

    @cached_property
    def keys(self) -> frozenset[str]:
        """The configured API keys (empty: authentication off)."""
        keys = {k.strip() for k in self.api_keys.split(",") if k.strip()}
        if self.api_keys_file is not None:
            try:
                lines = self.api_keys_file.read_text(encoding="utf-8").splitlines()
            except OSError as exc:
                raise ConfigError("ALGRASP_API_KEYS_FILE", f"cannot read {self.api_keys_file}: {exc.strerror}") from None
            keys |= {ln.strip() for ln in lines if ln.strip() and not ln.lstrip().startswith("#")}
        return frozenset(keys)


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
