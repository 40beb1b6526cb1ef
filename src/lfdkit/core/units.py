"""Length units: the ones lfdkit knows, and exact conversion factors between them.

Every length lfdkit stores (demonstrations, paths, obstacles, clearances) is in
one unit, chosen by whoever recorded the data: a :class:`lfdkit.skill.Skill`
keeps it in its ``units`` parameter (and ``skill.json`` in ``"units"``), data
sets in their ``units`` attribute, and plots and tables show it. Quantities
derived from lengths follow: a reward's nominal weight ``Q`` and precisions
``P_c`` are in 1/units², squared errors (e1, MSE) in units².

The module is plain Python (no NumPy), so the command line can read
:data:`UNITS` without loading the library.

Units are checked where demonstrations enter (issue 31): a millimetre file
learned as metres made a skill whose plans reported 436.9 m/s.
:func:`implausible_units` is the rule. Converted to metres, demonstrations
that span more than :data:`MAX_EXTENT_M` (20 m) or move faster than
:data:`MAX_MEAN_SPEED_M_S` (5 m/s, mean speed over a timed demonstration; a
hand moves at well under 2 m/s) or span less than :data:`MIN_EXTENT_M` (1 mm),
or in centimetres less than :data:`MIN_EXTENT_CM` (2 cm: a 0.8 m reach in metres
read as centimetres), are not in the unit claimed. 20 m, not 5: lfdkit's own synthetic "metre"
sets span up to 11.4 m and a walking data set 7.1 m, and none of its 47
built-in sets (LASA included) trips the rule. What it misses: untimed
centimetre data spanning under 20 cm read as metres, untimed millimetre data
under 20 mm read as metres, and metres read as centimetres spanning over 2 m
(their speed, when timed, gives the first two away).
:meth:`lfdkit.skill.Skill.fit` warns (:class:`UnitsWarning`);
``lfdkit learn`` and ``lfdkit batch learn`` refuse when no ``--units`` was
given, naming the likely unit.

Examples
--------
>>> conversion_factor("m", "mm")
1000.0
>>> conversion_factor("mm", "cm")
0.1
>>> check_units("inch")
Traceback (most recent call last):
...
ValueError: units: expected one of 'm', 'cm', 'mm', got 'inch'
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

__all__ = [
    "MAX_EXTENT_M",
    "MAX_MEAN_SPEED_M_S",
    "MIN_EXTENT_CM",
    "MIN_EXTENT_M",
    "UNITS",
    "UnitsWarning",
    "check_units",
    "conversion_factor",
    "implausible_units",
    "likely_units",
    "misplaced_units",
]

#: Length units lfdkit knows, by name (``--units`` on the command line).
UNITS: tuple[str, ...] = ("m", "cm", "mm")

# Micrometres per unit: integers, so that every factor is one correctly rounded division.
_MICROMETRES = {"m": 1_000_000, "cm": 10_000, "mm": 1_000}


def check_units(units: Any, name: str = "units") -> str:
    """``units`` if it is one of :data:`UNITS`, else a ``ValueError`` naming ``name``.

    Parameters
    ----------
    units : object
        The value to check.
    name : str
        The argument's name, which starts the error message.

    Returns
    -------
    str
        ``units``.

    Raises
    ------
    ValueError
        If ``units`` is not one of ``"m"``, ``"cm"``, ``"mm"`` (the message
        lists them).
    """
    if not isinstance(units, str) or units not in _MICROMETRES:
        choices = ", ".join(repr(u) for u in UNITS)
        raise ValueError(f"{name}: expected one of {choices}, got {units!r}")
    return units


def conversion_factor(from_units: str, to_units: str) -> float:
    """The number a length in ``from_units`` is multiplied by to be in ``to_units``.

    Parameters
    ----------
    from_units, to_units : {"m", "cm", "mm"}
        The units converted from and to.

    Returns
    -------
    float
        ``1000.0`` from ``"m"`` to ``"mm"``, ``0.01`` from ``"cm"`` to
        ``"m"``, exactly ``1.0`` between equal units. Squared lengths take
        the factor squared; 1/length² (precisions, weights) its inverse
        squared.

    Raises
    ------
    ValueError
        If either unit is not one of :data:`UNITS` (the message names
        ``from_units`` or ``to_units``).
    """
    source = _MICROMETRES[check_units(from_units, "from_units")]
    target = _MICROMETRES[check_units(to_units, "to_units")]
    return source / target


#: Largest span (m) of a demonstration set accepted as given: no arm reaches, and no
#: hand-guided demonstration spans, 20 m (lfdkit's synthetic sets span up to 11.4 m).
MAX_EXTENT_M = 20.0
#: Smallest span (m): a demonstration under 1 mm is metres read as millimetres.
MIN_EXTENT_M = 1e-3
#: Smallest span of a whole task recorded in centimetres (cm): an arm's task spans tens
#: of centimetres, and one of a few millimetres (a small insertion) is recorded in
#: millimetres, whose floor stays :data:`MIN_EXTENT_M`. A 0.8 m reach recorded in metres
#: and learned as centimetres spans 0.8 cm: it passed the 1 mm floor.
MIN_EXTENT_CM = 2.0
#: Fastest mean speed (m/s) of a timed demonstration: a hand guiding a tool moves at
#: well under 2 m/s (LASA's handwriting peaks at 0.07 m/s).
MAX_MEAN_SPEED_M_S = 5.0

# The span (m) a demonstration typically has: the suggested unit brings the data nearest it.
_TYPICAL_EXTENT_M = 0.5


class UnitsWarning(UserWarning):
    """Demonstrations whose size or speed is implausible in their stated unit.

    ``likely`` is the unit they are probably in (:func:`likely_units`);
    ``detail`` the numbers without the fix, for a caller that words its own
    (``lfdkit learn`` says ``--units mm``).
    """

    def __init__(self, message: str, likely: str | None = None, detail: str = "") -> None:
        super().__init__(message)
        self.likely = likely
        self.detail = detail or message


def likely_units(extent: float, units: str) -> str:
    """The unit in which a span of ``extent`` (in ``units``) is nearest a typical demonstration's.

    Parameters
    ----------
    extent : float
        The demonstrations' largest span along one axis, in ``units``.
    units : {"m", "cm", "mm"}
        The unit ``extent`` was given in.

    Returns
    -------
    str
        One of :data:`UNITS` other than ``units``: e.g. ``"mm"`` for 800
        read as metres (0.8 m), ``"cm"`` for 80 (0.8 m).
    """
    check_units(units)
    others = [u for u in UNITS if u != units]
    if not extent > 0.0:
        return others[0]
    return min(
        others,
        key=lambda u: abs(math.log(extent * conversion_factor(u, "m") / _TYPICAL_EXTENT_M)),
    )


def implausible_units(extent: float, units: str, mean_speed: float | None = None) -> str | None:
    """Why demonstrations of this size and speed are not in ``units``; None when plausible.

    Parameters
    ----------
    extent : float
        The demonstrations' largest span along one axis, in ``units``.
    units : {"m", "cm", "mm"}
        Their stated unit.
    mean_speed : float, optional
        The fastest demonstration's mean speed (path length over duration),
        in ``units`` per second; None for untimed demonstrations.

    Returns
    -------
    str or None
        A clause naming the numbers and the rule, e.g. ``"they span 800 m,
        more than a demonstration can (over 20 m)"``.

    Examples
    --------
    >>> implausible_units(0.8, "m") is None
    True
    >>> implausible_units(800.0, "m")
    'they span 800 m, more than a demonstration can (over 20 m)'
    """
    check_units(units)
    in_m = conversion_factor(units, "m")
    shown = f"{extent:.4g} {units}"
    if extent * in_m > MAX_EXTENT_M:
        return f"they span {shown}, more than a demonstration can (over {MAX_EXTENT_M:g} m)"
    if mean_speed is not None and mean_speed * in_m > MAX_MEAN_SPEED_M_S:
        return (
            f"they move at {mean_speed:.4g} {units}/s on average, faster than a hand "
            f"(over {MAX_MEAN_SPEED_M_S:g} m/s)"
        )
    if extent * in_m < MIN_EXTENT_M:
        return f"they span {shown}, less than a demonstration can (under {MIN_EXTENT_M * 1e3:g} mm)"
    if units == "cm" and extent < MIN_EXTENT_CM:
        return (
            f"they span {shown}, less than a task recorded in centimetres does (under "
            f"{MIN_EXTENT_CM:g} cm; one that small is recorded in mm)"
        )
    return None


def misplaced_units(
    point: Sequence[float],
    low: Sequence[float],
    high: Sequence[float],
    units: str,
    size: float = 0.0,
) -> str | None:
    """The unit a point far from a workspace is probably in, when another unit brings it inside.

    A goal typed in metres for a skill in millimetres lies near the origin,
    hundreds of millimetres from every demonstration; read as metres (×1000)
    it lies among them. A point is said to be misplaced when it lies more
    than half the workspace's largest span outside the workspace's bounding
    box and, converted from another unit, within that box grown by a quarter
    of the span. A point near the origin stays near it in any unit, so a
    real target far from the demonstrations is not flagged unless a unit
    change brings it among them. An obstacle (``size`` > 0) near the origin
    is misplaced too where its size is below :data:`MIN_EXTENT_M` (a box
    given in metres to a skill in millimetres: a carton 0.2 mm long) and
    another unit makes it at least that large, no larger than the
    workspace's span, and brings its position within the grown box.

    Parameters
    ----------
    point : sequence of float, length q
        The point as given, in ``units``.
    low, high : sequence of float, length q
        Corners of the workspace's bounding box (e.g. the demonstrations'
        smallest and largest coordinates), in ``units``.
    units : {"m", "cm", "mm"}
        The unit the point was read in.
    size : float
        An obstacle's largest extent in ``units`` (0: a point, or not known).

    Returns
    -------
    str or None
        The unit in which ``point`` lies in the workspace, or None when it
        lies near the workspace or no unit brings it there.

    Examples
    --------
    >>> misplaced_units([0.35, 0.5], [-400.0, 450.0], [400.0, 500.0], "mm")
    'm'
    >>> misplaced_units([350.0, 500.0], [-400.0, 450.0], [400.0, 500.0], "mm") is None
    True
    >>> misplaced_units([0.3, 0.2], [-400.0, 0.0], [400.0, 500.0], "mm") is None
    True
    >>> misplaced_units([0.3, 0.2], [-400.0, 0.0], [400.0, 500.0], "mm", size=0.2)
    'm'
    """
    check_units(units)
    span = max(h - lo for lo, h in zip(low, high, strict=True))
    if not span > 0.0:
        return None

    def outside(values: Sequence[float], grow: float) -> float:
        excess = (
            max(lo - grow - v, v - h - grow, 0.0)
            for v, lo, h in zip(values, low, high, strict=True)
        )
        return math.sqrt(sum(e * e for e in excess))

    if not outside(point, 0.0) > 0.5 * span:
        tiny = 0.0 < size * conversion_factor(units, "m") < MIN_EXTENT_M
        if not tiny:
            return None
        for other in UNITS:  # largest first: metres typed for millimetres is the usual slip
            factor = conversion_factor(other, units)
            grown = size * factor
            if factor > 1.0 and conversion_factor(units, "m") * grown >= MIN_EXTENT_M:
                if grown <= span and outside([factor * v for v in point], 0.25 * span) == 0.0:
                    return other
        return None
    for other in UNITS:
        if other == units:
            continue
        factor = conversion_factor(other, units)
        if outside([factor * v for v in point], 0.25 * span) == 0.0:
            return other
    return None
