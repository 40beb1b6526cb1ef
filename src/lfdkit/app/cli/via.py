"""``--via X,Y[,Z]@T[:QX,QY,QZ,QW]``: via-points on the command line (``plan``, ``plot``,
``execute``, ``batch evaluate``).

A via-point is a point and when to pass it: ``T`` a phase strictly between 0
and 1 (``0.5``), a percentage of the movement (``50%``) or seconds from the
start (``2.1s``, within the plan's duration); for a skill with orientation,
optionally the tool's orientation there after a colon, a unit quaternion
``x,y,z,w`` (``@50%:0,0,0.7071,0.7071``). The option repeats, one
via-point each. Every mistake is one line naming the option and the value
(:class:`~lfdkit.app.cli.common.UsageError`, exit 2): no ``@``, a coordinate
that is not a number, the wrong count of coordinates for the skill, a phase
outside (0, 1), a time past the plan's end, an unknown unit of time, an
orientation that is not 4 numbers of norm 1.
"""

from __future__ import annotations

import argparse
import math
import re

from lfdkit.app.cli.common import UsageError
from lfdkit.core.numbers import parse_decimal

__all__ = ["add_via_option", "via_points"]

_FORM = (
    "X,Y[,Z]@T[:QX,QY,QZ,QW] (T a phase 0<T<1, a percentage like 40% or seconds like 1.5s; "
    "optionally the orientation there, a unit quaternion)"
)


def add_via_option(parser: argparse.ArgumentParser) -> None:
    """Add the repeatable ``--via`` option (raw text; :func:`via_points` checks it)."""
    parser.add_argument(
        "--via",
        action="append",
        metavar="X,Y[,Z]@T[:QX,QY,QZ,QW]",
        help="pass through this point (path units) at T: a phase 0<T<1 of the movement, a "
        "percentage (40%%) or seconds from the start (1.5s); repeat for several. The nominal "
        "bends through it the way the demonstrations varied (their ProMP). A skill with "
        "orientation takes the tool's orientation there after a colon, a unit quaternion "
        "(e.g. @50%%:0,0,0.7071,0.7071); start and goal orientation are kept",
    )


def via_points(
    texts: list[str] | None, n_dims: int, duration: float
) -> list[tuple[float, list[float]] | tuple[float, list[float], list[float]]] | None:
    """The ``--via`` values as :meth:`lfdkit.skill.Skill.plan`'s ``via``.

    ``[(phase, point)]``, or ``(phase, point, orientation)`` for a value with
    an orientation (whether the skill has one is :meth:`~lfdkit.skill.Skill.plan`'s
    to say).

    Parameters
    ----------
    texts : list of str or None
        The option's values, as typed.
    n_dims : int
        The skill's dimension.
    duration : float
        Seconds the plan lasts (to turn a time into a phase).

    Raises
    ------
    UsageError
        One line naming ``--via`` and the value, for any mistake.
    """
    if not texts:
        return None
    return [_via_point(text, n_dims, duration) for text in texts]


def _via_point(text: str, n_dims: int, duration: float) -> tuple:
    where, sep, when = text.rpartition("@")
    if not sep:
        raise UsageError(f"--via {text!r}: no '@T'; expected {_FORM}")
    when, colon, turn = when.partition(":")
    orientation = _orientation(text, turn) if colon else None
    try:
        point = [parse_decimal(v) for v in where.split(",")]
    except ValueError:
        if re.search(r"[0-9.](m|cm|mm)\s*(,|$)", where):
            raise UsageError(
                f"--via {text!r}: coordinates take no unit; give plain numbers in the path's "
                "units (the skill's, or --units)"
            ) from None
        raise UsageError(
            f"--via {text!r}: the point {where!r} is not finite numbers separated by commas; "
            f"expected {_FORM}"
        ) from None
    if len(point) != n_dims:
        raise UsageError(
            f"--via {text!r}: {len(point)} coordinates for a {n_dims}-D skill; "
            f"give {n_dims} (path units)"
        )
    word = when.strip()
    # A trailing unit of time; "1e-3" is a number, not "1" in unit "e-3".
    unit = re.search(r"(%|[a-zA-Z]+)$", word)
    suffix = unit.group(0) if unit else ""
    try:
        number = parse_decimal(word[: len(word) - len(suffix)].strip())
    except ValueError:
        raise UsageError(
            f"--via {text!r}: when {when!r} is not a number; expected {_FORM}"
        ) from None
    if suffix == "":
        phase = number
    elif suffix == "%":
        phase = number / 100.0
    elif suffix.lower() in ("s", "ms"):
        seconds = number / (1000.0 if suffix.lower() == "ms" else 1.0)
        if not 0.0 < seconds < duration:
            raise UsageError(
                f"--via {text!r}: {seconds:g} s is not within the plan, which lasts "
                f"{duration:.4g} s; give a time strictly between 0 and {duration:.4g} s"
            )
        phase = seconds / duration
    else:
        raise UsageError(
            f"--via {text!r}: unknown unit of time {suffix!r}; give a phase (0.4), "
            "a percentage (40%) or seconds (1.5s)"
        )
    if not 0.0 < phase < 1.0:
        raise UsageError(
            f"--via {text!r}: phase {phase:g} is outside (0, 1); give when to pass the point "
            "as a fraction of the movement (0 is the start, 1 the goal: those are --start "
            "and --goal)"
        )
    return (phase, point) if orientation is None else (phase, point, orientation)


def _orientation(text: str, turn: str) -> list[float]:
    """The orientation after ``:``: four numbers of norm 1 (within the library's tolerance)."""
    try:
        q = [parse_decimal(v) for v in turn.split(",")]
    except ValueError:
        raise UsageError(
            f"--via {text!r}: the orientation {turn!r} is not numbers separated by commas; "
            "give a unit quaternion QX,QY,QZ,QW"
        ) from None
    if len(q) != 4:
        raise UsageError(
            f"--via {text!r}: the orientation has {len(q)} values; give a unit quaternion "
            "QX,QY,QZ,QW (4 values)"
        )
    # Here, not at the top: building the parser must not load NumPy (rotations does).
    from lfdkit.core.rotations import UNIT_NORM_TOLERANCE

    norm = math.sqrt(sum(v * v for v in q))
    if abs(norm - 1.0) > UNIT_NORM_TOLERANCE:
        raise UsageError(
            f"--via {text!r}: the orientation has norm {norm:.6g}; a unit quaternion's norm is "
            f"1 (within {UNIT_NORM_TOLERANCE:g}): normalise it"
        )
    return q
