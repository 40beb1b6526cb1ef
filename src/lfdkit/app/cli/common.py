"""What several commands share: errors, messages, progress, argument types, option groups."""

from __future__ import annotations

import argparse
import logging
import math
import os
import re
import sys
import tempfile
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, NamedTuple

from lfdkit.core.kernels import use_compiled
from lfdkit.core.numbers import parse_decimal, parse_whole
from lfdkit.core.options import (
    DEMONSTRATION_SPEED,
    MAX_HORIZON,
    MIN_HORIZON,
    MODELS,
    PLANNERS,
    SKILL_DEFAULTS,
)
from lfdkit.core.progress import COMPILE_NOTE, LOGGER, Progress, kernels_compiled
from lfdkit.core.units import MAX_EXTENT_M, MAX_MEAN_SPEED_M_S, MIN_EXTENT_M, UNITS

__all__ = [
    "CommandError",
    "LazyChoices",
    "UnknownClass",
    "UsageError",
    "add_force_option",
    "add_loudness_options",
    "add_orientation_options",
    "add_output_folder_option",
    "add_planner_options",
    "add_seed_option",
    "add_skill_file_options",
    "add_skill_param_options",
    "add_units_option",
    "add_unknown_class_option",
    "arm_keys",
    "bounded_int",
    "check_writable",
    "elapsed",
    "load_skill_file",
    "option_named",
    "orientation_options",
    "parse_fraction",
    "parse_numbers",
    "parse_quaternion",
    "parse_unknown_class",
    "point_arg",
    "positive_decimal",
    "positive_or_none",
    "refuse_existing",
    "refuse_implausible_metres",
    "skill_and_scene",
    "skill_params",
    "tell",
    "units_refusal",
    "unknown_class_options",
    "working",
]


class CommandError(Exception):
    """A failure to report on one line, with exit code 1."""


class UsageError(CommandError):
    """A wrong use of the command found after parsing (a folder not there): exit code 2."""


def tell(args: argparse.Namespace, message: str, *, level: int = 1) -> None:
    """Progress on stderr: level 1 is shown by default, level 2 only with --verbose."""
    if args.verbosity >= level:
        progress = getattr(args, "progress", None)
        if progress is not None:  # above the bars, without tearing them
            progress.write(message)
        else:
            print(message, file=sys.stderr, flush=True)


def elapsed(args: argparse.Namespace) -> float:
    """Seconds since the command started (the clock of every time it reports)."""
    return time.perf_counter() - args.started


class _StageLines(logging.Handler):
    """``--verbose``: each stage record as one line on stderr, after the command's clock."""

    def __init__(self, args: argparse.Namespace) -> None:
        super().__init__(logging.INFO)
        self.args = args

    def emit(self, record: logging.LogRecord) -> None:
        try:
            indent = "  " * int(getattr(record, "depth", 0))
            line = f"[{elapsed(self.args):6.1f} s] {indent}{record.getMessage()}"
            self.args.progress.write(line)
        except Exception:  # a log line must never end the work
            self.handleError(record)


# The commands that run lfdkit's numba kernels (and so compile them on a first run).
_COMPILING = frozenset({"demo", "learn", "plan", "plot", "execute", "compare", "batch"})
# Of those, the ones making one plan: NumPy's kernels unless LFDKIT_KERNELS=numba (issue 30).
_ONE_PLAN = frozenset({"plan", "plot"})


@contextmanager
def working(args: argparse.Namespace, label: str | None = None) -> Iterator[Progress]:
    """The command's progress while it works: yields the :class:`~lfdkit.core.progress.Progress`.

    On a terminal (stderr a TTY, not ``--quiet``) a bar per stage, under a
    clock of the whole command (``label``, default ``lfdkit COMMAND``),
    redrawn twice a second; with ``--verbose`` each stage's start and wall
    time, and every 2 s how far a long stage has come, as lines
    (:data:`lfdkit.core.progress.LOGGER` records). ``--quiet``: nothing.
    """
    # A bar only on a terminal: in a log file its carriage returns would garble the lines.
    bars = args.verbosity >= 1 and _is_terminal(sys.stderr)
    progress = Progress(bars=bars, log=args.verbosity >= 2)
    args.progress = progress
    handler, saved = None, (LOGGER.level, LOGGER.propagate)
    if args.verbosity >= 2:
        handler = _StageLines(args)
        LOGGER.addHandler(handler)
        LOGGER.setLevel(logging.INFO)
        LOGGER.propagate = False  # the lines are the command's; not twice through the root
    label = label or f"lfdkit {args.command}"
    compiles = args.command in _COMPILING and (args.command not in _ONE_PLAN or use_compiled())
    if compiles and not kernels_compiled():
        # A first run compiles the numba kernels: said, so the bars do not look stuck.
        label = f"{label}: {COMPILE_NOTE}"
        tell(args, f"first run here: {COMPILE_NOTE}", level=1 if bars else 2)
    try:
        with progress.stage(label, announce=False):
            yield progress
    finally:
        progress.close()
        if handler is not None:
            LOGGER.removeHandler(handler)
            LOGGER.setLevel(saved[0])
            LOGGER.propagate = saved[1]
        args.progress = None


def _is_terminal(stream: object) -> bool:
    isatty = getattr(stream, "isatty", None)
    try:
        return bool(isatty()) if callable(isatty) else False
    except (OSError, ValueError):  # closed or detached
        return False


def refuse_existing(path: Path, force: bool, option: str = "--output") -> None:
    """Refuse an output file before the work, not after it.

    Refused: an existing file without ``force``, a missing or read-only folder,
    and anything but a regular file (a device, FIFO or link is never written).
    """
    if path.is_dir():
        raise CommandError(f"{option} {path}: is a directory; give a file name")
    if path.exists() and not force:
        raise CommandError(f"{option} {path}: exists; pass --force to overwrite it")
    if not path.parent.exists():
        raise CommandError(f"{option} {path}: folder {path.parent} does not exist")
    check_writable(path.parent, option, path)
    from lfdkit.io.atomic import NotRegularFileError, check_output_path  # not for --help

    try:  # a device, FIFO or link is never written, --force or not: say so before the work
        check_output_path(path, overwrite=True)
    except NotRegularFileError as exc:
        raise CommandError(f"{option} {exc}") from None


def check_writable(folder: Path, option: str, shown: Path) -> None:
    """Create and remove a probe file in ``folder``: the one test that also holds for root.

    ``os.access`` says yes to root on a read-only mount and knows nothing of
    quotas; the file that is finally written goes through the same call.
    """
    try:
        with tempfile.TemporaryFile(dir=folder, prefix=".lfdkit-probe-"):
            pass
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise CommandError(
            f"{option} {shown}: cannot write in folder {folder} ({reason.lower()})"
        ) from None


def parse_numbers(text: str) -> list[float]:
    try:
        values = [parse_decimal(v, finite=False) for v in text.split(",")]
    except ValueError as exc:
        raise argparse.ArgumentTypeError(
            f"expected numbers separated by commas, got {text!r} ({exc})"
        ) from None
    if len(values) not in (2, 3) or not all(v == v and abs(v) != float("inf") for v in values):
        raise argparse.ArgumentTypeError(
            f"expected 2 or 3 finite numbers like 0.4,0.45, got {text!r}"
        )
    return values


def _quaternion(text: str | None, option: str) -> list[float] | None:
    """``--start-orientation``/``--goal-orientation``: ``qx,qy,qz,qw``, normalised.

    Checked by the command, not by argparse, so that a bad value is one line (exit 2).
    """
    if text is None:
        return None
    try:
        values = [parse_decimal(v, finite=False) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 4 or not all(math.isfinite(v) for v in values):
        raise UsageError(
            f"{option}: expected 4 finite numbers qx,qy,qz,qw (a quaternion, scalar last), "
            f"got {text!r}"
        )
    norm = math.hypot(*values)  # scaled inside: 1e200 components do not overflow
    if norm < 1e-9:
        raise UsageError(f"{option}: a zero quaternion is no orientation, got {text!r}")
    return [v / norm for v in values]


def orientation_options(args: argparse.Namespace) -> dict[str, list[float] | None]:
    """The start and goal orientation options, checked, as :meth:`Skill.plan`'s keywords."""
    return {
        f"{end}_orientation": _quaternion(
            getattr(args, f"{end}_orientation"), f"--{end}-orientation"
        )
        for end in ("start", "goal")
    }


def _whole(text: str) -> int:
    """An argparse type: a whole number in decimal digits (no ``1_000``)."""
    try:
        return parse_whole(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def bounded_int(low: int, high: int) -> Callable[[str], int]:
    """An argparse type: an integer from ``low`` to ``high`` (a usage error otherwise)."""

    def parse(text: str) -> int:
        try:
            value = parse_whole(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"expected {low} to {high:,}, got {text!r}")
        return value

    return parse


#: ``--obstacle`` keys of a box's edge lengths, by axis.
BOX_SIZE_KEYS = ("sx", "sy", "sz")
#: ``--obstacle`` keys of a half-space's normal (to its free side), by axis.
NORMAL_KEYS = ("nx", "ny", "nz")
#: A good half-space, for the errors about a bad one.
NORMAL_EXAMPLE = "e.g. table:0,0,0.7,nx=0,ny=0,nz=1 for a table top at height 0.7"
#: Units of a box's ``yaw=`` (anticlockwise about z) and their size in radians.
YAW_UNITS = {"deg": math.pi / 180.0, "rad": 1.0}


def _obstacle(text: str):
    """An ``--obstacle`` value: round, a box or a half-space (an argparse type).

    ``CLASS:X,Y[,Z][,r=R][,vx=VX,vy=VY[,vz=VZ]]``; a box adds
    ``sx=,sy=[,sz=][,yaw=]`` or is written in a row,
    ``CLASS:CX,CY[,CZ],LX,LY[,LZ][,YAW|,QX,QY,QZ,QW]``; a half-space adds
    ``nx=,ny=[,nz=]``.

    Returns (label, position, radius, velocity, box, normal): ``velocity`` is
    None for a static obstacle, else the list of the given components
    (units/s); ``box`` is None unless a box, else ``(edge lengths, unit
    quaternion [x, y, z, w])``; ``normal`` is None unless a half-space, else its normal's
    components (a direction: not in units, not normalised here).
    """
    label, sep, rest = text.partition(":")
    if not sep or not label.strip():
        raise argparse.ArgumentTypeError(
            f"expected CLASS:X,Y[,Z][,r=RADIUS][,vx=VX,vy=VY] or "
            f"CLASS:X,Y[,Z],sx=SX,sy=SY[,sz=SZ][,yaw=ANGLEdeg] or "
            f"CLASS:X,Y[,Z],nx=NX,ny=NY[,nz=NZ], got {text!r}"
        )
    radius = 0.0
    coords = []
    velocity: dict[str, float] = {}
    sizes: dict[str, float] = {}
    normal: dict[str, float] = {}
    yaw = None
    seen: set[str] = set()
    for token in rest.split(","):
        token = token.strip()
        key = token.partition("=")[0].strip() if "=" in token else None
        if key is not None:
            if key in seen:  # the later one would silently win
                raise argparse.ArgumentTypeError(f"{key}= is given twice in {text!r}; give it once")
            seen.add(key)
        if key in ("vx", "vy", "vz"):
            try:
                value = parse_decimal(token.partition("=")[2])
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise argparse.ArgumentTypeError(f"{key} in {text!r} is not a finite number")
            velocity[key] = value
        elif key in BOX_SIZE_KEYS:
            try:
                value = parse_decimal(token.partition("=")[2])
            except ValueError:
                value = math.nan
            if not value >= 0:  # NaN too
                raise argparse.ArgumentTypeError(
                    f"{key} in {text!r}: a box's edge length must be a finite number >= 0"
                )
            sizes[key] = value
        elif key in NORMAL_KEYS:
            try:
                value = parse_decimal(token.partition("=")[2])
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise argparse.ArgumentTypeError(
                    f"{key} in {text!r}: a half-space's normal component must be a finite "
                    f"number; {NORMAL_EXAMPLE}"
                )
            normal[key] = value
        elif key == "yaw":
            yaw = _yaw(token.partition("=")[2], text)
        elif key == "r":
            try:
                radius = parse_decimal(token.partition("=")[2], finite=False)
            except ValueError:
                raise argparse.ArgumentTypeError(f"radius in {text!r} is not a number") from None
            if not radius >= 0 or radius == float("inf"):
                raise argparse.ArgumentTypeError(f"radius in {text!r} must be finite and >= 0")
        elif key is not None:
            raise argparse.ArgumentTypeError(
                f"unknown key {key}= in {text!r}; expected r=, vx=, vy=, vz=, "
                "or for a box sx=, sy=, sz=, yaw=, or for a half-space nx=, ny=, nz="
            )
        else:
            coords.append(token)
    turn = None
    if len(coords) > 3:
        coords, sizes, yaw, turn = _box_in_a_row(coords, sizes, yaw, normal, text)
    position = parse_numbers(",".join(coords))
    box = None
    if sizes or yaw is not None:
        wanted = list(BOX_SIZE_KEYS[: len(position)])
        extra = sorted(set(sizes) - set(wanted))
        if extra:
            raise argparse.ArgumentTypeError(
                f"{extra[0]}= in {text!r}: a {len(position)}-D box has edges "
                f"{', '.join(w + '=' for w in wanted)} only"
            )
        missing = [w for w in wanted if w not in sizes]
        if missing:
            raise argparse.ArgumentTypeError(
                f"box in {text!r}: missing its edge length {missing[0]}=; a "
                f"{len(position)}-D box needs {', '.join(w + '=' for w in wanted)}"
            )
        if turn is None:  # about z: [x, y, z, w] = [0, 0, sin(yaw/2), cos(yaw/2)]
            angle = 0.0 if yaw is None else yaw
            turn = [0.0, 0.0, math.sin(0.5 * angle), math.cos(0.5 * angle)]
        box = ([sizes[w] for w in wanted], turn)
    normal_vector = _normal(normal, position, text, box is not None, bool(velocity))
    if not velocity:
        return label.strip(), position, radius, None, box, normal_vector
    wanted = ["vx", "vy", "vz"][: len(position)]
    if sorted(velocity) != wanted:
        raise argparse.ArgumentTypeError(
            f"velocity in {text!r}: give {', '.join(w + '=' for w in wanted)} "
            f"for a {len(position)}-D position"
        )
    return label.strip(), position, radius, [velocity[w] for w in wanted], box, None


def _normal(
    given: dict[str, float], position: list[float], text: str, is_box: bool, moves: bool
) -> list[float] | None:
    """A half-space's ``nx=,ny=[,nz=]`` in axis order (None when none is given)."""
    if not given:
        return None
    example = NORMAL_EXAMPLE
    if is_box:
        raise argparse.ArgumentTypeError(
            f"half-space in {text!r}: give either a box's sx=, sy= or a half-space's nx=, ny=, "
            f"not both; {example}"
        )
    if moves:
        raise argparse.ArgumentTypeError(
            f"half-space in {text!r}: a half-space cannot move (drop vx=, vy=, vz=); {example}"
        )
    wanted = list(NORMAL_KEYS[: len(position)])
    keys = ", ".join(w + "=" for w in wanted)
    extra = sorted(set(given) - set(wanted))
    if extra:
        raise argparse.ArgumentTypeError(
            f"{extra[0]}= in {text!r}: a {len(position)}-D half-space's normal has {keys} only; "
            f"{example}"
        )
    missing = [w for w in wanted if w not in given]
    if missing:
        raise argparse.ArgumentTypeError(
            f"half-space in {text!r}: missing its normal component {missing[0]}=; a "
            f"{len(position)}-D half-space needs {keys}; {example}"
        )
    components = [given[w] for w in wanted]
    if not any(components):
        raise argparse.ArgumentTypeError(
            f"half-space in {text!r}: the normal {keys} is zero; give the direction of the "
            f"free side, {example}"
        )
    return components


def _box_in_a_row(
    coords: list[str], sizes: dict[str, float], yaw: float | None, normal: dict, text: str
) -> tuple[list[str], dict[str, float], float | None, list[float] | None]:
    """A box written ``CX,CY[,CZ],LX,LY[,LZ][,YAW|,QX,QY,QZ,QW]``: centre, edges, turn.

    4 or 5 values are a 2-D box (the fifth its yaw, with its unit), 6 or 7 a
    3-D one, 10 a 3-D box and its orientation as a unit quaternion ``x, y, z,
    w``. Returns the centre's tokens, the edges by name, the yaw and the
    quaternion (None: about z by the yaw).
    """
    n = len(coords)
    if sizes or normal or n not in (4, 5, 6, 7, 10):
        raise argparse.ArgumentTypeError(
            f"{n} values in {text!r}: a position has 2 or 3; a box is CX,CY[,CZ],LX,LY[,LZ] "
            "with an optional yaw (e.g. 30deg) or quaternion QX,QY,QZ,QW, or its edges by name "
            "(sx=,sy=[,sz=])"
        )
    q = 2 if n in (4, 5) else 3
    numbers = coords if n == 10 else coords[: 2 * q]
    try:
        values = [parse_decimal(v) for v in numbers]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: a box's values must be numbers") from None
    edges = values[q : 2 * q]
    if not all(v >= 0 for v in edges):
        raise argparse.ArgumentTypeError(
            f"{text!r}: a box's edge lengths must be finite numbers >= 0"
        )
    named = dict(zip(BOX_SIZE_KEYS, edges, strict=False))
    if n in (5, 7):
        if yaw is not None:
            raise argparse.ArgumentTypeError(f"yaw is given twice in {text!r}; give it once")
        return coords[:q], named, _yaw(coords[-1], text), None
    if n == 10:
        if yaw is not None:
            raise argparse.ArgumentTypeError(
                f"{text!r}: give the box's quaternion or its yaw, not both"
            )
        from lfdkit.core.rotations import check_quaternions

        try:
            turn = check_quaternions(values[6:10], "quaternion", n=1)[0]
        except ValueError as exc:
            raise argparse.ArgumentTypeError(f"{text!r}: {exc}") from None
        return coords[:q], named, None, [float(v) for v in turn]
    return coords[:q], named, yaw, None


def _yaw(value: str, text: str) -> float:
    """A box's ``yaw=`` value (``30deg`` or ``0.52rad``: the unit is required) in radians."""
    value = value.strip()
    unit = next((u for u in YAW_UNITS if value.endswith(u)), None)
    if unit is None:
        raise argparse.ArgumentTypeError(
            f"yaw in {text!r} has no unit; write it as e.g. yaw=30deg or yaw=0.52rad"
        )
    try:
        angle = parse_decimal(value[: -len(unit)])
    except ValueError:
        raise argparse.ArgumentTypeError(f"yaw in {text!r} is not a finite number") from None
    return angle * YAW_UNITS[unit]


def skill_params(args: argparse.Namespace) -> dict:
    """The :class:`~lfdkit.skill.Skill` parameters of ``learn``'s options (defaults the Skill's).

    ``units`` only when ``--units`` was given: without it the Skill's default
    (metres) holds, and demonstrations implausible in metres are refused
    (:func:`units_refusal`).
    """
    params = {
        "mimic": args.mimic,
        "n_points": args.n_points,
        "random_state": args.seed,
        "planner": args.planner,
        "horizon": args.horizon,
        "model": args.model,
        "duration": args.duration,
    }
    if args.units is not None:
        params["units"] = args.units
    return params


def units_refusal(source: object, warning: Warning, units: str) -> str:
    """The one line that refuses demonstrations implausible in ``units`` when no --units was given.

    ``warning`` is the :class:`lfdkit.core.units.UnitsWarning` the skill raised.
    """
    likely = getattr(warning, "likely", None)
    detail = getattr(warning, "detail", str(warning)).removeprefix("demos: ")
    return _units_line(source, detail, likely, units)


def _units_line(source: object, detail: str, likely: str | None, units: str) -> str:
    return (
        f"{source}: {detail}; no --units was given, so they were read as {units}: "
        f"pass --units {likely} if that is their unit (--units {units} to learn them as they are)"
    )


def refuse_implausible_metres(source: object, paths: Any, times: Any) -> None:
    """Demonstrations (``paths``, ``times`` per path or None) refused when implausible in metres.

    Their largest extent along an axis and the fastest one's mean speed
    (path length over duration; untimed ones count for the extent only), on
    the one line :func:`units_refusal` gives. ``--periodic`` and
    ``--task-frames`` learn without the skill's own check, so they call this
    when no --units was given.
    """
    import numpy as np

    from lfdkit.core.geometry import path_length
    from lfdkit.core.units import implausible_units, likely_units

    extent = float(np.ptp(np.vstack(paths), axis=0).max())
    speeds = [
        path_length(path) / float(t[-1] - t[0])
        for path, t in zip(paths, times, strict=True)
        if t is not None and t[-1] > t[0]
    ]
    why = implausible_units(extent, "m", max(speeds) if speeds else None)
    if why is not None:
        raise CommandError(_units_line(source, why, likely_units(extent, "m"), "m"))


def _duration(text: str) -> float | str:
    """``learn --duration``: seconds, or ``auto`` (the path's length at a hand's pace)."""
    if text == "auto":
        return text
    value = positive_decimal(text)
    if value is None:
        raise argparse.ArgumentTypeError(f"expected seconds > 0 or 'auto', got {text!r}")
    return value


class LazyChoices:
    """argparse choices read from a registry when argparse first needs them.

    ``keys`` returns the names; the registries (mimic methods, arms) import
    modules that ``lfdkit --help`` and the other commands should not wait for.
    """

    def __init__(self, keys: Callable[[], Iterable[str]]) -> None:
        self._keys = keys

    def __contains__(self, value: object) -> bool:
        return value in tuple(self._keys())

    def __iter__(self) -> Iterator[str]:
        return iter(tuple(self._keys()))


def _mimic_keys() -> tuple[str, ...]:
    from lfdkit.mimic import MIMIC_METHODS

    return tuple(MIMIC_METHODS)


def arm_keys() -> tuple[str, ...]:
    from lfdkit.execute.arm import ARMS

    return tuple(ARMS)


def _scene_from_args(args: argparse.Namespace, n_dims: int):
    from lfdkit.io.scenes import load_scene
    from lfdkit.model.box import Box
    from lfdkit.model.half_space import HalfSpace
    from lfdkit.model.motion import ConstantVelocity
    from lfdkit.model.scene import Obstacle, Scene

    obstacles = []
    if args.scene is not None:
        try:
            obstacles += list(load_scene(args.scene))
        except ValueError as exc:  # the library's advice names its functions, not options
            message = str(exc).replace(
                "load_scene expects exactly one; use load_scenes to read them all",
                "--scene takes one: keep the rows of one demo, or leave out the demo column",
            )
            raise CommandError(f"--scene {message}") from None
    for label, position, radius, velocity, box, normal in args.obstacle or ():
        if len(position) != n_dims:
            hint = " (a radius is given as r=R)" if len(position) == n_dims + 1 else ""
            raise CommandError(
                f"--obstacle {label}: {len(position)} coordinates for a {n_dims}-D skill{hint}"
            )
        motion = None if velocity is None else ConstantVelocity(velocity)
        if normal is not None:  # a direction: the same in every --units
            obstacles.append(HalfSpace(label, position, radius, normal))
        elif box is None:
            obstacles.append(Obstacle(label, position, radius, motion=motion))
        else:
            size, turn = box
            obstacles.append(Box(label, position, radius, size, turn, motion=motion))
    scene = Scene(tuple(obstacles))
    if len(scene) and scene.positions.shape[1] != n_dims:
        raise CommandError(
            f"--scene {args.scene}: {scene.positions.shape[1]}-D obstacles for a {n_dims}-D skill"
        )
    return scene


def _load_skill(path: Path):
    from lfdkit.skill import Skill

    return Skill.load(path)


def point_arg(values, name: str, n_dims: int):
    if values is not None and len(values) != n_dims:
        raise CommandError(f"{name}: {len(values)} coordinates for a {n_dims}-D skill")
    return values


def positive_or_none(text: str | None, option: str, what: str) -> float | None:
    """``text`` as a positive, finite number; a one-line usage error naming ``option``."""
    if text is None:
        return None
    value = positive_decimal(text)
    if value is None:
        raise UsageError(f"{option}: expected {what}, got {text!r}")
    return value


def positive_decimal(text: str) -> float | None:
    """``text`` as a finite number > 0, or None where it is not one (the caller words the error)."""
    try:
        value = parse_decimal(text, finite=False)
    except ValueError:
        return None
    return value if math.isfinite(value) and value > 0.0 else None


def load_skill_file(path: Path):
    """The skill file ``path``, read once: a :class:`~lfdkit.skill.Skill`, periodic or task-frame.

    A periodic skill (``lfdkit learn --periodic``) is a
    :class:`~lfdkit.skill.periodic.PeriodicSkill`, a task-frame one
    (``--task-frames``) a :class:`~lfdkit.skill.task_frames.TaskFrameSkill`.
    """
    from lfdkit.io.skill_file import TASK_FRAME_FORMAT, is_periodic_document, read_skill_file

    data = read_skill_file(path)
    # Only a periodic file imports the periodic skill (its rhythmic DMPs, issue 30).
    if is_periodic_document(data):
        from lfdkit.skill.periodic import PeriodicSkill as kind
    elif data.get("format") == TASK_FRAME_FORMAT:
        from lfdkit.skill.task_frames import TaskFrameSkill as kind
    else:
        from lfdkit.skill import Skill as kind
    return kind.from_dict(data, source=os.fspath(path))


def parse_quaternion(text: str | None, option: str) -> list[float] | None:
    """An option's ``qx,qy,qz,qw``, normalised; a one-line usage error naming ``option``."""
    return _quaternion(text, option)


def skill_and_scene(args: argparse.Namespace, skill=None):
    """The skill of ``plan``/``plot`` in ``--units``, with the scene, start and goal given.

    ``skill``: the skill file already read (:func:`load_skill_file`); default read here.
    """
    skill = _load_skill(args.skill) if skill is None else skill
    if args.units is not None:
        skill = skill.to_units(args.units)
    q = skill.n_dims_
    scene = _scene_from_args(args, q)
    return skill, scene, point_arg(args.start, "--start", q), point_arg(args.goal, "--goal", q)


def option_named(message: str) -> str:
    """A library error naming an argument (``start_orientation: ...``) as its option."""
    # The library's opt-in for unlearned obstacle classes, in the command line's words.
    message = re.sub(r"unknown_class=MARGIN \(lfdkit [^:]*: ([^)]*)\)", r"\1", message)
    message = re.sub(r"^unknown_response:", "--unknown-class response:", message)
    message = message.replace(
        "learn one with fit_reward() (demonstrations around obstacles) or adopt() it",
        "learn one with lfdkit learn --scenes (demonstrations around obstacles)",
    )
    message = re.sub(r"^via\[(\d+)\]:", lambda m: f"--via (value {int(m[1]) + 1}):", message)
    return re.sub(
        r"^(duration|speed|start_orientation|goal_orientation|unknown_class|q_start):",
        lambda m: "--" + m.group(1).replace("_", "-") + ":",
        message,
    )


def parse_fraction(text: str) -> float:
    """``--speed-fraction``: a number in (0, 1]."""
    try:
        value = parse_decimal(text, finite=False)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number in (0, 1], got {text!r}") from None
    if not 0.0 < value <= 1.0:  # also NaN
        raise argparse.ArgumentTypeError(f"expected a number in (0, 1], got {text!r}")
    return value


class UnknownClass(NamedTuple):
    """``--unknown-class margin=M[,response=R]``, parsed (``Skill.plan``'s two options)."""

    margin: float
    response: str | None = None


def parse_unknown_class(text: str) -> UnknownClass:
    """``--unknown-class margin=M[,response=R]``: margin (a length >= 0) and response.

    ``R`` is ``none`` (the default), ``nearest`` (the learned class nearest in
    size) or a learned class's name; whether it is learned is the skill's check.
    """
    fields = {}
    for part in text.split(","):
        key, sep, value = part.partition("=")
        key = key.strip().lower()
        if not sep or key not in ("margin", "response") or key in fields:
            raise argparse.ArgumentTypeError(
                "expected margin=LENGTH[,response=nearest|CLASS|none] (e.g. margin=0.02 or "
                f"margin=0.02,response=nearest), got {text!r}"
            )
        fields[key] = value.strip()
    if "margin" not in fields:
        raise argparse.ArgumentTypeError(f"expected margin=LENGTH (e.g. margin=0.02), got {text!r}")
    try:
        margin = parse_decimal(fields["margin"])
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected margin=LENGTH with a number, got {text!r}"
        ) from None
    if margin < 0.0:
        raise argparse.ArgumentTypeError(f"expected a margin >= 0, got {text!r}")
    response = fields.get("response", "none")
    if not response:
        raise argparse.ArgumentTypeError(
            f"expected response=nearest, a learned class or none, got {text!r}"
        )
    return UnknownClass(margin, None if response.lower() == "none" else response)


def unknown_class_options(args: argparse.Namespace) -> dict[str, Any]:
    """``Skill.plan``'s ``unknown_class`` and ``unknown_response`` from ``--unknown-class``."""
    option = args.unknown_class
    if option is None:
        return {}
    return {"unknown_class": option.margin, "unknown_response": option.response}


def write_timed_run(args: argparse.Namespace, timed: Any, summary: str, rate: float | None) -> None:
    """A plan's timed path (a ``TimedPath``), at ``--rate`` if given, to ``--output`` or stdout.

    Writes ``t``, the positions, velocities with ``--velocities`` and any
    orientations; the summary line ends with the rate and the file written
    (on standard output, which carries the path, it is shown at ``-v`` only).
    """
    import sys

    from lfdkit.io import path_csv, save_path

    if rate is not None:
        try:
            timed = timed.at_rate(rate)
        except ValueError as exc:
            raise CommandError(option_named(str(exc).replace("rate_hz", "--rate", 1))) from None
        summary += f"; written at {rate:g} Hz: {len(timed.times)} samples"
    columns = {
        "times": timed.times,
        "velocities": timed.velocities if args.velocities else None,
        "orientations": timed.orientations,
    }
    if args.output is None:
        sys.stdout.write(path_csv(timed.positions, **columns))
        tell(args, summary, level=2)
        return
    save_path(args.output, timed.positions, **columns, overwrite=args.force)
    tell(args, f"{summary}; wrote {args.output}")


def add_unknown_class_option(parser: argparse.ArgumentParser, units: str) -> None:
    """``--unknown-class margin=M`` (``Skill.plan``'s ``unknown_class``), lengths in ``units``."""
    parser.add_argument(
        "--unknown-class",
        type=parse_unknown_class,
        default=None,
        metavar="margin=M[,response=R]",
        help="plan around obstacles of a class the skill never learned as a hard radius plus "
        f"M ({units}; plus --clearance where there is one), and warn; R is the response it "
        "gets besides: none (default), nearest (the learned class nearest in size; the "
        "warning names it) or a learned class's name. Without it such an obstacle is refused",
    )


def add_loudness_options(parser: argparse.ArgumentParser) -> None:
    loud = parser.add_mutually_exclusive_group()
    loud.add_argument(
        "-q",
        "--quiet",
        dest="verbosity",
        action="store_const",
        const=0,
        help="print nothing on success",
    )
    loud.add_argument(
        "-v",
        "--verbose",
        dest="verbosity",
        action="store_const",
        const=2,
        help="say more about each step",
    )
    parser.set_defaults(verbosity=1)


def add_force_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-f", "--force", action="store_true", help="overwrite existing files")


def add_planner_options(parser: argparse.ArgumentParser, *, defaults: bool) -> None:
    """``--planner`` and ``--horizon``: with ``defaults`` the Skill's, else the skill file's."""
    parser.add_argument(
        "--planner",
        choices=PLANNERS,
        default=SKILL_DEFAULTS["planner"] if defaults else None,
        help="receding-horizon MPC or the full-horizon optimum"
        + (" (default %(default)s)" if defaults else " (default: the skill's)"),
    )
    parser.add_argument(
        "--horizon",
        type=_whole,
        default=SKILL_DEFAULTS["horizon"] if defaults else None,
        metavar="H",
        help=f"MPC horizon, {MIN_HORIZON} to {MAX_HORIZON}"
        + (" (default %(default)s)" if defaults else " (default: the skill's)"),
    )


def add_skill_file_options(parser: argparse.ArgumentParser) -> None:
    """The skill file, and the start, goal and obstacles to use it with (``plan``, ``plot``)."""
    parser.add_argument("skill", type=Path, metavar="SKILL.json", help="a skill from lfdkit learn")
    for end in ("start", "goal"):
        help = f"{end} (default: the demonstrations')"
        parser.add_argument(f"--{end}", type=parse_numbers, metavar="X,Y[,Z]", help=help)
    parser.add_argument(
        "--obstacle",
        type=_obstacle,
        action="append",
        metavar="CLASS:X,Y[,Z][,r=R][,vx=VX,vy=VY]",
        help="an obstacle of a learned class, optionally with its radius and, for one "
        "moving at constant velocity, its velocity in units/s (the plan keeps clear of "
        "where it will be when the tool passes; repeatable). A box gives its edge lengths "
        "and optionally its turn about z: CLASS:X,Y[,Z],sx=SX,sy=SY[,sz=SZ][,yaw=30deg|0.52rad]"
        "[,r=R] (X,Y[,Z] its centre; a box is never entered, even at --clearance 0), or "
        "in a row: CLASS:CX,CY[,CZ],LX,LY[,LZ][,30deg|,QX,QY,QZ,QW] (a quaternion x, y, z, w). A "
        "table, floor or wall (a half-space: every point on or below a plane) gives a point "
        "of its plane and its normal to the free side: CLASS:X,Y[,Z],nx=NX,ny=NY[,nz=NZ][,r=R] "
        "(e.g. table:0,0,0.7,nx=0,ny=0,nz=1; never entered)",
    )
    parser.add_argument(
        "--scene",
        type=Path,
        metavar="FILE",
        help="obstacles from a scene file (.csv or .json, one scene)",
    )


def add_orientation_options(parser: argparse.ArgumentParser) -> None:
    """``--start-orientation``/``--goal-orientation`` of a skill learned with orientation."""
    for end in ("start", "goal"):
        parser.add_argument(
            f"--{end}-orientation",
            metavar="QX,QY,QZ,QW",
            help=f"tool orientation at the {end}, a quaternion (scalar last, normalised); only "
            "for a skill learned with orientations (default: the demonstrations')",
        )


def add_output_folder_option(parser: argparse.ArgumentParser, name: str) -> None:
    """``-o/--output``: the folder a command writes its results in (default ./NAME)."""
    help = f"output directory (default: ./{name})"
    parser.add_argument("-o", "--output", type=Path, default=Path(name), help=help)


def add_units_option(parser: argparse.ArgumentParser, default: str | None, help: str) -> None:
    """``--units m|cm|mm``: the unit of the command's lengths (a wrong one lists the choices)."""
    parser.add_argument("--units", choices=UNITS, default=default, help=help)


def add_seed_option(parser: argparse.ArgumentParser, default: int | None, help: str) -> None:
    parser.add_argument("--seed", type=bounded_int(0, 2**32 - 1), default=default, help=help)


def add_skill_param_options(parser: argparse.ArgumentParser) -> None:
    """The Skill parameters of ``learn`` and ``batch learn``: defaults the Skill's own."""
    parser.add_argument(
        "--mimic",
        choices=LazyChoices(_mimic_keys),
        # A metavar, or argparse lists the choices as the parser is built (seconds).
        metavar="METHOD",
        default=SKILL_DEFAULTS["mimic"],
        # %(choices)s: the registry is read only when the help is printed.
        help="generalized path method, a key of lfdkit.mimic.MIMIC_METHODS: %(choices)s "
        "(default %(default)s)",
    )
    parser.add_argument(
        "--n-points",
        type=_whole,
        default=SKILL_DEFAULTS["n_points"],
        help="points of the path and of plans (default %(default)s)",
    )
    add_seed_option(parser, SKILL_DEFAULTS["random_state"], "seed of GMR's initialisation")
    add_planner_options(parser, defaults=True)
    parser.add_argument(
        "--model",
        choices=MODELS,
        default=SKILL_DEFAULTS["model"],
        help="obstacle behaviour: 'auto' chooses the model from the demonstrations (how far "
        "ahead the person reacts, the clearance kept, a late or slow swerve, which turns with "
        "the path in 2-D); 'thesis' is the thesis's model exactly; 'path' is 'auto' with "
        "every learned response turned with the path at its obstacle, for a person who "
        "reacts relative to the motion (2-D) (default %(default)s)",
    )
    parser.add_argument(
        "--duration",
        type=_duration,
        default=SKILL_DEFAULTS["duration"],
        metavar="S",
        help="seconds the movement lasts when the demonstrations carry no times (no t "
        "column); 'auto' (default): the path's length at a hand's typical demonstration "
        f"speed, {DEMONSTRATION_SPEED:g} m/s on average (at least 1 s). Timed "
        "demonstrations give their own",
    )
    add_units_option(
        parser,
        None,
        "unit of the demonstrations and scenes, kept in the skill (default m; "
        f"demonstrations spanning over {MAX_EXTENT_M:g} m, under {MIN_EXTENT_M * 1e3:g} mm "
        f"or moving faster than {MAX_MEAN_SPEED_M_S:g} m/s are refused without it)",
    )


#: ``--offset``, ``--height``, ``--tool-length``, ``--q-start``: their command-line defaults.
_TASK_OPTIONS = {
    "offset": (0.0, 0.0, 0.0),
    "height": 0.2,
    "tool_length": 0.0,
    "q_start": None,
    "approach": 0.0,
    "retreat": 0.0,
}


def add_task_description_options(parser: argparse.ArgumentParser) -> None:
    """The path task's description (``execute``, ``batch evaluate``): options or a task file."""
    group = parser.add_argument_group(
        "the task description (path task): these options, or --task-file"
    )
    group.add_argument(
        "--task-file",
        type=Path,
        metavar="TASK.json",
        help="the task description as JSON: any of name, frame (4x4) or offset [x, y, z], "
        "tool (4x4, flange to tool) or tool_length, height, orientation [qx, qy, qz, qw] (the "
        "tool's when the skill learned none), q_start, approach, retreat; metres and radians",
    )
    group.add_argument(
        "--offset",
        type=float,
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="where the skill's origin is in the robot's base frame, m (default 0 0 0)",
    )
    group.add_argument(
        "--height",
        type=float,
        metavar="Z",
        help="2-D skill: height of its plane, m (default 0.2)",
    )
    group.add_argument(
        "--q-start",
        type=float,
        nargs="+",
        metavar="Q",
        help="a configuration near the wanted one at the start (rad), picking the arm's "
        "branch (default: elbow up for UR arms, the middle of the limits otherwise)",
    )
    group.add_argument(
        "--tool-length",
        type=float,
        metavar="L",
        help="the tool point's distance along the flange's z axis, m (default 0)",
    )
    for move, how in (
        ("approach", "into the first pose from"),
        ("retreat", "out of the last pose"),
    ):
        group.add_argument(
            f"--{move}",
            type=float,
            metavar="D",
            help=f"a straight move along the tool's z axis {how} D m back (default 0: none)",
        )


def task_description(args: argparse.Namespace, name: str = "path"):
    """The :class:`~lfdkit.execute.pipeline.TaskDescription` of the options or ``--task-file``."""
    from lfdkit.execute.pipeline import TaskDescription

    given = {key: getattr(args, key) for key in _TASK_OPTIONS if getattr(args, key) is not None}
    if args.task_file is not None:
        if given:
            option = "--" + next(iter(given)).replace("_", "-")
            raise UsageError(f"{option}: the task file describes the task; give one or the other")
        from lfdkit.io.text import load_json

        path = args.task_file
        if not path.is_file():
            raise UsageError(f"--task-file {path}: no such file")
        try:
            return TaskDescription.from_dict(load_json(str(path)), str(path))
        except ValueError as exc:
            raise CommandError(f"--task-file {str(exc).splitlines()[0]}") from None
    data = {**_TASK_OPTIONS, **given, "name": name}
    try:
        return TaskDescription.from_dict(data, "task")
    except ValueError as exc:  # the options are numbers already: only their meaning is wrong
        raise CommandError(str(exc).removeprefix("task: ")) from None
