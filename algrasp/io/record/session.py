"""Recording one run from a shell (CLI, service, batch): a thin layer over RunRecorder
that a caller feeds with what it computed, or a no-op when recording is off."""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from algrasp.io.record.recorder import RunRecorder, new_run_id


class Recording:
    """What a run computed, written as it comes (``enabled`` False: nothing is written)."""

    def __init__(self, recorder: RunRecorder | None, command: str, part: dict[str, Any], options: dict[str, Any]) -> None:
        self._rec = recorder
        self.run_id = recorder.run_id if recorder else new_run_id()
        self.record_path: str | None = str(recorder.path) if recorder else None
        self._t0 = time.perf_counter()
        if recorder:
            name = part.get("name")  # a malformed part's "name" may be anything: the summary keeps a string or None
            recorder.summary.update({"command": command, "part_name": name if isinstance(name, str) else None,
                                     "action": options.get("action"),
                                     "steps": None, "agreement": None, "cycle_time_s": None})
            recorder.write("/request", {"run_id": self.run_id, "command": command, "part": part, "options": options})

    def fields(self) -> dict[str, Any]:
        """``run_id`` and ``record_path`` for JSON outputs."""
        return {"run_id": self.run_id, "record_path": self.record_path}

    def analysis(self, doc: dict[str, Any]) -> None:
        if self._rec:
            self._rec.write("/analysis", doc)

    def plan(self, doc: dict[str, Any]) -> None:
        if self._rec:
            self._rec.write("/plan", doc)
            self._rec.summary.update({"steps": len(doc["steps"]), "cycle_time_s": doc.get("cycle_time_s"),
                                      "action": self._rec.summary.get("action") or doc.get("action"),
                                      "timings_s": {k: float(v) for k, v in doc.get("timings_s", {}).items()}})

    def validation(self, doc: dict[str, Any], trajectories: Any, outline_m: Any, jaw_size_m: tuple[float, float]) -> None:
        """The validation document (without its plan: that is on ``/plan``) and every
        simulated trajectory."""
        if self._rec:
            self._rec.write("/validation", doc)
            self._rec.summary.update({"agreement": doc["agreement"]})
            self._rec.summary["timings_s"]["validation"] = float(doc["wall_seconds"])
            self._rec.trajectories(outline_m, jaw_size_m, list(trajectories))

    def plan_scene(self, frames: list[tuple[float, ...]], outline_m: Any, jaw_size_m: tuple[float, float]) -> None:
        """A plan without validation: the part at each action's outcome on ``/scene``, ``/tf``."""
        if self._rec:
            self._rec.keyframes(outline_m, jaw_size_m, frames)


@contextmanager
def recording(enabled: bool, directory: Path | None, command: str, part: dict[str, Any],
              options: dict[str, Any], run_id: str | None = None) -> Iterator[Recording]:
    """A Recording for the block; the record is completed (and renamed) when the block
    ends, also when it raises (the ``/run`` status then says ``error``). ``run_id``: chosen
    by the caller (the service, so it can remove the partial record of a worker it lost)."""
    if not enabled:
        yield Recording(None, command, part, options)
        return
    with RunRecorder(directory, run_id) as rec:
        session = Recording(rec, command, part, options)
        t0 = time.perf_counter()
        yield session
        rec.summary["timings_s"]["total"] = time.perf_counter() - t0
