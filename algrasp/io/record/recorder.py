"""One MCAP record per run (an adapter: the only module writing MCAP).

``RunRecorder`` writes ``<dir>/<run_id>.mcap.partial`` (zstd chunks, small enough that a
crash loses at most the last ~64 KiB) and renames it to ``<run_id>.mcap`` only when the
run is finished, so no crashed run looks complete; a partial file still reads up to its
last complete chunk. Channels:

- JSON channels with the schemas of ``schemas``: ``/request`` (part document and
  options), ``/analysis``, ``/plan`` (with the optimised execution when there is one),
  ``/validation`` (per-sample results and agreement), ``/sim/state`` (every simulated
  state), ``/run`` (summary, timings, software versions; written last);
- Foxglove well-known schemas (protobuf): ``/scene`` (``foxglove.SceneUpdate``: the
  part's exact hull outline and the two jaws) and ``/tf`` (``foxglove.FrameTransforms``:
  world → part, world → gripper → jaws), with log times following simulation time, so
  the file opened in Foxglove's 3-D panel shows the part turning between the jaws.
  Simulated samples follow each other on the timeline, one second apart. A plan-only
  record (no validation) has the same two channels with one frame per action
  (:mod:`algrasp.io.record.scene`: the part at each action's outcome between the jaws).
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import time
import uuid
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

import orjson

from algrasp.geometry.angles import to_deg
from algrasp.io.record.schemas import TOPICS

if TYPE_CHECKING:  # numpy is not needed to list or replay runs
    from algrasp.geometry.curves import FloatArray

CHUNK_BYTES = 64 * 1024
SAMPLE_GAP_S = 1.0
DEFAULT_DIR_ENV = "ALGRASP_LOG_DIR"


def default_directory() -> Path:
    """``$ALGRASP_LOG_DIR`` or ``logs/`` in the working directory."""
    return Path(os.environ.get(DEFAULT_DIR_ENV, "logs"))


def new_run_id() -> str:
    """Sortable and unique: UTC time, then 8 random hex digits."""
    return time.strftime("%Y%m%dT%H%M%SZ", time.gmtime()) + "-" + uuid.uuid4().hex[:8]


def versions() -> dict[str, str]:
    """Versions of the software that computed the run (a new dict each call)."""
    return dict(_versions())


@cache
def _versions() -> dict[str, str]:
    """Read once per process: package metadata costs milliseconds per lookup."""
    import importlib.metadata as md
    import platform

    out = {"python": platform.python_version()}
    for pkg in ("algrasp", "numpy", "scipy", "casadi", "drake", "mcap"):
        try:
            out[pkg] = md.version(pkg)
        except md.PackageNotFoundError:
            continue
    return out


PARTIAL_SUFFIX = ".mcap.partial"
"""A run's record while it is written (renamed to ``.mcap`` when the run finishes)."""


def partial_path(directory: Path, run_id: str) -> Path:
    """Where the record of run ``run_id`` is written until the run finishes."""
    return directory / f"{run_id}{PARTIAL_SUFFIX}"


def discard_partial(directory: Path, run_id: str) -> None:
    """Remove a run's partial record (its worker was killed, or its run failed)."""
    with contextlib.suppress(OSError):
        partial_path(directory, run_id).unlink(missing_ok=True)


def discard_record(directory: Path, run_id: str) -> None:
    """Remove a run's record, final or partial (a batch part whose outcome was never
    stored: it is recorded again under the same id)."""
    discard_partial(directory, run_id)
    with contextlib.suppress(OSError):
        (directory / f"{run_id}.mcap").unlink(missing_ok=True)


def _storage_error(directory: Path, err: OSError) -> Exception:
    from algrasp.errors import StorageError

    # No path in the message: it reaches HTTP clients, who must not learn the server's layout.
    return StorageError("records", f"cannot write run records in the record directory: "
                        f"{err.strerror or type(err).__name__} (disk full or read-only?)", 30.0)


_ORJSON_OPTIONS = orjson.OPT_SERIALIZE_NUMPY | orjson.OPT_NON_STR_KEYS
"""numpy scalars and arrays as numbers and lists; non-string keys as strings (as ``json``)."""


def json_bytes(payload: dict[str, Any]) -> bytes:
    """A message's JSON (UTF-8, no spaces) by orjson: every number reads back to the same
    float as ``json.dumps`` wrote it (both print the shortest repr that round-trips;
    only the exponent's form differs, ``1e-5`` for ``1e-05``), ~20× faster on the 100 Hz
    trajectories that are most of a plan's bytes. NaN and infinities raise ValueError as
    ``json.dumps(allow_nan=False)`` does (orjson would write null). O(size)."""
    if not _finite(payload):
        json.dumps(payload, allow_nan=False)  # raises, naming the value
    return orjson.dumps(payload, option=_ORJSON_OPTIONS)


def _finite(value: Any) -> bool:
    """Whether no float in ``value`` (dicts, lists, tuples) is NaN or infinite: a list of
    numbers is summed in C (a non-finite sum is checked item by item: it may overflow)."""
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, dict):
        return all(_finite(v) for v in value.values())
    if isinstance(value, (list, tuple)):
        try:
            if math.isfinite(sum(value)):
                return True
        except (TypeError, OverflowError):  # not all numbers; an int too large for a float
            pass
        return all(_finite(v) for v in value)
    return True


@cache
def _json_schema(topic: str) -> bytes:
    """The JSON schema of a topic as a record stores it (built once per process)."""
    return json.dumps(TOPICS[topic]).encode()


@cache
def _proto_schema(cls: Any) -> bytes:
    """A protobuf message class's file descriptor set, as ``mcap_protobuf`` registers it
    (built once per process: it walks every descriptor the message depends on)."""
    from mcap_protobuf.schema import build_file_descriptor_set

    return bytes(build_file_descriptor_set(cls).SerializeToString())


class RunRecorder:
    """Context manager writing one run; ``path`` is the final record path."""

    def __init__(self, directory: Path | None = None, run_id: str | None = None) -> None:
        from mcap.writer import CompressionType, Writer

        self.run_id = run_id or new_run_id()
        self.directory = directory or default_directory()
        self.directory.mkdir(parents=True, exist_ok=True)
        self.path = self.directory / f"{self.run_id}.mcap"
        self.partial = partial_path(self.directory, self.run_id)
        self.started = time.time()
        self._t0_ns = time.time_ns()
        try:
            self._file = open(self.partial, "wb")  # noqa: SIM115 - closed in close()
        except OSError as err:
            raise _storage_error(self.directory, err) from None
        self._writer = Writer(self._file, chunk_size=CHUNK_BYTES, compression=CompressionType.ZSTD)
        self._writer.start(profile="", library="algrasp")
        self._channels: dict[str, int] = {}
        self.summary: dict[str, Any] = {"run_id": self.run_id, "started_unix_s": self.started, "timings_s": {}}

    def __enter__(self) -> RunRecorder:
        return self

    def __exit__(self, exc_type: Any, exc: BaseException | None, tb: Any) -> None:
        if exc is not None and not isinstance(exc, Exception):
            self._file.close()  # KeyboardInterrupt etc.: leave the partial file as it is
            return
        try:
            self.finish(error=None if exc is None else exc)
        except OSError as err:  # disk full, read-only: nothing half written is left
            self.discard()
            raise _storage_error(self.directory, err) from None
        if isinstance(exc, OSError):  # a write failed in the block, the summary did not
            self.path.unlink(missing_ok=True)
            raise _storage_error(self.directory, exc) from None

    def discard(self) -> None:
        """Close and remove the partial record (a run that cannot be written whole)."""
        with contextlib.suppress(OSError):
            self._file.close()
        self.partial.unlink(missing_ok=True)

    def _channel(self, topic: str) -> int:
        if topic not in self._channels:
            sid = self._writer.register_schema(TOPICS[topic]["title"], "jsonschema", _json_schema(topic))
            self._channels[topic] = self._writer.register_channel(topic, "json", sid)
        return self._channels[topic]

    def _proto_channel(self, topic: str, cls: Any) -> int:
        if topic not in self._channels:
            sid = self._writer.register_schema(cls.DESCRIPTOR.full_name, "protobuf", _proto_schema(cls))
            self._channels[topic] = self._writer.register_channel(topic, "protobuf", sid)
        return self._channels[topic]

    def write(self, topic: str, payload: dict[str, Any], log_time_ns: int | None = None) -> None:
        """A JSON message on one of the channels of ``schemas.TOPICS``."""
        t = time.time_ns() if log_time_ns is None else log_time_ns
        self._writer.add_message(self._channel(topic), t, json_bytes(payload), t)

    def finish(self, error: BaseException | None = None) -> Path:
        """Write ``/run``, close, and rename to the final name (also after a user error,
        so failed requests are reviewable; the status says so)."""
        from algrasp.errors import AlgraspError

        self.summary["status"] = "ok" if error is None else "error"
        self.summary["error"] = None if error is None else (
            error.to_dict() if isinstance(error, AlgraspError) else {"type": type(error).__name__, "message": str(error)})
        self.summary["versions"] = versions()
        self.summary.setdefault("command", "unknown")
        self.write("/run", self.summary)
        self._writer.finish()
        self._file.close()
        os.replace(self.partial, self.path)
        return self.path

    # ------------------------------------------------------------ simulation

    def trajectories(self, outline_m: FloatArray, jaw_size_m: tuple[float, float],
                     runs: list[list[tuple[float, ...]]]) -> None:
        """Every simulated run as ``/sim/state`` JSON plus Foxglove ``/scene`` and ``/tf``.
        ``runs[k]`` holds (t, x, y, φ, α, q_lower, q_higher) samples in SI units."""
        from foxglove_schemas_protobuf.FrameTransforms_pb2 import FrameTransforms
        from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate

        scene_ch = self._proto_channel("/scene", SceneUpdate)
        tf_ch = self._proto_channel("/tf", FrameTransforms)
        start_ns = self._t0_ns
        for k, samples in enumerate(runs):
            if not samples:
                continue
            scene = _scene(outline_m, jaw_size_m, start_ns)
            self._writer.add_message(scene_ch, start_ns, scene.SerializeToString(), start_ns)
            for t, x, y, phi, alpha, ql, qh in samples:
                ns = start_ns + int(t * 1e9)
                self.write("/sim/state", {"sample": k, "t_s": t, "x_m": x, "y_m": y, "phi_deg": to_deg(phi),
                                          "gripper_angle_deg": to_deg(alpha), "lower_jaw_m": ql,
                                          "higher_jaw_m": qh}, ns)
                tf = _transforms(ns, x, y, phi, alpha, ql, qh)
                self._writer.add_message(tf_ch, ns, tf.SerializeToString(), ns)
            start_ns += int((samples[-1][0] + SAMPLE_GAP_S) * 1e9)

    def keyframes(self, outline_m: FloatArray, jaw_size_m: tuple[float, float], frames: list[tuple[float, ...]]) -> None:
        """Foxglove ``/scene`` and ``/tf`` only (nothing simulated: no ``/sim/state``):
        ``frames`` hold (t, x, y, φ, α, q_lower, q_higher) in SI units."""
        from foxglove_schemas_protobuf.FrameTransforms_pb2 import FrameTransforms
        from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate

        scene_ch = self._proto_channel("/scene", SceneUpdate)
        tf_ch = self._proto_channel("/tf", FrameTransforms)
        start_ns = self._t0_ns
        self._writer.add_message(scene_ch, start_ns, _scene(outline_m, jaw_size_m, start_ns).SerializeToString(), start_ns)
        for t, x, y, phi, alpha, ql, qh in frames:
            ns = start_ns + int(t * 1e9)
            self._writer.add_message(tf_ch, ns, _transforms(ns, x, y, phi, alpha, ql, qh).SerializeToString(), ns)


    def belt_trajectories(self, outline_m: FloatArray, walls: list[Any], wall_thickness_m: float,
                          runs: list[list[tuple[float, ...]]]) -> None:
        """A belt validation's runs (conventions §9) as Foxglove ``/scene`` (the part's
        outline in frame ``part``; rails, fences and tail as boxes in ``world``) and ``/tf``
        (world → part). ``runs[k]`` holds (t, x, y, φ) samples in SI units; ``walls`` are
        :class:`algrasp.sim.belt.Wall` (metres)."""
        from foxglove_schemas_protobuf.FrameTransform_pb2 import FrameTransform
        from foxglove_schemas_protobuf.FrameTransforms_pb2 import FrameTransforms
        from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate
        from foxglove_schemas_protobuf.Vector3_pb2 import Vector3
        from google.protobuf.timestamp_pb2 import Timestamp

        scene_ch = self._proto_channel("/scene", SceneUpdate)
        tf_ch = self._proto_channel("/tf", FrameTransforms)
        start_ns = self._t0_ns
        for samples in runs:
            if not samples:
                continue
            scene = _belt_scene(outline_m, walls, wall_thickness_m, start_ns)
            self._writer.add_message(scene_ch, start_ns, scene.SerializeToString(), start_ns)
            for t, x, y, phi in samples:
                ns = start_ns + int(t * 1e9)
                stamp = Timestamp(seconds=ns // 1_000_000_000, nanos=ns % 1_000_000_000)
                tf = FrameTransforms(transforms=[FrameTransform(timestamp=stamp, parent_frame_id="world", child_frame_id="part",
                                                                translation=Vector3(x=x, y=y, z=0.0), rotation=_quat_z(phi))])
                self._writer.add_message(tf_ch, ns, tf.SerializeToString(), ns)
            start_ns += int((samples[-1][0] + SAMPLE_GAP_S) * 1e9)


def _belt_scene(outline_m: FloatArray, walls: list[Any], thick: float, ns: int) -> Any:
    """The part's hull outline (frame ``part``) and every wall as a box (frame ``world``): fences, tail
    chords and the exit guide red, rails grey."""
    from foxglove_schemas_protobuf.Color_pb2 import Color
    from foxglove_schemas_protobuf.CubePrimitive_pb2 import CubePrimitive
    from foxglove_schemas_protobuf.LinePrimitive_pb2 import LinePrimitive
    from foxglove_schemas_protobuf.Point3_pb2 import Point3
    from foxglove_schemas_protobuf.Pose_pb2 import Pose
    from foxglove_schemas_protobuf.SceneEntity_pb2 import SceneEntity
    from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate
    from foxglove_schemas_protobuf.Vector3_pb2 import Vector3
    from google.protobuf.timestamp_pb2 import Timestamp

    stamp = Timestamp(seconds=ns // 1_000_000_000, nanos=ns % 1_000_000_000)
    line = LinePrimitive(type=LinePrimitive.LINE_LOOP, thickness=2.0, scale_invariant=True,
                         points=[Point3(x=float(px), y=float(py), z=0.0) for px, py in outline_m],
                         color=Color(r=0.1, g=0.5, b=0.9, a=1.0), pose=Pose(orientation=_quat_z(0.0)))
    entities = [SceneEntity(timestamp=stamp, frame_id="part", id="part", frame_locked=True, lines=[line])]
    cubes = []
    for w in walls:
        c, s = math.cos(w.alpha), math.sin(w.alpha)
        centre = Vector3(x=w.start[0] + 0.5 * w.length * c + 0.5 * thick * s,
                         y=w.start[1] + 0.5 * w.length * s - 0.5 * thick * c, z=0.0)
        fence = w.name.startswith(("fence", "tail", "exit"))  # the exit guide is cut as a fence is
        cubes.append(CubePrimitive(pose=Pose(position=centre, orientation=_quat_z(w.alpha)),
                                   size=Vector3(x=w.length, y=thick, z=thick),
                                   color=Color(r=0.8, g=0.1, b=0.1, a=0.9) if fence else Color(r=0.6, g=0.6, b=0.6, a=0.8)))
    entities.append(SceneEntity(timestamp=stamp, frame_id="world", id="fences", cubes=cubes))
    return SceneUpdate(entities=entities)


def _quat_z(angle: float) -> Any:
    from foxglove_schemas_protobuf.Quaternion_pb2 import Quaternion

    return Quaternion(x=0.0, y=0.0, z=math.sin(angle / 2), w=math.cos(angle / 2))


def _transforms(ns: int, x: float, y: float, phi: float, alpha: float, ql: float, qh: float) -> Any:
    from foxglove_schemas_protobuf.FrameTransform_pb2 import FrameTransform
    from foxglove_schemas_protobuf.FrameTransforms_pb2 import FrameTransforms
    from foxglove_schemas_protobuf.Vector3_pb2 import Vector3
    from google.protobuf.timestamp_pb2 import Timestamp

    stamp = Timestamp(seconds=ns // 1_000_000_000, nanos=ns % 1_000_000_000)
    rows = [("world", "part", (x, y), phi), ("world", "gripper", (0.0, 0.0), alpha),
            ("gripper", "jaw_lower", (0.0, ql), 0.0), ("gripper", "jaw_higher", (0.0, qh), 0.0)]
    return FrameTransforms(transforms=[
        FrameTransform(timestamp=stamp, parent_frame_id=p, child_frame_id=c,
                       translation=Vector3(x=tx, y=ty, z=0.0), rotation=_quat_z(a)) for p, c, (tx, ty), a in rows])


def _scene(outline_m: FloatArray, jaw_size_m: tuple[float, float], ns: int) -> Any:
    """The part's hull outline (frame ``part``) and the jaws (frames ``jaw_*``)."""
    from foxglove_schemas_protobuf.Color_pb2 import Color
    from foxglove_schemas_protobuf.CubePrimitive_pb2 import CubePrimitive
    from foxglove_schemas_protobuf.LinePrimitive_pb2 import LinePrimitive
    from foxglove_schemas_protobuf.Point3_pb2 import Point3
    from foxglove_schemas_protobuf.Pose_pb2 import Pose
    from foxglove_schemas_protobuf.SceneEntity_pb2 import SceneEntity
    from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate
    from foxglove_schemas_protobuf.Vector3_pb2 import Vector3
    from google.protobuf.timestamp_pb2 import Timestamp

    stamp = Timestamp(seconds=ns // 1_000_000_000, nanos=ns % 1_000_000_000)
    line = LinePrimitive(type=LinePrimitive.LINE_LOOP, thickness=2.0, scale_invariant=True,
                         points=[Point3(x=float(px), y=float(py), z=0.0) for px, py in outline_m],
                         color=Color(r=0.1, g=0.5, b=0.9, a=1.0), pose=Pose(orientation=_quat_z(0.0)))
    entities = [SceneEntity(timestamp=stamp, frame_id="part", id="part", frame_locked=True, lines=[line])]
    length, thick = jaw_size_m
    for name, side in (("jaw_lower", -1.0), ("jaw_higher", 1.0)):
        cube = CubePrimitive(pose=Pose(position=Vector3(x=0.0, y=side * thick / 2, z=0.0), orientation=_quat_z(0.0)),
                             size=Vector3(x=length, y=thick, z=thick), color=Color(r=0.6, g=0.6, b=0.6, a=0.8))
        entities.append(SceneEntity(timestamp=stamp, frame_id=name, id=name, frame_locked=True, cubes=[cube]))
    return SceneUpdate(entities=entities)
