"""URScript programs that play a sweeping motion on a UR controller (thesis §6.4).

Two kinds of program:

``motion="movel"``
    One ``movel(p[x, y, z, rx, ry, rz], a=..., v=..., r=...)`` per tool pose:
    the controller moves the tool in straight lines between the poses at the
    given tool speed and acceleration, blending past each pose within
    ``blend_radius`` (0: stop at every pose). The first ``movel`` goes in a
    straight line from wherever the tool is to the first pose.
``motion="servoj"``
    A ``movej`` to the first joint configuration (URScript's default joint
    acceleration 1.4 rad/s² and speed 1.05 rad/s), then one
    ``servoj([q1, ..., q6], t=dt, lookahead_time=0.1, gain=300)`` line per
    sample of a uniformly resampled trajectory
    (:meth:`lfdkit.robot.timing.Timing.resample`): the controller tracks the
    stream, each command holding for ``dt`` seconds. Lines are written out
    one per sample rather than as a list and a loop, so the program shows
    exactly what is sent; at 125 Hz a minute of motion is 7,500 lines (for
    much longer motions stream over RTDE instead).

Numbers are written in fixed-point notation with 9 decimals (trailing zeros
dropped), so every value is within 5e-10 of the input: 0.5 nm for positions
in metres and 0.5 nrad for angles, far below the robot's repeatability, and
no exponent notation appears in the program.

Checks
------
Besides finite numbers and shapes, these caps guard against unit mistakes
and values no UR controller accepts; they are lfdkit's choices, kept at or
below the UR5's limits:

* tool speed ``0 < speed <= 1.0`` m/s (the UR5's maximum tool speed is about 1 m/s);
* tool acceleration ``0 < acceleration <= 5.0`` m/s²;
* ``0 <= blend_radius < half the shortest distance between consecutive positions``
  (a blend must end before the next one starts);
* positions within ``1.0`` m of the base origin (the UR5 reaches 0.85 m; a
  larger value is most likely millimetres passed as metres);
* servoj: ``dt >= 0.002`` s (one e-Series control period; CB-series controllers
  run at 125 Hz and need ``dt >= 0.008``), equally spaced ``times``, joint
  angles within ±2π rad and joint speeds between samples at most 3.2 rad/s
  (thesis Table 6.2).
"""

from __future__ import annotations

import keyword
import re
from datetime import datetime, timezone
from pathlib import Path
from typing import IO, Any, Literal

import numpy as np

from lfdkit import __version__
from lfdkit._validation import check_path, check_positive
from lfdkit.demos import PathLike, atomic_write

__all__ = [
    "MAX_TOOL_ACCELERATION",
    "MAX_TOOL_SPEED",
    "MIN_SERVO_DT",
    "format_number",
    "urscript_program",
    "write_urscript",
]

MAX_TOOL_SPEED = 1.0
"""Largest tool speed accepted for ``movel`` (m/s)."""

MAX_TOOL_ACCELERATION = 5.0
"""Largest tool acceleration accepted for ``movel`` (m/s²)."""

MIN_SERVO_DT = 0.002
"""Shortest ``servoj`` time step accepted (s): one control period of an e-Series controller."""

MAX_REACH = 1.0
"""Largest distance of a tool position from the base origin accepted (m)."""

JOINT_LIMIT = 2.0 * np.pi
"""UR5 joint position limit, ± this (rad)."""

JOINT_SPEED_LIMIT = 3.2
"""UR5 joint speed limit (rad/s, thesis Table 6.2)."""

SERVO_LOOKAHEAD = 0.1
"""``lookahead_time`` written in every ``servoj`` (s): smooths the stream, adds this much lag."""

SERVO_GAIN = 300
"""``gain`` written in every ``servoj``: proportional gain of the controller's tracking."""

DECIMALS = 9
"""Decimals written for every number; values are exact to 5e-10."""

_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
# URScript keywords and the built-in literals a function cannot be named after.
_RESERVED = {
    "def", "end", "if", "elif", "else", "while", "for", "return", "break", "continue",
    "thread", "run", "kill", "global", "local", "and", "or", "not", "xor", "True",
    "False", "halt", "sec", "pass", "p",
}  # fmt: skip
_REL_DT_TOL = 1e-6  # relative tolerance on the spacing of servoj times


def format_number(value: float) -> str:
    """Write a number for URScript: fixed point, 9 decimals, trailing zeros dropped.

    Parameters
    ----------
    value : float
        A finite number.

    Returns
    -------
    str
        E.g. ``0.192`` for 0.192, ``-1.570796327`` for −π/2, ``0.0`` for
        values that round to zero (no ``-0.0``). Always has a decimal point.
    """
    text = f"{float(value):.{DECIMALS}f}".rstrip("0")
    if text.endswith("."):
        text += "0"
    return "0.0" if text == "-0.0" else text


def _fmt_list(values: np.ndarray) -> str:
    return ", ".join(format_number(v) for v in values)


def _check_name(name: Any) -> str:
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise ValueError(
            f"name: must be a URScript identifier (letters, digits, _; not starting with a "
            f"digit), got {name!r}"
        )
    if name in _RESERVED or keyword.iskeyword(name):
        raise ValueError(f"name: {name!r} is a reserved word; choose another program name")
    return name


def _check_bounded(value: Any, name: str, cap: float, unit: str) -> float:
    v = check_positive(value, name)
    if v > cap:
        raise ValueError(f"{name}: must be <= {cap:g} {unit}, got {v!r}")
    return v


def _check_header(header: Any) -> list[str]:
    if header is None:
        return []
    if not isinstance(header, str):
        raise TypeError(f"header: expected a str or None, got {type(header).__name__}")
    if not header.isascii():
        raise ValueError("header: must be ASCII text (UR controllers read ASCII scripts)")
    return [f"# {line}".rstrip() for line in header.splitlines()]


def _check_poses(poses: Any) -> np.ndarray:
    arr = check_path(poses, "poses", min_points=1, n_dims=6)
    reach = np.linalg.norm(arr[:, :3], axis=1)
    if (reach > MAX_REACH).any():
        i = int(np.argmax(reach > MAX_REACH))
        raise ValueError(
            f"poses: row {i} is {reach[i]:.4g} m from the base origin; a UR5 reaches 0.85 m "
            "(positions must be in metres, not millimetres)"
        )
    return arr


def _check_servo(joint_path: Any, times: Any) -> tuple[np.ndarray, float]:
    if joint_path is None or times is None:
        raise ValueError("joint_path, times: both are required with motion='servoj'")
    q = check_path(joint_path, "joint_path", n_dims=6)
    try:
        t = np.asarray(times, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError("times: expected a numeric array of shape (n,)") from exc
    if t.shape != (len(q),):
        raise ValueError(
            f"times: expected shape ({len(q)},), one per row of joint_path, got shape {t.shape}"
        )
    if not np.isfinite(t).all():
        raise ValueError("times: contains NaN or an infinite value")
    steps = np.diff(t)
    dt = float(steps.mean())
    if dt <= 0 or np.abs(steps - dt).max() > _REL_DT_TOL * dt:
        raise ValueError(
            "times: must be equally spaced and increasing (resample the trajectory, "
            "e.g. Timing.resample(125))"
        )
    if dt < MIN_SERVO_DT:
        raise ValueError(
            f"times: step {dt:g} s is shorter than one controller period ({MIN_SERVO_DT:g} s)"
        )
    bad = np.abs(q) > JOINT_LIMIT
    if bad.any():
        i, j = (int(k) for k in np.argwhere(bad)[0])
        raise ValueError(
            f"joint_path: joint {j} at row {i} is {q[i, j]:.6g} rad, outside the UR5 limits ±2π rad"
        )
    speed = np.abs(np.diff(q, axis=0)) / dt
    if (speed > JOINT_SPEED_LIMIT * (1.0 + 1e-9)).any():
        i, j = (int(k) for k in np.argwhere(speed > JOINT_SPEED_LIMIT * (1.0 + 1e-9))[0])
        raise ValueError(
            f"joint_path: joint {j} moves at {speed[i, j]:.4g} rad/s between rows {i} and "
            f"{i + 1}, above the UR5 limit of {JOINT_SPEED_LIMIT:g} rad/s"
        )
    return q, dt


def urscript_program(
    poses: Any = None,
    *,
    name: str = "lfdkit_sweep",
    motion: Literal["movel", "servoj"] = "movel",
    speed: float = 0.25,
    acceleration: float = 1.2,
    blend_radius: float = 0.0,
    times: Any = None,
    joint_path: Any = None,
    header: str | None = None,
) -> str:
    """A URScript program that plays a motion on a UR controller.

    Parameters
    ----------
    poses : array_like, shape (n, 6), optional
        Tool poses ``[x, y, z, rx, ry, rz]`` in the base frame (metres, and a
        rotation vector in radians), e.g. from
        :func:`lfdkit.robot.poses.pose_vector` followed by
        :func:`~lfdkit.robot.poses.unwrap_rotvecs`. Required for ``"movel"``,
        must be omitted for ``"servoj"``.
    name : str
        Name of the URScript function; a valid identifier.
    motion : {"movel", "servoj"}
        Linear tool moves through the poses, or a joint-position stream.
    speed : float
        ``movel`` tool speed (m/s), in ``(0, 1]``.
    acceleration : float
        ``movel`` tool acceleration (m/s²), in ``(0, 5]``.
    blend_radius : float
        ``movel`` blend radius (m), ``>= 0`` and below half the shortest
        distance between consecutive positions. The last move always has 0.
    times : array_like, shape (n,), optional
        ``servoj`` only: equally spaced sample times (s), as returned by
        :meth:`lfdkit.robot.timing.Timing.resample`; their spacing is the
        ``t`` of every ``servoj``.
    joint_path : array_like, shape (n, 6), optional
        ``servoj`` only: joint angles (rad) at ``times``.
    header : str, optional
        Extra ASCII text for the header comment (one comment line per line).

    Returns
    -------
    str
        The program, ``\\n`` line endings: header comments (lfdkit version, UTC
        date, number of poses or samples, units), ``def name():`` ... ``end``
        and a final ``name()`` call.

    Raises
    ------
    ValueError
        For a bad shape, NaN/inf, a value outside the ranges in the module
        notes, or an argument that does not belong to the chosen ``motion``.
    """
    name = _check_name(name)
    extra = _check_header(header)
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")
    lines = [f"# URScript program written by lfdkit {__version__} on {stamp}"]

    if motion == "movel":
        if times is not None or joint_path is not None:
            raise ValueError("times, joint_path: only used with motion='servoj'")
        if poses is None:
            raise ValueError("poses: required with motion='movel'")
        p = _check_poses(poses)
        v = _check_bounded(speed, "speed", MAX_TOOL_SPEED, "m/s")
        a = _check_bounded(acceleration, "acceleration", MAX_TOOL_ACCELERATION, "m/s^2")
        r = check_positive(blend_radius, "blend_radius", allow_zero=True)
        if r > 0:
            seg = np.linalg.norm(np.diff(p[:, :3], axis=0), axis=1)
            if len(seg) and r >= 0.5 * seg.min():
                k = int(np.argmin(seg))
                raise ValueError(
                    f"blend_radius: {r:g} m is not below half the shortest move "
                    f"({seg[k]:.4g} m between poses {k} and {k + 1})"
                )
        lines += [
            f"# {len(p)} poses, movel: p[x, y, z, rx, ry, rz] in the robot base frame, "
            "metres and radians (rotation vector)",
            f"# tool speed {format_number(v)} m/s, acceleration {format_number(a)} m/s^2, "
            f"blend radius {format_number(r)} m",
        ]
        body = []
        for i, pose in enumerate(p):
            ri = r if i < len(p) - 1 else 0.0  # stop at the last pose
            body.append(
                f"movel(p[{_fmt_list(pose)}], a={format_number(a)}, v={format_number(v)}, "
                f"r={format_number(ri)})"
            )
    elif motion == "servoj":
        if poses is not None:
            raise ValueError("poses: not used with motion='servoj'; pass joint_path and times")
        q, dt = _check_servo(joint_path, times)
        lines += [
            f"# {len(q)} samples, servoj every {format_number(dt)} s "
            f"({format_number(dt * (len(q) - 1))} s): joint angles in radians",
            f"# lookahead_time {SERVO_LOOKAHEAD} s, gain {SERVO_GAIN}; starts with movej "
            "to the first sample",
        ]
        body = [f"movej([{_fmt_list(q[0])}], a=1.4, v=1.05)"]
        tail = f", t={format_number(dt)}, lookahead_time={SERVO_LOOKAHEAD}, gain={SERVO_GAIN})"
        body += [f"servoj([{_fmt_list(row)}]{tail}" for row in q]
    else:
        raise ValueError(f"motion: expected 'movel' or 'servoj', got {motion!r}")

    lines += extra
    lines.append(f"def {name}():")
    lines += [f"  {line}" for line in body]
    lines += ["end", f"{name}()"]
    return "\n".join(lines) + "\n"


def write_urscript(path: PathLike, program: str, *, overwrite: bool = False) -> Path:
    """Write a URScript program to a file, atomically.

    Parameters
    ----------
    path : str or os.PathLike
        Destination, e.g. ``sweep.script``; its directory must exist.
    program : str
        The program text (:func:`urscript_program`); ASCII only.
    overwrite : bool
        Replace an existing file; otherwise an existing ``path`` raises.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    FileExistsError
        If ``path`` exists and ``overwrite`` is false.
    ValueError
        If ``program`` is empty or not ASCII.
    """
    if not isinstance(program, str):
        raise TypeError(f"program: expected a str, got {type(program).__name__}")
    if not program.strip():
        raise ValueError("program: is empty")
    if not program.isascii():
        raise ValueError("program: must be ASCII text (UR controllers read ASCII scripts)")
    text = program if program.endswith("\n") else program + "\n"

    def writer(f: IO[Any]) -> None:
        f.write(text)

    return atomic_write(path, writer, overwrite=overwrite)
