"""What one browser tab owns, the checks on each request, and the work behind the page.

A tab gets a random session id when the page loads (:meth:`SessionStore.new`)
and sends it with every request; its learned skill, its learning job and its
layers live in its :class:`Session`, so several tabs never see each other's
data. The drawing itself (demonstrations, obstacles, marks) stays in the page
and comes with the requests that need it (learn, export), checked field by
field here: every number finite and within :data:`LIMITS`, every count
bounded, every name plain. A bad field is a :class:`RequestError` naming it,
which the page shows as one line.

Everything is lfdkit's own code: learning is :func:`lfdkit.skill.learn` (what
``lfdkit learn`` runs) on the files :func:`lfdkit.io.save_demos` and
:func:`lfdkit.io.save_scenes` write in a private temporary folder, planning
is :meth:`lfdkit.skill.Skill.plan` with :func:`lfdkit.emulate.metrics.clearance`, the
URScript program is :func:`lfdkit.tasks.sweeping.execution.execute_skill`'s.
No file path ever comes from the browser: uploads are written to a private
temporary file whose name the server chooses.

Task frames: when every clean demonstration recorded the same task frames (the
rule of ``demos.csv``), the same learning job also fits a
:class:`lfdkit.skill.TaskFrameSkill` on the clean ones (those not marked
around an obstacle), as ``lfdkit learn demos.csv --task-frames`` does on a
``demos.csv`` of them (same defaults, metres: its file is that command's,
byte for byte), kept beside the obstacle skill
(:attr:`Session.frame_skill`); the obstacle skill is learned as without
frames. Frames that differ between demonstrations, or a fit that fails, cost
the frame skill only (one progress line), never the job.
:func:`frame_plan_response` plans it for the frames' new poses
(:meth:`TaskFrameSkill.plan`, its extrapolation warnings as lines) and
:func:`export_frame_skill` gives its file.
"""

from __future__ import annotations

import contextlib
import math
import re
import secrets
import tempfile
import threading
import time
import warnings
from collections import OrderedDict
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from lfdkit.model.demos import Demo

__all__ = [
    "LIMITS",
    "VIEW",
    "LearnJob",
    "RequestError",
    "Session",
    "SessionStore",
    "TeachData",
    "example_data",
    "export_demos_csv",
    "export_frame_skill",
    "export_plan_csv",
    "export_scenes_csv",
    "export_skill",
    "export_urscript",
    "frame_layer",
    "frame_plan_response",
    "import_demos",
    "import_scenes",
    "parse_frame_plan_request",
    "parse_teach_data",
    "plan_response",
    "skill_layers",
    "start_learning",
]

#: Bounds on what a request may hold (the page shows them; the server enforces them).
LIMITS: dict[str, Any] = {
    "max_body_bytes": 2_000_000,  # any request body, uploads included
    "max_demos": 60,
    "max_points": 5_000,  # per demonstration
    "max_obstacles": 40,
    "max_frames": 8,  # task frames a demonstration records (TaskFrameSkill's)
    "max_coordinate": 100.0,  # metres from the robot base, either way
    "max_radius": 1.0,  # metres
    "max_box_edge": 2.0,  # metres, a box's width or depth
    "max_sessions": 32,  # tabs served at once; the least recently used goes first
    "max_jobs": 2,  # learning jobs at once (the machine's cores)
    "max_heat_cells": 20_000,
    "max_name_chars": 40,
}

#: The canvas's default view, metres: x from -0.7 to 0.7, y from 0 to 0.8 (the
#: robot's base at the origin, the table in front of it, as in the sweeping task).
VIEW: tuple[float, float, float, float] = (-0.7, 0.7, 0.0, 0.8)

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.\-]*$")
_UPLOAD_FORMATS = {"demos": (".csv", ".json", ".npz"), "scenes": (".csv", ".json")}
_LOG_LINES = 200


# warnings.catch_warnings swaps process-wide state: one block at a time (_said_here).
_WARNINGS_LOCK = threading.Lock()


class RequestError(ValueError):
    """A request the page sent that cannot be served; ``message`` is shown in the page."""

    def __init__(self, message: str, status: int = 400) -> None:
        super().__init__(message)
        self.status = status


# ----------------------------------------------------------------- checks
def _mapping(value: Any, name: str) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise RequestError(f"{name}: expected an object, got {_kind(value)}")
    return value


def _list(value: Any, name: str, most: int) -> list[Any]:
    if not isinstance(value, list):
        raise RequestError(f"{name}: expected a list, got {_kind(value)}")
    if len(value) > most:
        raise RequestError(f"{name}: at most {most} allowed, got {len(value)}")
    return value


def _number(value: Any, name: str, bound: float | None = None) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise RequestError(f"{name}: expected a number, got {_kind(value)}")
    number = float(value)
    if not math.isfinite(number):
        raise RequestError(f"{name}: expected a finite number, got {value!r}")
    if bound is not None and abs(number) > bound:
        raise RequestError(f"{name}: expected a number within ±{bound:g}, got {number:g}")
    return number


def _name(value: Any, name: str) -> str:
    if not isinstance(value, str) or not value:
        raise RequestError(f"{name}: expected a non-empty name, got {_kind(value)}")
    if len(value) > LIMITS["max_name_chars"] or not _NAME.match(value):
        raise RequestError(
            f"{name}: {value[:50]!r} is not a plain name (letters, digits, '_', '-', '.', "
            f"at most {LIMITS['max_name_chars']} characters)"
        )
    return value


def _kind(value: Any) -> str:
    if value is None:
        return "nothing"
    if isinstance(value, bool):
        return "true/false"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, str):
        return "text"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, Mapping):
        return "an object"
    return type(value).__name__


def parse_point(value: Any, name: str) -> np.ndarray:
    """A 2-D point ``[x, y]`` in metres, checked."""
    items = _list(value, name, 2)
    if len(items) != 2:
        raise RequestError(f"{name}: expected [x, y], got {len(items)} numbers")
    bound = LIMITS["max_coordinate"]
    point = np.array([_number(v, f"{name}[{i}]") for i, v in enumerate(items)])
    far = np.flatnonzero(np.abs(point) > bound)
    if far.size:  # most often a file in millimetres: say so (lfdkit learn has --units)
        raise RequestError(
            f"{name}[{far[0]}]: expected a number within ±{bound:g} (metres from the robot's "
            f"base), got {point[far[0]]:g}; the page works in metres: convert a file in "
            "millimetres, or learn from it with lfdkit learn --units mm"
        )
    return point


def parse_obstacles(value: Any, name: str = "obstacles") -> list[tuple[str, Any]]:
    """``[{"id", "class", "x", "y", "radius"}, ...]`` as (id, Obstacle) pairs.

    An item with ``"shape": "box"`` is a :class:`lfdkit.model.box.Box` turned by
    ``"yaw"`` (radians, anticlockwise; 0 by default) with edges ``"width"``
    (along its own x) and ``"depth"`` (along its own y), in metres; its
    ``radius`` (0 by default) rounds it.
    """
    from lfdkit.model.box import Box
    from lfdkit.model.scene import Obstacle

    found: list[tuple[str, Any]] = []
    seen: set[str] = set()
    for j, item in enumerate(_list(value, name, LIMITS["max_obstacles"])):
        where = f"{name}[{j}]"
        item = _mapping(item, where)
        key = _name(item.get("id", f"o{j}"), f"{where}.id")
        if key in seen:
            raise RequestError(f"{where}.id: {key!r} is used twice")
        seen.add(key)
        label = _name(item.get("class"), f"{where}.class")
        x = _number(item.get("x"), f"{where}.x", LIMITS["max_coordinate"])
        y = _number(item.get("y"), f"{where}.y", LIMITS["max_coordinate"])
        radius = _number(item.get("radius", 0.0), f"{where}.radius")
        if not 0.0 <= radius <= LIMITS["max_radius"]:
            raise RequestError(
                f"{where}.radius: expected 0 to {LIMITS['max_radius']:g} m, got {radius:g}"
            )
        shape = item.get("shape", "round")
        if shape == "round":
            found.append((key, Obstacle(label, [x, y], radius)))
            continue
        if shape != "box":
            raise RequestError(f"{where}.shape: expected 'round' or 'box', got {_kind(shape)}")
        edges = []
        for edge in ("width", "depth"):
            length = _number(item.get(edge), f"{where}.{edge}")
            if not 0.0 < length <= LIMITS["max_box_edge"]:
                raise RequestError(
                    f"{where}.{edge}: expected more than 0 and at most "
                    f"{LIMITS['max_box_edge']:g} m, got {length:g}"
                )
            edges.append(length)
        yaw = _number(item.get("yaw", 0.0), f"{where}.yaw", 100.0)
        found.append((key, Box.from_yaw(label, [x, y], edges, yaw, radius)))
    return found


def parse_scene(value: Any, name: str = "obstacles") -> Any:
    """The obstacles of a request as a :class:`lfdkit.model.scene.Scene`."""
    from lfdkit.model.scene import Scene

    return Scene(tuple(obstacle for _, obstacle in parse_obstacles(value, name)))


def parse_frames(value: Any, name: str) -> dict[str, np.ndarray] | None:
    """``{frame name: [x, y, angle]}`` (metres, radians) as a demonstration's task frames.

    The poses of the objects the task acts on while it was drawn
    (:attr:`lfdkit.model.demos.Demo.frames`); None or ``{}``: none recorded.
    """
    from lfdkit.io.demos import is_frame_name

    if value is None:
        return None
    items = _mapping(value, name)
    if len(items) > LIMITS["max_frames"]:
        raise RequestError(f"{name}: at most {LIMITS['max_frames']} allowed, got {len(items)}")
    frames: dict[str, np.ndarray] = {}
    for key, pose in items.items():
        if not is_frame_name(key) or len(key) > LIMITS["max_name_chars"]:
            raise RequestError(
                f"{name}: {key!r} cannot name a task frame (letters, digits, '_' and '-', "
                f"starting with a letter or digit; at most {LIMITS['max_name_chars']} characters)"
            )
        at = f"{name}[{key!r}]"
        numbers = _list(pose, at, 3)
        if len(numbers) != 3:
            raise RequestError(f"{at}: expected [x, y, angle], got {len(numbers)} numbers")
        x, y = parse_point(numbers[:2], at)
        frames[key] = np.array([x, y, _number(numbers[2], f"{at}[2]", 100.0)])
    return frames or None


@dataclass
class TeachData:
    """The page's drawing: its demonstrations as :class:`~lfdkit.model.demos.Demo` records.

    Each record holds the points (m), times (s) or None, and id; a
    demonstration marked as swerving around obstacles holds the
    :class:`~lfdkit.model.scene.Scene` of those obstacles, the others (clean
    demonstrations) none; one drawn with task frames on the table, their
    poses (``frames``).
    """

    demos: list[Demo]

    @property
    def ids(self) -> list[str]:
        """The demonstrations' ids, in order."""
        return [demo.id for demo in self.demos]

    @property
    def scenes(self) -> dict[str, Any]:
        """The scene of each marked demonstration, by id."""
        return {demo.id: demo.scene for demo in self.demos if demo.scene is not None}


def parse_teach_data(payload: Any) -> TeachData:
    """Check the drawing a request carries: ``{"demos": [...], "obstacles": [...]}``.

    Each demonstration is ``{"id", "points": [[x, y], ...], "times": [t, ...]
    or null, "obstacles": [obstacle ids it swerved around], "frames": {name:
    [x, y, angle]} or null}``, in metres, seconds and radians. The marks may
    also come as a top-level ``"marks": {demo id: [obstacle ids]}``, the form
    ``GET /api/example`` and the scene imports answer, so that a payload
    posted back as it came keeps its swerves (they were once dropped, and
    every marked stroke learned as clean); both forms are merged, and a mark
    naming no demonstration or obstacle is refused.
    """
    from lfdkit.model.scene import Scene

    payload = _mapping(payload, "request")
    obstacles = dict(parse_obstacles(payload.get("obstacles", [])))
    top_marks = {
        _name(key, "marks"): _list(value, f"marks[{key!r}]", LIMITS["max_obstacles"])
        for key, value in _mapping(payload.get("marks") or {}, "marks").items()
    }
    data = TeachData([])
    seen_ids: set[str] = set()
    for j, item in enumerate(_list(payload.get("demos"), "demos", LIMITS["max_demos"])):
        where = f"demos[{j}]"
        item = _mapping(item, where)
        key = _name(item.get("id"), f"{where}.id")
        if key in seen_ids:
            raise RequestError(f"{where}.id: {key!r} is used twice")
        points = _list(item.get("points"), f"{where}.points", LIMITS["max_points"])
        if len(points) < 3:
            raise RequestError(f"{where}: {len(points)} points; a demonstration needs at least 3")
        path = np.array([parse_point(p, f"{where}.points[{i}]") for i, p in enumerate(points)])
        stamps = item.get("times")
        if stamps is not None:
            stamps = _list(stamps, f"{where}.times", LIMITS["max_points"])
            if len(stamps) != len(points):
                raise RequestError(f"{where}.times: {len(stamps)} times for {len(points)} points")
            stamps = np.array([_number(t, f"{where}.times[{i}]") for i, t in enumerate(stamps)])
            if np.any(np.diff(stamps) <= 0.0):
                raise RequestError(f"{where}.times: must increase strictly")
        marks = _list(item.get("obstacles", []), f"{where}.obstacles", LIMITS["max_obstacles"])
        named = [(f"{where}.obstacles[{i}]", mark) for i, mark in enumerate(marks)]
        named += [(f"marks[{key!r}][{i}]", mark) for i, mark in enumerate(top_marks.get(key, []))]
        around, seen = [], set()
        for at, mark in named:
            mark = _name(mark, at)
            if mark not in obstacles:
                raise RequestError(f"{at}: no obstacle {mark!r}; list it under obstacles")
            if mark not in seen:  # marked in both forms: one obstacle, not two
                seen.add(mark)
                around.append(obstacles[mark])
        seen_ids.add(key)
        frames = parse_frames(item.get("frames"), f"{where}.frames")
        data.demos.append(
            Demo(
                path, stamps, id=key, scene=Scene(tuple(around)) if around else None, frames=frames
            )
        )
    unknown = sorted(set(top_marks) - seen_ids)
    if unknown:
        raise RequestError(
            f"marks: no demonstration {', '.join(map(repr, unknown))}; "
            "mark only demonstrations the request sends"
        )
    return data


# ------------------------------------------------------------------ files
def _write_training_files(data: TeachData, folder: Path) -> tuple[Path, Path | None]:
    """The drawing as the files ``lfdkit learn`` reads (JSON keeps per-demo times)."""
    from lfdkit.io import save_demos, save_scenes

    # points, times, ids (not scenes; nor frames: the skill learned here does not use them)
    records = [Demo(demo.points, demo.times, id=demo.id) for demo in data.demos]
    demos = save_demos(folder / "demos.json", records)
    scenes = None
    if data.scenes:
        scenes = save_scenes(folder / "scenes.csv", data.scenes)
    return demos, scenes


def export_demos_csv(data: TeachData) -> str:
    """``demos.csv`` (:func:`lfdkit.io.save_demos`), with ``t`` when every demo has times.

    With the task frames' poses (``frame_<name>_x, _y, _angle``) where the
    demonstrations recorded them: ``lfdkit learn demos.csv --task-frames``
    learns a :class:`lfdkit.skill.TaskFrameSkill` from it.
    """
    from lfdkit.io import save_demos

    if not data.demos:
        raise RequestError("demos: nothing to export; draw or import demonstrations first")
    with tempfile.TemporaryDirectory(prefix="lfdkit-teach-") as folder:
        path = save_demos(Path(folder) / "demos.csv", _csv_records(data.demos))
        return path.read_text(encoding="utf-8")


def _csv_records(demos: Sequence[Demo]) -> list[Demo]:
    """The records ``demos.csv`` holds: points, times (all or none), ids, the common frames.

    What :func:`export_demos_csv` writes and what the task-frame skill is
    learned from, so that the page's frame skill is the one ``lfdkit learn
    demos.csv --task-frames`` learns. Raises :class:`RequestError` where the
    demonstrations recorded different task frames (:func:`_common_frames`).
    """
    names = _common_frames(demos)
    timed = all(demo.times is not None for demo in demos)  # a CSV has all or none
    return [
        Demo(
            demo.points,
            demo.times if timed else None,
            id=demo.id,
            frames={name: demo.frames[name] for name in names} if names else None,
        )
        for demo in demos
    ]


def _common_frames(demos: Sequence[Demo]) -> list[str]:
    """The task frames every demonstration recorded, in the first one's order (``[]``: none).

    A CSV gives each demonstration the same frames' columns
    (``frame_<name>_x, _y, _angle``, what ``lfdkit learn --task-frames`` reads).
    """
    names = list(demos[0].frames or {})
    for demo in demos:
        have = list(demo.frames or {})
        if sorted(have) != sorted(names):
            raise RequestError(
                f"frames: demonstration {demo.id!r} recorded the task frames "
                f"{', '.join(have) or 'none'}, {demos[0].id!r} {', '.join(names) or 'none'}; "
                "every demonstration of a file (and of a task-frame skill) records the same "
                "ones: delete the strokes drawn before a frame was placed (or after one was "
                "removed)"
            )
    return names


def export_scenes_csv(data: TeachData) -> str:
    """``scenes.csv`` (:func:`lfdkit.io.save_scenes`): each marked demonstration's obstacles."""
    from lfdkit.io import save_scenes

    if not data.scenes:
        raise RequestError(
            "scenes: no demonstration is marked as swerving around an obstacle; nothing to export"
        )
    with tempfile.TemporaryDirectory(prefix="lfdkit-teach-") as folder:
        path = save_scenes(Path(folder) / "scenes.csv", data.scenes)
        return path.read_text(encoding="utf-8")


def _upload_suffix(kind: str, fmt: Any) -> str:
    suffixes = _UPLOAD_FORMATS[kind]
    suffix = f".{fmt}".lower() if isinstance(fmt, str) else ""
    if suffix not in suffixes:
        raise RequestError(
            f"format: a {kind} file must be {', '.join(s[1:] for s in suffixes)}, got {fmt!r}"
        )
    return suffix


def _read_upload(body: bytes, suffix: str, reader: Callable[[Path], Any], what: str) -> Any:
    """Read uploaded bytes with an lfdkit reader, from a private file the server names."""
    if not body:
        raise RequestError(f"{what}: the file is empty")
    with tempfile.TemporaryDirectory(prefix="lfdkit-teach-") as folder:
        path = Path(folder) / f"upload{suffix}"
        path.write_bytes(body)
        try:
            return reader(path)
        except (ValueError, TypeError, OSError) as exc:
            # The message names the private file; the page knows it as "the uploaded file".
            text = str(exc).replace(str(path), f"the {what} file").splitlines()[0]
            raise RequestError(text) from None


def _obstacle_json(key: str, obstacle: Any) -> dict[str, Any]:
    """The page's form of a round obstacle or a 2-D box (see :func:`parse_obstacles`)."""
    item = {
        "id": key,
        "class": obstacle.label,
        "x": float(obstacle.position[0]),
        "y": float(obstacle.position[1]),
        "radius": float(obstacle.radius),
    }
    if obstacle.shape == "box":
        qz, qw = (float(v) for v in obstacle.orientation[2:])
        item.update(
            shape="box",
            width=float(obstacle.size[0]),
            depth=float(obstacle.size[1]),
            yaw=2.0 * math.atan2(qz, qw),
        )
    return item


def _demos_json(records: Sequence[Demo]) -> list:
    """Demonstration records as the page's demos (their task frames' poses too)."""
    out = []
    for demo in records:
        key, stamps = demo.id, demo.times
        if demo.points.shape[1] != 2:
            raise RequestError(
                f"demo {key!r}: is {demo.points.shape[1]}-D; the page draws 2-D paths"
            )
        out.append(
            {
                "id": str(key),
                "points": demo.points.tolist(),
                "times": None if stamps is None else (stamps - stamps[0]).tolist(),
                "obstacles": [],
                "frames": None
                if demo.frames is None
                else {name: pose.tolist() for name, pose in demo.frames.items()},
            }
        )
    if len(out) > LIMITS["max_demos"]:
        raise RequestError(f"demos: at most {LIMITS['max_demos']} allowed, got {len(out)}")
    return out


def import_demos(body: bytes, fmt: Any) -> dict[str, Any]:
    """An uploaded demonstrations file (``csv``, ``json`` or ``npz``) as the page's demos.

    Task frames recorded in the file (``frame_<name>_x, _y, _angle``) come with
    each demonstration.
    """
    from lfdkit.io import load_demos

    suffix = _upload_suffix("demos", fmt)
    records = _read_upload(
        body, suffix, lambda path: load_demos(path, as_records=True), "demonstrations"
    )
    result = {"demos": _demos_json(records)}
    # The page's learning checks (parse_teach_data) at import: a file the page
    # would refuse to learn from is refused now, with the same message.
    parse_teach_data({"demos": result["demos"], "obstacles": []})
    return result


def _scenes_json(scenes: Mapping[Any, Any]) -> dict[str, Any]:
    """Scenes by demo id as the page's obstacles (one per distinct obstacle) and marks."""
    obstacles: dict[tuple, str] = {}
    kept: dict[str, Any] = {}
    marks: dict[str, list[str]] = {}
    for key, scene in scenes.items():
        for obstacle in scene:
            if obstacle.shape not in ("round", "box") or obstacle.n_dims != 2:
                raise RequestError(
                    f"scene of demo {key!r}: the page draws round obstacles and boxes in 2-D, "
                    f"got a {obstacle.n_dims}-D {obstacle.shape} one"
                )
            spot = (
                obstacle.label,
                obstacle.shape,
                *obstacle.position.tolist(),
                obstacle.radius,
                *np.asarray(obstacle.fields().get("size", ())).tolist(),
                *(obstacle.fields().get(k) for k in ("qz", "qw")),
            )
            name = obstacles.setdefault(spot, f"o{len(obstacles) + 1}")
            kept.setdefault(name, obstacle)
            marks.setdefault(str(key), []).append(name)
    if len(obstacles) > LIMITS["max_obstacles"]:
        raise RequestError(
            f"obstacles: at most {LIMITS['max_obstacles']} allowed, got {len(obstacles)}"
        )
    listed = [_obstacle_json(name, obstacle) for name, obstacle in kept.items()]
    parse_obstacles(listed)  # the page's learning checks (size, position), at import
    return {"obstacles": listed, "marks": marks}


def import_scenes(body: bytes, fmt: Any) -> dict[str, Any]:
    """An uploaded scene file (``csv`` or ``json``): its obstacles and which demo each marks."""
    from lfdkit.io import load_scenes

    suffix = _upload_suffix("scenes", fmt)
    return _scenes_json(_read_upload(body, suffix, load_scenes, "scene"))


def example_data() -> dict[str, Any]:
    """The shipped sweeping example (:func:`lfdkit.tasks.sweeping.example_files`) for the page."""
    from lfdkit.io import load_demos, load_scenes
    from lfdkit.tasks.sweeping import example_files

    files = example_files()
    out = {"demos": _demos_json(load_demos(files["demos"], as_records=True))}
    out.update(_scenes_json(load_scenes(files["scenes"])))
    return out


# ---------------------------------------------------------------- learning
@dataclass
class LearnJob:
    """One learning run: its state, its progress lines and, when it failed, why."""

    state: str = "running"  # "running", "done" or "failed"
    lines: list[str] = field(default_factory=list)
    started: float = field(default_factory=time.perf_counter)
    seconds: float | None = None
    error: str | None = None
    warnings: list[str] = field(default_factory=list)

    def say(self, message: str) -> None:
        elapsed = time.perf_counter() - self.started
        self.lines.append(f"{elapsed:6.1f} s  {message}")
        del self.lines[:-_LOG_LINES]

    def status(self) -> dict[str, Any]:
        elapsed = self.seconds if self.seconds is not None else time.perf_counter() - self.started
        return {
            "state": self.state,
            "lines": list(self.lines),
            "elapsed": elapsed,
            "error": self.error,
            "warnings": list(self.warnings),
        }


@dataclass
class Session:
    """One tab's server-side state: its skills, the layers to show, its learning job.

    ``skill`` is the obstacle skill (:class:`lfdkit.skill.Skill`), ``frame_skill``
    the :class:`lfdkit.skill.TaskFrameSkill` learned beside it from the clean
    demonstrations when every one of them recorded the same task frames (None otherwise).
    """

    id: str
    skill: Any = None
    frame_skill: Any = None
    layers: dict[str, Any] | None = None
    job: LearnJob | None = None
    used: float = field(default_factory=time.monotonic)
    lock: threading.Lock = field(default_factory=threading.Lock)

    @property
    def busy(self) -> bool:
        return self.job is not None and self.job.state == "running"

    def fitted(self) -> Any:
        if self.skill is None:
            raise RequestError("no skill learned yet in this tab; draw demonstrations and learn")
        return self.skill

    def frame_fitted(self) -> Any:
        """The task-frame skill, or a :class:`RequestError` saying how to get one."""
        if self.frame_skill is None:
            raise RequestError(
                "frames: no task-frame skill learned in this tab; place a task frame (⊹), draw "
                "every demonstration with it on the table (moved and turned between strokes) "
                "and learn"
            )
        return self.frame_skill

    def exportable(self) -> Any:
        """The skill, for a file that leaves the page: refused where ``lfdkit learn`` refuses it.

        A reward fit that did not converge can be tried in the page (its
        warning shows), but no skill, plan or robot program is written from it.
        """
        skill = self.fitted()
        fit = skill.ioc_info_ or {}
        if not fit.get("converged", True):
            raise RequestError(
                "the obstacle reward fit did not converge, so this skill is not exported "
                "(`lfdkit learn` refuses it too): add demonstrations around the obstacles "
                "and learn again"
            )
        return skill


class SessionStore:
    """The sessions of the tabs served, at most ``max_sessions`` (least recently used go)."""

    def __init__(self, max_sessions: int | None = None, max_jobs: int | None = None) -> None:
        self.max_sessions = int(max_sessions or LIMITS["max_sessions"])
        self.jobs = threading.BoundedSemaphore(int(max_jobs or LIMITS["max_jobs"]))
        self._sessions: OrderedDict[str, Session] = OrderedDict()
        self._lock = threading.Lock()

    def __len__(self) -> int:
        return len(self._sessions)

    def new(self) -> Session:
        session = Session(secrets.token_urlsafe(18))
        with self._lock:
            self._sessions[session.id] = session
            idle = [key for key, s in self._sessions.items() if not s.busy]
            while len(self._sessions) > self.max_sessions and idle:
                del self._sessions[idle.pop(0)]
        return session

    def get(self, key: Any) -> Session:
        with self._lock:
            session = self._sessions.get(key) if isinstance(key, str) else None
            if session is None:
                raise RequestError(
                    "this tab's session has ended (the server restarted or too many tabs are "
                    "open); reload the page",
                    status=410,
                )
            self._sessions.move_to_end(key)
            session.used = time.monotonic()
            return session


def _learn_params(payload: Mapping[str, Any]) -> dict[str, Any]:
    from lfdkit.core.options import PLANNERS, SKILL_DEFAULTS

    params = _mapping(payload.get("params", {}), "params")
    mimic = params.get("mimic", SKILL_DEFAULTS["mimic"])
    planner = params.get("planner", SKILL_DEFAULTS["planner"])
    from lfdkit.mimic import MIMIC_METHODS

    if mimic not in MIMIC_METHODS:
        raise RequestError(f"params.mimic: expected one of {', '.join(MIMIC_METHODS)}")
    if planner not in PLANNERS:
        raise RequestError(f"params.planner: expected one of {', '.join(PLANNERS)}")
    return {"mimic": mimic, "planner": planner, "units": "m"}


def start_learning(store: SessionStore, session: Session, payload: Any) -> LearnJob:
    """Check the drawing and learn from it in a worker thread; the job reports progress.

    Raises
    ------
    RequestError
        For a bad drawing (checked before the thread starts), a tab that is
        already learning, or when the server is learning for other tabs already.
    """
    data = parse_teach_data(payload)
    params = _learn_params(payload)
    clean = sum(1 for demo in data.demos if demo.scene is None)
    if clean < 2:
        raise RequestError(
            f"demos: {clean} clean demonstrations (not marked around an obstacle); the path is "
            "learned from at least 2"
        )
    with session.lock:
        if session.busy:
            raise RequestError("this tab is learning already; wait for it to finish", 409)
        if not store.jobs.acquire(blocking=False):
            raise RequestError("the server is learning for other tabs; try again shortly", 429)
        job = session.job = LearnJob()
    thread = threading.Thread(
        target=_learn_worker, args=(store, session, job, data, params), daemon=True
    )
    thread.start()
    return job


def _learn_worker(
    store: SessionStore, session: Session, job: LearnJob, data: TeachData, params: dict
) -> None:
    from lfdkit.skill import learn

    try:
        with tempfile.TemporaryDirectory(prefix="lfdkit-teach-") as folder:
            demos_path, scenes_path = _write_training_files(data, Path(folder))
            # Exactly what `lfdkit learn` runs, on the same kind of files.
            skill = learn(demos_path, scenes_path, progress=job.say, **params)
        fit = skill.ioc_info_ or {}
        if not fit.get("converged", True):
            job.warnings.append(
                f"the obstacle reward fit did not converge ({fit.get('convergence_message')}); "
                "`lfdkit learn` would refuse this skill: try it here, but it is not exported; "
                "add demonstrations around the obstacles"
            )
        job.warnings += [str(w) for w in skill.mimic_info_.get("warnings", [])]
        frame_skill = _learn_frame_skill(data, job)
        job.say("layers: distance space, classes; first plan (compiles the planner once)")
        layers = skill_layers(skill, data)
        layers["task_frames"] = None if frame_skill is None else frame_layer(frame_skill, data)
        skill.plan()  # the first plan compiles the planner: here, not on the first drag
        with session.lock:
            session.skill, session.frame_skill, session.layers = skill, frame_skill, layers
            job.seconds = time.perf_counter() - job.started
            job.say(f"done in {job.seconds:.1f} s")
            job.state = "done"
    except Exception as exc:  # every failure ends as a line in the page
        message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        if not isinstance(exc, (ValueError, TypeError)):
            message = f"unexpected {type(exc).__name__}: {message}"
        job.error = message
        job.seconds = time.perf_counter() - job.started
        job.say(f"failed: {message}")
        job.state = "failed"
    finally:
        store.jobs.release()


@contextlib.contextmanager
def _said_here() -> Iterator[list[str]]:
    """The warnings lfdkit raises at calls made on this module's lines, one line each.

    Filled when the block ends. :class:`~lfdkit.skill.TaskFrameSkill` warns at
    its caller (``stacklevel``): those are this module's. A warning another
    thread raised meanwhile is handed on, as it would have gone.
    """
    lines: list[str] = []
    with _WARNINGS_LOCK, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield lines
    for said in caught:
        if said.filename == __file__:
            lines.append(str(said.message).splitlines()[0])
        else:
            warnings.warn_explicit(said.message, said.category, said.filename, said.lineno)


def _learn_frame_skill(data: TeachData, job: LearnJob) -> Any:
    """The :class:`~lfdkit.skill.TaskFrameSkill` of the drawing's task frames, or None.

    Fitted on the clean demonstrations (those not marked around an obstacle:
    they show the task in its frames, as they give the obstacle skill its
    path; a swerve round a cup is not part of it), as ``demos.csv`` holds
    them (:func:`_csv_records`), with ``lfdkit learn --task-frames``'s
    defaults, in metres: its file is that command's for a ``demos.csv`` of
    those strokes. No frames recorded: None, silently. Frames that differ
    between the clean demonstrations, or a fit that fails: None and one
    progress line why (the obstacle skill is learned all the same). The
    fit's warnings (EM not converged, a frame that never moved) join the job's.
    """
    from lfdkit.app.cli.task_frames import DEFAULT_COMPONENTS
    from lfdkit.skill import TaskFrameSkill

    clean = [demo for demo in data.demos if demo.scene is None]
    if not any(demo.frames for demo in clean):
        return None
    try:
        records = _csv_records(clean)
    except RequestError as exc:
        job.say(f"task frames: no task-frame skill: {exc}")
        return None
    names = list(records[0].frames or {})
    marked = len(data.demos) - len(clean)
    left_out = f" ({marked} marked around obstacles left out)" if marked else ""
    job.say(
        f"task frames: a task-frame skill (TP-GMM) in {', '.join(names)} from "
        f"{len(clean)} clean strokes{left_out}"
    )
    skill = TaskFrameSkill(n_components=DEFAULT_COMPONENTS, units="m")
    try:
        with _said_here() as said:
            skill.fit(records)
    except Exception as exc:  # the frame skill's failure, never the job's
        text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        if not isinstance(exc, (ValueError, TypeError)):
            text = f"unexpected {type(exc).__name__}: {text}"
        job.say(f"task frames: no task-frame skill: {text}")
        return None
    job.warnings += [f"task-frame skill: {line}" for line in said]
    job.say(f"task frames: {skill.summary()}")
    return skill


def frame_layer(skill: Any, data: TeachData) -> dict[str, Any]:
    """What the page shows of a task-frame skill: its frames, where to start them, a summary.

    ``poses``: each frame's pose ``[x, y, angle]`` (m, rad) as the last clean
    demonstration (one the skill learned from) recorded it, where the page puts
    the frames to try first.
    """
    last = next(d.frames for d in reversed(data.demos) if d.scene is None and d.frames)
    return {
        "frames": list(skill.frame_names_),
        "poses": {name: np.asarray(last[name], float).tolist() for name in skill.frame_names_},
        "summary": skill.summary(),
        "duration": skill.duration_,
    }


def _left_normals(path: np.ndarray) -> np.ndarray:
    tangents = np.gradient(path, axis=0)
    tangents /= np.maximum(np.linalg.norm(tangents, axis=1, keepdims=True), 1e-300)
    return np.column_stack((-tangents[:, 1], tangents[:, 0]))


def skill_layers(skill: Any, data: TeachData) -> dict[str, Any]:
    """The layers the page shows: path, Distance-Space, reward parameters, timing, fit.

    The Distance-Space (thesis Fig 4.7b) is each clean demonstration's signed
    distance along the generalized path's left normal
    (:func:`lfdkit.emulate.metrics.distance_space`), None where the normal misses it.
    Each class's reward term is ``exp(-(x - O)ᵀ P (x - O))``: its ``reach``
    is ``1/sqrt(λ)`` along each eigenvector of ``P`` (where the term has
    fallen to 1/e), in metres.
    """
    from lfdkit.emulate import metrics
    from lfdkit.mimic import MIMIC_METHODS

    path = skill.path_
    normals = _left_normals(path)
    clean = [demo.points for demo in data.demos if demo.scene is None]
    vectors = metrics.distance_space(path, clean, same_direction=False)
    signed = np.einsum("jmq,mq->jm", vectors, normals)
    distance_space = [[None if not math.isfinite(v) else float(v) for v in row] for row in signed]
    classes = []
    reward = skill.reward_
    if reward is not None:
        for name in reward.classes:
            precision = np.asarray(reward.precisions[name], dtype=float)
            values, vectors_p = np.linalg.eigh(precision)
            reach = [1.0 / math.sqrt(v) if v > 0 else None for v in values]
            classes.append(
                {
                    "name": name,
                    "precision": precision.tolist(),
                    "reach": reach,
                    "axes": vectors_p.T.tolist(),
                }
            )
    info = skill.ioc_info_ or {}
    mimic = skill.mimic_info_
    return {
        "units": skill.units,
        "path": path.tolist(),
        "normals": normals.tolist(),
        "distance_space": distance_space,
        "nominal_weight": None if reward is None else float(reward.nominal_weight),
        "classes": classes,
        "timing": {"duration": float(skill.timing_.duration), "source": skill.timing_.source},
        "fit": {
            "mimic": MIMIC_METHODS[skill.mimic].label,
            "n_clean": int(mimic.get("n_demos", len(clean))),
            "reversed": [int(j) for j in mimic.get("reversed", [])],
            "n_obstacle": int(info.get("n_demos", 0)),
            "loss": info.get("loss"),
            "converged": info.get("converged"),
            "not_learned": list(info.get("not_learned", [])),
        },
        "dmp_basis": int(skill.dmp_.n_basis_),
    }


# ---------------------------------------------------------------- planning
@dataclass
class PlanRequest:
    """A checked plan request: start, goal, the scene and the heat map's grid."""

    start: np.ndarray | None
    goal: np.ndarray | None
    scene: Any
    heat: tuple[tuple[float, float, float, float], int, int] | None


def parse_plan_request(payload: Any) -> PlanRequest:
    payload = _mapping(payload, "request")
    start = payload.get("start")
    goal = payload.get("goal")
    start = None if start is None else parse_point(start, "start")
    goal = None if goal is None else parse_point(goal, "goal")
    scene = parse_scene(payload.get("obstacles", []))
    heat = payload.get("heat")
    grid = None
    if heat:
        heat = _mapping(heat, "heat")
        view = _list(heat.get("view", list(VIEW)), "heat.view", 4)
        if len(view) != 4:
            raise RequestError("heat.view: expected [xmin, xmax, ymin, ymax]")
        x0, x1, y0, y1 = (
            _number(v, f"heat.view[{i}]", LIMITS["max_coordinate"]) for i, v in enumerate(view)
        )
        if not (x1 > x0 and y1 > y0):
            raise RequestError("heat.view: expected xmin < xmax and ymin < ymax")
        nx = _number(heat.get("nx", 100), "heat.nx")
        ny = _number(heat.get("ny", 60), "heat.ny")
        if nx != int(nx) or ny != int(ny) or nx < 2 or ny < 2:
            raise RequestError("heat: nx and ny must be whole numbers of at least 2")
        if nx * ny > LIMITS["max_heat_cells"]:
            raise RequestError(f"heat: at most {LIMITS['max_heat_cells']} cells, got {nx * ny:g}")
        grid = ((x0, x1, y0, y1), int(nx), int(ny))
    return PlanRequest(start, goal, scene, grid)


def _downsample(points: np.ndarray, most: int = 120) -> np.ndarray:
    if len(points) <= most:
        return points
    keep = np.unique(np.linspace(0, len(points) - 1, most).round().astype(int))
    return points[keep]


def heat_map(skill: Any, nominal: np.ndarray, scene: Any, grid: tuple) -> dict[str, Any]:
    """The learned reward on a grid (row by row from ``ymin``), scaled to 0..1.

    As :func:`lfdkit.app.plot.draw_reward`, the colour scale starts one unit (an
    obstacle's height) below the lowest reward at an obstacle centre, so the
    steep nominal term far from the path does not wash out the obstacles.
    """
    (x0, x1, y0, y1), nx, ny = grid
    reward = skill.reward_
    if reward is None:
        from lfdkit.emulate import Reward

        reward = Reward(1.0, {})
    gx, gy = np.meshgrid(np.linspace(x0, x1, nx), np.linspace(y0, y1, ny))
    values = reward.value(np.column_stack((gx.ravel(), gy.ravel())), nominal, scene)
    top, bottom = float(values.max()), float(values.min())
    low = bottom
    if len(scene):
        low = max(bottom, float(reward.value(scene.positions, nominal, scene).min()) - 1.0)
    span = max(top - low, 1e-12)
    scaled = np.clip((values - low) / span, 0.0, 1.0).reshape(ny, nx)
    return {
        "view": [x0, x1, y0, y1],
        "nx": nx,
        "ny": ny,
        "low": low,
        "high": top,
        "values": np.round(scaled, 3).tolist(),
    }


def plan_response(session: Session, payload: Any) -> dict[str, Any]:
    """Plan with the tab's skill (:meth:`Skill.plan`) and measure the plan against the scene."""
    from lfdkit.emulate import metrics

    request = parse_plan_request(payload)
    skill = session.fitted()
    started = time.perf_counter()
    timed = skill.plan(request.start, request.goal, request.scene)
    plan_ms = 1e3 * (time.perf_counter() - started)
    nominal = _downsample(skill.nominal(request.start, request.goal))
    clearance = metrics.clearance(timed.points, request.scene)
    out: dict[str, Any] = {
        "points": timed.points.tolist(),
        "times": timed.times.tolist(),
        "duration": float(timed.duration),
        "peak_speed": float(timed.speeds.max()),
        "nominal": nominal.tolist(),
        "clearance": clearance.tolist(),
        "min_clearance": float(clearance.min()) if len(clearance) else None,
        "collisions": metrics.collisions(timed.points, request.scene),
        "goal_error": float(timed.details.goal_error),
        "plan_ms": plan_ms,
    }
    out["collision_free"] = out["collisions"] == 0
    if request.heat is not None:
        # A picture: the nominal at 60 points is close enough and twice as fast.
        out["heat"] = heat_map(skill, _downsample(nominal, 60), request.scene, request.heat)
    return out


def parse_frame_plan_request(payload: Any, names: Sequence[str]) -> dict[str, np.ndarray]:
    """``{"frames": {name: [x, y, angle]}}`` (m, rad) with exactly the skill's frames, checked.

    Parameters
    ----------
    payload : object
        The request's JSON.
    names : sequence of str
        The task-frame skill's frames (:attr:`TaskFrameSkill.frame_names_`).

    Returns
    -------
    dict of str to ndarray, shape (3,)
        Each frame's pose, as :func:`parse_frames` reads a demonstration's.
    """
    payload = _mapping(payload, "request")
    frames = parse_frames(payload.get("frames"), "frames") or {}
    missing = [name for name in names if name not in frames]
    unknown = [name for name in frames if name not in names]
    if unknown:
        raise RequestError(
            f"frames: no task frame {', '.join(map(repr, unknown))} in this skill; give the "
            f"poses of {', '.join(names)} only"
        )
    if missing:
        raise RequestError(
            f"frames: missing {', '.join(map(repr, missing))}; give the pose of each frame of "
            f"this skill ({', '.join(names)}) as [x, y, angle] (metres, radians)"
        )
    return frames


def frame_plan_response(session: Session, payload: Any) -> dict[str, Any]:
    """Plan the tab's task-frame skill (:meth:`TaskFrameSkill.plan`) for the frames' poses.

    Returns
    -------
    dict
        ``points`` (n, 2) m and ``times`` (n,) s, downsampled as the obstacle
        plan's nominal (at most 120 points; the skill plans 100); ``duration``
        s; ``warnings``: one line each (a frame posed beyond the
        demonstrations' poses: the plan extrapolates); ``plan_ms``.
    """
    skill = session.frame_fitted()
    frames = parse_frame_plan_request(payload, skill.frame_names_)
    # Drawn without times (an imported file): as long as the obstacle skill's plan.
    duration = None if skill.duration_ is not None else float(session.fitted().timing_.duration)
    started = time.perf_counter()
    with _said_here() as said:
        timed = skill.plan(frames, duration=duration)
    plan_ms = 1e3 * (time.perf_counter() - started)
    keep = _downsample(np.arange(len(timed.times)))
    return {
        "frames": {name: pose.tolist() for name, pose in frames.items()},
        "points": timed.positions[keep].tolist(),
        "times": timed.times[keep].tolist(),
        "duration": float(timed.times[-1]),
        "warnings": said,
        "plan_ms": plan_ms,
    }


# ----------------------------------------------------------------- exports
def export_frame_skill(session: Session) -> bytes:
    """The task-frame skill's file (:meth:`TaskFrameSkill.save`'s bytes, ``lfdkit learn``'s)."""
    skill = session.frame_fitted()
    with tempfile.TemporaryDirectory(prefix="lfdkit-teach-") as folder:
        return skill.save(Path(folder) / "task-frame-skill.json").read_bytes()


def export_skill(session: Session) -> bytes:
    """The skill file :meth:`Skill.save` writes, byte for byte."""
    skill = session.exportable()
    with tempfile.TemporaryDirectory(prefix="lfdkit-teach-") as folder:
        return skill.save(Path(folder) / "skill.json").read_bytes()


def export_plan_csv(session: Session, payload: Any) -> str:
    """The plan as ``t,x,y`` CSV (:func:`lfdkit.io.path_csv`), as ``lfdkit plan`` writes it."""
    from lfdkit.io import path_csv

    request = parse_plan_request(payload)
    timed = session.exportable().plan(request.start, request.goal, request.scene)
    return path_csv(timed.points, times=timed.times)


def export_urscript(session: Session, payload: Any) -> str:
    """The UR5 ``servoj`` program of the plan (:func:`~lfdkit.tasks.sweeping.execute_skill`).

    The sweep is planned again with the brush's clearance, carried to the
    arm's poses and joints and timed; what the arm cannot do is a
    :class:`RequestError` with the reason (no simulation).
    """
    from lfdkit.tasks.sweeping.execution import execute_skill

    request = parse_plan_request(payload)
    execution = execute_skill(
        session.exportable(),
        request.start,
        request.goal,
        request.scene,
        simulate=False,
        header="lfdkit teach: a skill drawn in the browser",
    )
    return execution.program
