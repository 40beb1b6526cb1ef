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
    (:meth:`lfdkit.execute.timing.Timing.resample`): the controller tracks the
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
A program drives a real arm, so every argument is checked before a line is
written, and every refusal is a :class:`URScriptError` (a ``ValueError``;
:class:`URScriptTypeError` for a value of the wrong kind, also a
``TypeError``) whose message names the argument, the pose or sample index
and the offending value:

* *Values.* Every pose, joint angle and time is a real number: ``bool``,
  ``str``, ``complex``, ``None`` and other objects are refused as they are
  given, before NumPy would turn ``True`` into 1.0; NaN and infinities too.
* *Rotations.* A rotation vector ``[rx, ry, rz]`` has norm at most π (plus
  1e-9): every rotation has one, and a larger norm is most likely degrees
  passed as radians (``[0, 180, 0]``). Tool-down sweeping poses are
  rotations by π, so :func:`lfdkit.execute.poses.unwrap_rotvecs` keeps them at
  norm π (it only picks between ``±π a``); a sequence it unwraps past π is
  refused.
* *Arm.* The program is for one arm, ``arm=`` (an
  :class:`lfdkit.execute.arm.Arm` of UR type, :attr:`~lfdkit.execute.arm.Arm.ur_type`;
  default the UR5 of the thesis): its reach, joint limits and forward
  kinematics are what the checks below use; messages name it.
* *Positions.* Every tool position lies in the :class:`Workspace` box
  (default: on or above the table plane ``z = 0``, where the UR5 of the
  sweeping set-up stands) and, unless the workspace says otherwise, has an
  inverse kinematics solution for the arm (:func:`lfdkit.execute.ur5.inverse`).
  Only the poses are checked, not the straight lines ``movel`` draws between
  them. ``servoj`` samples are checked through their forward kinematics.
* *Joint streams* (``servoj``): joint angles within the arm's
  ``joint_limits``; the speed between consecutive samples at most its
  ``max_joint_speed``; and the acceleration implied at every tick at most its
  ``max_joint_acceleration`` (per joint). The stream starts from
  rest (the ``movej`` before it stops at the first sample) and the robot
  stops after the last sample, so the first step and the stop count too: a
  0.025 rad step from rest in one 8 ms tick (3.1 rad/s, under the speed
  limit) implies 390 rad/s² and is refused.
* *Motion parameters*, real numbers (not ``bool``) and finite: tool speed
  ``0 < speed <= 1.0`` m/s, tool acceleration ``0 < acceleration <= 5.0``
  m/s², ``0 <= blend_radius <= 1.0`` m and below half the shortest distance
  between consecutive positions (a blend must end before the next one
  starts), servoj time step ``0.002 <= dt <= 1.0`` s (0.002 s is one
  e-Series control period; CB-series controllers run at 125 Hz and need
  ``dt >= 0.008``).

No number is formatted unless its magnitude is below 1e9, so a program never
holds a 300-digit literal.
"""

from __future__ import annotations

import keyword
import math
import numbers
import re
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, Literal

import numpy as np

from lfdkit import __version__
from lfdkit.execute import ur5
from lfdkit.execute.arm import UR5, Arm
from lfdkit.execute.poses import pose_matrix
from lfdkit.io import write_text
from lfdkit.model.demos import PathLike

__all__ = [
    "DEFAULT_WORKSPACE",
    "MAX_BLEND_RADIUS",
    "MAX_ROTATION",
    "MAX_SERVO_DT",
    "MAX_TOOL_ACCELERATION",
    "MAX_TOOL_SPEED",
    "MIN_SERVO_DT",
    "MOUNT_Z",
    "URScriptError",
    "URScriptTypeError",
    "Workspace",
    "format_number",
    "urscript_program",
    "write_urscript",
]

MAX_TOOL_SPEED = 1.0
"""Largest tool speed accepted for ``movel`` (m/s)."""

MAX_TOOL_ACCELERATION = 5.0
"""Largest tool acceleration accepted for ``movel`` (m/s²)."""

MAX_BLEND_RADIUS = 1.0
"""Largest ``movel`` blend radius accepted (m); the UR5 reaches about 0.85 m."""

MIN_SERVO_DT = 0.002
"""Shortest ``servoj`` time step accepted (s): one control period of an e-Series controller."""

MAX_SERVO_DT = 1.0
"""Longest ``servoj`` time step accepted (s); a stream ticks every 2 to 8 ms."""

MAX_ROTATION = np.pi + 1e-9
"""Largest rotation-vector norm accepted (rad): π, plus round-off."""

MOUNT_Z = 0.0
"""Height of the plane the arm stands on in its base frame (m): a table top, as in
the sweeping task (:data:`lfdkit.tasks.sweeping.scenarios.TABLE_Z`)."""

SERVO_LOOKAHEAD = 0.1
"""``lookahead_time`` written in every ``servoj`` (s): smooths the stream, adds this much lag."""

SERVO_GAIN = 300
"""``gain`` written in every ``servoj``: proportional gain of the controller's tracking."""

DECIMALS = 9
"""Decimals written for every number; values are exact to 5e-10."""

_MAX_FORMATTED = 1e9  # no number this large is written (nor anything a UR arm needs)
_MAX_EXTENT = 1000.0  # |box corner| cap (m): keeps even an unbounded workspace printable
_REL_TOL = 1e-9  # relative slack on the joint speed and acceleration limits
_REL_DT_TOL = 1e-6  # relative tolerance on the spacing of servoj times
_POSE_COLUMNS = ("x", "y", "z", "rx", "ry", "rz")

_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
# URScript keywords, built-in literals and the functions the program calls (a program
# named movel would call itself instead of moving).
_RESERVED = {
    "def", "end", "if", "elif", "else", "while", "for", "return", "break", "continue",
    "thread", "run", "kill", "global", "local", "and", "or", "not", "xor", "True",
    "False", "halt", "sec", "pass", "p", "movel", "movej", "movec", "movep", "servoj",
    "speedj", "speedl", "stopj", "stopl", "sleep", "sync", "textmsg", "popup",
}  # fmt: skip


# ------------------------------------------------------------------ errors
class URScriptError(ValueError):
    """An argument that would make a wrong or unsafe URScript program.

    Attributes
    ----------
    argument : str or None
        Name of the offending argument, e.g. ``"poses"``.
    index : int or None
        Index of the offending pose or sample (row), ``None`` for a scalar argument.
    """

    def __init__(self, message: str, argument: str | None = None, index: int | None = None):
        super().__init__(message)
        self.argument = argument
        self.index = index


class URScriptTypeError(URScriptError, TypeError):
    """An argument of the wrong kind: ``bool``, ``str``, ``complex``, ``None`` or an object."""


def _show(value: Any) -> str:
    """A short ``repr`` for messages (a 400-digit int is cut)."""
    if isinstance(value, (float, np.floating)) and not isinstance(value, bool):
        return f"{float(value):.6g}"
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


# ------------------------------------------------------------------ raw values
def _real(value: Any, where: str, argument: str, index: int | None = None) -> float:
    """A real number as a float, checked as given (no bool, str, complex, None, NaN, inf)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise URScriptTypeError(
            f"{where}: expected a real number, got {_show(value)} ({type(value).__name__})",
            argument,
            index,
        )
    try:
        out = float(value)
    except (OverflowError, TypeError, ValueError, ArithmeticError) as exc:
        raise URScriptError(
            f"{where}: {_show(value)} is not a usable number", argument, index
        ) from exc
    if not math.isfinite(out):
        raise URScriptError(f"{where}: must be finite, got {_show(value)}", argument, index)
    return out


def _scalar(
    value: Any, name: str, upper: float, unit: str, *, lower: float = 0.0, allow_lower: bool = False
) -> float:
    """A real number in ``(lower, upper]`` (``[lower, upper]`` with ``allow_lower``)."""
    v = _real(value, name, name)
    if v < lower or (v == lower and not allow_lower):
        bound = ">=" if allow_lower else ">"
        raise URScriptError(f"{name}: must be {bound} {lower:g} {unit}, got {_show(v)}", name)
    if v > upper:
        raise URScriptError(f"{name}: must be <= {upper:g} {unit}, got {_show(v)}", name)
    return v


def _is_sequence(value: Any) -> bool:
    return isinstance(value, Sequence) and not isinstance(value, (str, bytes, bytearray))


def _real_rows(value: Any, name: str, columns: tuple[str, ...], min_rows: int) -> np.ndarray:
    """Rows of real numbers, as given, as a float64 array ``(n, len(columns))``.

    A real-typed NumPy array is converted at once; anything else (lists, object
    arrays) is read element by element, so that a ``True`` or a ``"0.4"`` is
    refused with its position rather than converted.
    """
    n_cols = len(columns)
    shape_text = f"(n, {n_cols})"
    if isinstance(value, np.ndarray) and value.dtype.kind in "iuf":
        if value.ndim != 2 or value.shape[1] != n_cols:
            raise URScriptError(
                f"{name}: expected an array of shape {shape_text}, got shape {value.shape}", name
            )
        with np.errstate(over="ignore"):  # a float128 beyond float64 becomes inf: refused below
            out = value.astype(np.float64)
        bad = ~np.isfinite(out)
        if bad.any():
            i, j = (int(k) for k in np.argwhere(bad)[0])
            raise URScriptError(
                f"{name}[{i}] {columns[j]}: must be finite, got {_show(value[i, j])}", name, i
            )
    else:
        if isinstance(value, np.ndarray) and value.ndim == 2:
            rows: Sequence[Any] = list(value)
        elif _is_sequence(value):
            rows = value
        else:
            shape = f" of shape {value.shape}" if isinstance(value, np.ndarray) else ""
            raise URScriptTypeError(
                f"{name}: expected a list of rows or an array of shape {shape_text}, got "
                f"{type(value).__name__}{shape}",
                name,
            )
        out = np.empty((len(rows), n_cols))
        for i, row in enumerate(rows):
            if isinstance(row, np.ndarray) and row.ndim == 1:
                items: Sequence[Any] = list(row)
            elif _is_sequence(row):
                items = row
            else:
                raise URScriptTypeError(
                    f"{name}[{i}]: expected a row of {n_cols} numbers, got {_show(row)} "
                    f"({type(row).__name__})",
                    name,
                    i,
                )
            if len(items) != n_cols:
                raise URScriptError(
                    f"{name}[{i}]: expected {n_cols} numbers ({', '.join(columns)}), "
                    f"got {len(items)}",
                    name,
                    i,
                )
            for j, item in enumerate(items):
                out[i, j] = _real(item, f"{name}[{i}] {columns[j]}", name, i)
    if len(out) < min_rows:
        raise URScriptError(f"{name}: needs at least {min_rows} row(s), got {len(out)}", name)
    return out


def _real_vector(value: Any, name: str) -> np.ndarray:
    """A 1-D sequence of real numbers, checked as given, as float64 ``(n,)``."""
    if isinstance(value, np.ndarray) and value.ndim != 1:
        raise URScriptError(f"{name}: expected shape (n,), got shape {value.shape}", name)
    if isinstance(value, np.ndarray) and value.dtype.kind in "iuf":
        with np.errstate(over="ignore"):
            out = value.astype(np.float64)
        bad = ~np.isfinite(out)
        if bad.any():
            i = int(np.argmax(bad))
            raise URScriptError(f"{name}[{i}]: must be finite, got {_show(value[i])}", name, i)
        return out
    if not (isinstance(value, np.ndarray) or _is_sequence(value)):
        raise URScriptTypeError(
            f"{name}: expected a sequence of numbers, got {type(value).__name__}", name
        )
    return np.array([_real(v, f"{name}[{i}]", name, i) for i, v in enumerate(value)], dtype=float)


def _vec(values: np.ndarray) -> str:
    return "(" + ", ".join(f"{v:.6g}" for v in values) + ")"


# ------------------------------------------------------------------ workspace
@dataclass(frozen=True)
class Workspace:
    """Where a program may put the tool: a box in the base frame and the arm's reach.

    Parameters
    ----------
    lower, upper : tuple of 3 float
        Opposite corners ``(x, y, z)`` of the box (m, robot base frame); every
        tool position must satisfy ``lower <= position <= upper``. Finite and
        within ±1000 m. The default is the half-space on or above the table
        plane (:data:`MOUNT_Z`), cut at 1.2 m, beyond the UR5's reach, so that
        the table and the reach check are what bind (the UR10 reaches 1.3 m:
        widen the box for it). Raise ``lower[2]`` to keep
        a mounted tool off the table: the tool frame of the sweeping set-up is
        the flange, 0.192 m above the table while sweeping, with the brush
        reaching down to 2 mm above it.
    check_reach : bool
        Also require every pose to have an inverse kinematics solution for
        the program's arm (:func:`lfdkit.execute.ur5.inverse`, with ``tool``).
    tool : array_like, shape (4, 4), optional
        Flange→tool transform of the controller's tool centre point, so that
        poses are tool poses; ``None``: the tool frame is the flange (as in
        the sweeping task, :mod:`lfdkit.tasks.sweeping`).

    Notes
    -----
    There is no ``workspace=None``: to switch the box and the reach check off,
    pass :meth:`Workspace.unbounded` explicitly.
    """

    lower: tuple[float, float, float] = (-1.2, -1.2, MOUNT_Z)
    upper: tuple[float, float, float] = (1.2, 1.2, 1.2)
    check_reach: bool = True
    tool: tuple[tuple[float, ...], ...] | None = None

    def __post_init__(self) -> None:
        corners = {}
        for name in ("lower", "upper"):
            value = getattr(self, name)
            is_vector = isinstance(value, np.ndarray) and value.ndim == 1
            if not (_is_sequence(value) or is_vector) or len(value) != 3:
                raise URScriptTypeError(
                    f"{name}: expected 3 numbers (x, y, z) in metres, got {_show(value)}", name
                )
            corner = tuple(_real(v, f"{name}[{k}]", name, k) for k, v in enumerate(value))
            for k, v in enumerate(corner):
                if abs(v) > _MAX_EXTENT:
                    raise URScriptError(
                        f"{name}[{k}]: must be within ±{_MAX_EXTENT:g} m, got {_show(v)}", name, k
                    )
            corners[name] = corner
            object.__setattr__(self, name, corner)
        for k, axis in enumerate("xyz"):
            if corners["lower"][k] >= corners["upper"][k]:
                raise URScriptError(
                    f"lower, upper: the box is empty along {axis} "
                    f"({corners['lower'][k]:g} >= {corners['upper'][k]:g} m)",
                    "lower",
                )
        if not isinstance(self.check_reach, (bool, np.bool_)):
            raise URScriptTypeError(
                f"check_reach: expected a bool, got {_show(self.check_reach)}", "check_reach"
            )
        object.__setattr__(self, "check_reach", bool(self.check_reach))
        if self.tool is not None:
            rows = _real_rows(self.tool, "tool", tuple(f"column {c}" for c in range(4)), 4)
            if rows.shape != (4, 4):
                raise URScriptError(f"tool: expected shape (4, 4), got {rows.shape}", "tool")
            try:
                ur5.forward(np.zeros(6), tool=rows)  # checks it is a rigid transform
            except (TypeError, ValueError) as exc:
                raise URScriptError(str(exc), "tool") from exc
            object.__setattr__(self, "tool", tuple(tuple(float(v) for v in r) for r in rows))

    @classmethod
    def unbounded(cls) -> Workspace:
        """No reach check and a ±1000 m box: only values no program should hold are refused."""
        return cls((-_MAX_EXTENT,) * 3, (_MAX_EXTENT,) * 3, check_reach=False)

    @property
    def tool_matrix(self) -> np.ndarray | None:
        """``tool`` as a ``(4, 4)`` array, or ``None``."""
        return None if self.tool is None else np.array(self.tool)

    def check_positions(
        self, positions: Any, name: str = "positions", what: str = "position"
    ) -> np.ndarray:
        """Refuse tool positions outside the box (``lower <= position <= upper``).

        Parameters
        ----------
        positions : array_like, shape (n, 3)
            Positions ``(x, y, z)`` in metres, robot base frame.
        name : str
            What the positions are called in messages (``name[i]``).
        what : str
            What one row is, for messages ("position", "tool position").

        Returns
        -------
        ndarray, shape (n, 3)
            The positions as float64.

        Raises
        ------
        URScriptError
            For a position that is not 3 finite numbers, or outside the box; the
            message names the row, the coordinate and the bound, with a hint for
            millimetres passed as metres.
        """
        rows = _real_rows(positions, name, _POSE_COLUMNS[:3], 1)
        self._refuse_outside(rows, name, what)
        return rows

    def check_poses(self, poses: Any, arm: Arm = UR5, name: str = "poses") -> np.ndarray:
        """Refuse tool poses a program must not send: outside the box or (``check_reach``) reach.

        Parameters
        ----------
        poses : array_like, shape (n, 6)
            UR poses ``(x, y, z, rx, ry, rz)``: metres and a rotation vector in
            radians (norm at most :data:`MAX_ROTATION`), robot base frame.
        arm : Arm
            The UR arm whose inverse kinematics decide the reach (with ``tool``).
        name : str
            What the poses are called in messages (``name[i]``).

        Returns
        -------
        ndarray, shape (n, 6)
            The poses as float64.

        Raises
        ------
        URScriptError
            For a pose that is not 6 finite numbers, a rotation of more than π
            (degrees passed as radians), a position outside the box, or a pose
            with no inverse kinematics solution for ``arm``; the message names
            the row.
        """
        arm = _check_arm(arm)
        p = _real_rows(poses, name, _POSE_COLUMNS, 1)
        norm = np.hypot(np.hypot(p[:, 3], p[:, 4]), p[:, 5])  # no overflow for 1e300
        if (norm > MAX_ROTATION).any():
            i = int(np.argmax(norm > MAX_ROTATION))
            raise URScriptError(
                f"{name}[{i}]: rotation vector {_vec(p[i, 3:])} has norm {norm[i]:.6g} rad, more "
                "than π; a UR pose takes a rotation vector in radians with norm <= π (a value "
                "like 180 is degrees)",
                name,
                i,
            )
        self._refuse_outside(p[:, :3], name, "position")
        if not self.check_reach:
            return p
        frames = pose_matrix(p)
        sols = ur5.inverse(frames, tool=self.tool_matrix, strict=False, arm=arm)
        unreachable = np.isnan(sols).all(axis=(1, 2))
        if unreachable.any():
            i = int(np.argmax(unreachable))
            try:
                ur5.inverse(frames[i], tool=self.tool_matrix, arm=arm)
                reason = "unreachable"  # pragma: no cover - the batch said so
            except ur5.UnreachableError as exc:
                reason = str(exc).removeprefix("pose: ")
            raise URScriptError(f"{name}[{i}]: {reason} for the {arm.name}", name, i)
        return p

    def _refuse_outside(self, positions: np.ndarray, name: str, what: str) -> None:
        """:meth:`check_positions` of positions already read as finite float rows."""
        lo, hi = np.array(self.lower), np.array(self.upper)
        out = (positions < lo) | (positions > hi)
        if out.any():
            i, k = (int(v) for v in np.argwhere(out)[0])
            side = "below" if positions[i, k] < lo[k] else "above"
            bound = lo[k] if side == "below" else hi[k]
            hint = ""
            if k == 2 and side == "below" and self.lower[2] == MOUNT_Z:
                hint = " (under the table plane)"
            elif np.abs(positions[i]).max() > 10.0:
                hint = " (millimetres passed as metres?)"
            raise URScriptError(
                f"{name}[{i}]: {what} {_vec(positions[i])} m is outside the workspace: "
                f"{'xyz'[k]} = {positions[i, k]:.6g} m is {side} {bound:g} m{hint}",
                name,
                i,
            )


#: The default :class:`Workspace`: on or above the table, within the arm's reach.
DEFAULT_WORKSPACE = Workspace()


def _check_arm(arm: Any) -> Arm:
    if not isinstance(arm, Arm):
        raise URScriptTypeError(
            f"arm: expected an Arm (e.g. lfdkit.execute.arm.UR5), got {_show(arm)}", "arm"
        )
    if not arm.ur_type:
        raise URScriptError(
            f"arm: URScript drives UR arms; {arm.name} does not have the UR joint structure "
            "(Arm.ur_type)",
            "arm",
        )
    return arm


def _check_workspace(workspace: Any) -> Workspace:
    if not isinstance(workspace, Workspace):
        raise URScriptTypeError(
            f"workspace: expected a Workspace (Workspace.unbounded() switches the box and "
            f"reach checks off), got {_show(workspace)}",
            "workspace",
        )
    return workspace


# ------------------------------------------------------------------ formatting
def format_number(value: float) -> str:
    """Write a number for URScript: fixed point, 9 decimals, trailing zeros dropped.

    Parameters
    ----------
    value : float
        A finite real number (not a ``bool``) of magnitude below 1e9.

    Returns
    -------
    str
        E.g. ``0.192`` for 0.192, ``-1.570796327`` for −π/2, ``0.0`` for
        values that round to zero (no ``-0.0``). Always has a decimal point.

    Raises
    ------
    URScriptError
        For a value that is not a finite real number below 1e9 in magnitude
        (never a 300-digit literal).
    """
    return _format(_real(value, "value", "value"))


def _format(value: float) -> str:
    """:func:`format_number` of a value already known to be a finite float."""
    if abs(value) >= _MAX_FORMATTED:
        raise URScriptError(f"value: {_show(value)} is too large to write (|value| < 1e9)", "value")
    text = f"{value:.{DECIMALS}f}".rstrip("0")
    if text.endswith("."):
        text += "0"
    return "0.0" if text == "-0.0" else text


def _fmt_list(values: np.ndarray) -> str:
    return ", ".join(_format(v) for v in values.tolist())


# ------------------------------------------------------------------ argument checks
def _check_name(name: Any) -> str:
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise URScriptError(
            f"name: must be a URScript identifier (letters, digits, _; not starting with a "
            f"digit), got {_show(name)}",
            "name",
        )
    if name in _RESERVED or keyword.iskeyword(name):
        raise URScriptError(
            f"name: {name!r} is a reserved word or a URScript function; choose another name",
            "name",
        )
    return name


def _check_header(header: Any) -> list[str]:
    if header is None:
        return []
    if not isinstance(header, str):
        raise URScriptTypeError(
            f"header: expected a str or None, got {type(header).__name__}", "header"
        )
    lines = header.splitlines()
    for i, line in enumerate(lines):
        if not all(32 <= ord(c) < 127 or c == "\t" for c in line):
            raise URScriptError(
                f"header: must be ASCII text (UR controllers read ASCII scripts) without control "
                f"characters; line {i} is {_show(line)}",
                "header",
                i,
            )
    return [f"# {line}".rstrip() for line in lines]


def _first(mask: np.ndarray) -> tuple[int, int]:
    """(sample, joint) of the first true entry of a (samples, joints) mask with one."""
    i, j = np.argwhere(mask)[0]
    return int(i), int(j)


def _joint_error(sample: int, joint: int, what: str) -> URScriptError:
    """The error for one joint at one sample of a servoj stream, naming both."""
    return URScriptError(f"joint_path[{sample}] joint {joint}: {what}", "joint_path", sample)


def _check_servo(
    joint_path: Any, times: Any, workspace: Workspace, arm: Arm
) -> tuple[np.ndarray, float]:
    if joint_path is None or times is None:
        missing = "joint_path" if joint_path is None else "times"
        raise URScriptError("joint_path, times: both are required with motion='servoj'", missing)
    columns = tuple(f"joint {j}" for j in range(arm.n_joints))
    q = _real_rows(joint_path, "joint_path", columns, 2)
    t = _real_vector(times, "times")
    if t.shape != (len(q),):
        raise URScriptError(
            f"times: expected shape ({len(q)},), one per row of joint_path, got shape {t.shape}",
            "times",
        )
    with np.errstate(over="ignore", invalid="ignore"):  # huge times: refused just below
        steps = np.diff(t)
        dt = float(steps.mean())
        uneven = not np.isfinite(dt) or np.abs(steps - dt).max() > _REL_DT_TOL * dt
    if uneven or dt <= 0:
        raise URScriptError(
            "times: must be equally spaced and increasing (resample the trajectory, "
            "e.g. Timing.resample(125))",
            "times",
        )
    # A 500 Hz stream's mean step may round to just under 2 ms: the bounds take the same slack.
    if not MIN_SERVO_DT * (1 - _REL_DT_TOL) <= dt <= MAX_SERVO_DT * (1 + _REL_DT_TOL):
        raise URScriptError(
            f"times: step {dt:.6g} s is outside [{MIN_SERVO_DT:g}, {MAX_SERVO_DT:g}] s "
            f"(one controller period is {MIN_SERVO_DT:g} s; a stream ticks every 2 to 8 ms)",
            "times",
        )
    lower, upper = arm.joint_limits[:, 0], arm.joint_limits[:, 1]
    outside = (q < lower) | (q > upper)
    if outside.any():
        i, j = _first(outside)
        raise _joint_error(
            i,
            j,
            f"{q[i, j]:.6g} rad is outside the {arm.name} joint limits "
            f"[{lower[j]:.6g}, {upper[j]:.6g}] rad",
        )
    # Velocity over each tick; the stream starts and ends at rest.
    velocity = np.diff(q, axis=0) / dt
    speed_limit = arm.max_joint_speed
    fast = np.abs(velocity) > speed_limit * (1.0 + _REL_TOL)
    if fast.any():
        k, j = _first(fast)
        raise _joint_error(
            k + 1,
            j,
            f"moves at {velocity[k, j]:.6g} rad/s from sample {k}, above the {arm.name} "
            f"limit of {speed_limit[j]:g} rad/s",
        )
    rest = np.zeros((1, arm.n_joints))
    acceleration = np.diff(np.vstack((rest, velocity, rest)), axis=0) / dt
    hard = np.abs(acceleration) > arm.max_joint_acceleration * (1.0 + _REL_TOL)
    if hard.any():
        k, j = _first(hard)
        a, limit = acceleration[k, j], arm.max_joint_acceleration[j]
        if k == 0:
            i = 1
            what = f"a step of {q[1, j] - q[0, j]:.6g} rad in {dt:g} s from rest at sample 0"
        elif k == len(q) - 1:
            i = k
            what = f"stopping after the last sample from {velocity[-1, j]:.6g} rad/s"
        else:
            i = k
            what = f"a speed change from {velocity[k - 1, j]:.6g} to {velocity[k, j]:.6g} rad/s"
        raise _joint_error(
            i, j, f"{what} needs {a:.8g} rad/s^2, above the {arm.name} limit of {limit:g} rad/s^2"
        )
    tool = ur5.forward(q, tool=workspace.tool_matrix, arm=arm)[:, :3, 3]
    workspace._refuse_outside(tool, "joint_path", "tool position")  # finite: forward kinematics
    return q, dt


# ------------------------------------------------------------------ programs
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
    workspace: Workspace = DEFAULT_WORKSPACE,
    arm: Arm = UR5,
    speed_fraction: float = 1.0,
) -> str:
    """A URScript program that plays a motion on a UR controller.

    Parameters
    ----------
    poses : array_like, shape (n, 6), optional
        Tool poses ``[x, y, z, rx, ry, rz]`` in the base frame (metres, and a
        rotation vector in radians with norm <= π), e.g. from
        :func:`lfdkit.execute.poses.pose_vector`. Required for ``"movel"``,
        must be omitted for ``"servoj"``.
    name : str
        Name of the URScript function; a valid identifier, not a URScript
        keyword or a function the program calls.
    motion : {"movel", "servoj"}
        Linear tool moves through the poses, or a joint-position stream.
    speed : float
        ``movel`` tool speed (m/s), in ``(0, 1]``.
    acceleration : float
        ``movel`` tool acceleration (m/s²), in ``(0, 5]``.
    blend_radius : float
        ``movel`` blend radius (m), in ``[0, 1]`` and below half the shortest
        distance between consecutive positions. The last move always has 0.
    times : array_like, shape (n,), optional
        ``servoj`` only: equally spaced sample times (s), as returned by
        :meth:`lfdkit.execute.timing.Timing.resample`; their spacing is the
        ``t`` of every ``servoj``, in ``[0.002, 1]`` s.
    joint_path : array_like, shape (n, 6), optional
        ``servoj`` only: joint angles (rad) at ``times``, ``n >= 2``, starting
        and ending at rest (see the module notes).
    header : str, optional
        Extra printable ASCII text for the header comment (one comment line per line).
    workspace : Workspace
        Where the tool may go (:class:`Workspace`); by default on or above the
        table plane and within the arm's reach. ``Workspace.unbounded()``
        switches the box and reach checks off.
    arm : Arm
        The UR arm that runs the program (default: the UR5); its reach, joint
        limits and kinematics are checked against.
    speed_fraction : float
        ``servoj`` only: in ``(0, 1]``, scales the ``movej`` to the first
        sample (UR's defaults ``a=1.4`` rad/s², ``v=1.05`` rad/s), so that every
        motion command stays within the fraction the stream was timed at.

    Returns
    -------
    str
        The program, ``\\n`` line endings: header comments (lfdkit version, UTC
        date, number of poses or samples, units), ``def name():`` ... ``end``
        and a final ``name()`` call.

    Raises
    ------
    URScriptTypeError
        For a value of the wrong kind (``bool``, ``str``, ``complex``,
        ``None``, an object) where a number is expected.
    URScriptError
        For a bad shape, NaN/inf, a value outside the ranges in the module
        notes, or an argument that does not belong to the chosen ``motion``;
        the message names the argument, the pose or sample index and the value.
    """
    if not isinstance(motion, str) or motion not in ("movel", "servoj"):
        raise URScriptError(f"motion: expected 'movel' or 'servoj', got {_show(motion)}", "motion")
    name = _check_name(name)
    extra = _check_header(header)
    workspace = _check_workspace(workspace)
    arm = _check_arm(arm)
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")
    lines = [f"# URScript program written by lfdkit {__version__} on {stamp}"]

    if motion == "movel":
        if times is not None or joint_path is not None:
            extra_arg = "times" if times is not None else "joint_path"
            raise URScriptError("times, joint_path: only used with motion='servoj'", extra_arg)
        if poses is None:
            raise URScriptError("poses: required with motion='movel'", "poses")
        p = workspace.check_poses(poses, arm)
        v = _scalar(speed, "speed", MAX_TOOL_SPEED, "m/s")
        a = _scalar(acceleration, "acceleration", MAX_TOOL_ACCELERATION, "m/s^2")
        r = _scalar(blend_radius, "blend_radius", MAX_BLEND_RADIUS, "m", allow_lower=True)
        if r > 0:
            seg = np.linalg.norm(np.diff(p[:, :3], axis=0), axis=1)
            if len(seg) and r >= 0.5 * seg.min():
                k = int(np.argmin(seg))
                raise URScriptError(
                    f"blend_radius: {r:g} m is not below half the shortest move "
                    f"({seg[k]:.4g} m between poses {k} and {k + 1})",
                    "blend_radius",
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
    else:
        if poses is not None:
            raise URScriptError(
                "poses: not used with motion='servoj'; pass joint_path and times", "poses"
            )
        q, dt = _check_servo(joint_path, times, workspace, arm)
        lines += [
            f"# {len(q)} samples, servoj every {format_number(dt)} s "
            f"({format_number(dt * (len(q) - 1))} s): joint angles in radians",
            f"# lookahead_time {SERVO_LOOKAHEAD} s, gain {SERVO_GAIN}; starts with movej "
            "to the first sample",
        ]
        f = _scalar(speed_fraction, "speed_fraction", 1.0, "")
        # UR's movej defaults scaled like the speed slider: the approach as gentle as the stream.
        body = [
            f"movej([{_fmt_list(q[0])}], a={format_number(1.4 * f)}, v={format_number(1.05 * f)})"
        ]
        tail = f", t={format_number(dt)}, lookahead_time={SERVO_LOOKAHEAD}, gain={SERVO_GAIN})"
        body += [f"servoj([{_fmt_list(row)}]{tail}" for row in q]

    lines += extra
    lines.append(f"def {name}():")
    lines += [f"  {line}" for line in body]
    lines += ["end", f"{name}()"]
    return "\n".join(lines) + "\n"


def write_urscript(path: PathLike, program: str, *, overwrite: bool = False) -> Path:
    """Write a URScript program to a file, atomically (:func:`lfdkit.io.write_text`).

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
        The script's file.

    Raises
    ------
    URScriptTypeError
        If ``program`` is not a str.
    URScriptError
        If ``program`` is empty or not ASCII.
    FileExistsError, IsADirectoryError, FileNotFoundError
        As :func:`lfdkit.io.write_text`, e.g. ``path`` exists and
        ``overwrite`` is false.
    """
    if not isinstance(program, str):
        raise URScriptTypeError(f"program: expected a str, got {type(program).__name__}", "program")
    if not program.strip():
        raise URScriptError("program: is empty", "program")
    if not program.isascii():
        raise URScriptError(
            "program: must be ASCII text (UR controllers read ASCII scripts)", "program"
        )
    text = program if program.endswith("\n") else program + "\n"
    return write_text(path, text, overwrite=overwrite)
