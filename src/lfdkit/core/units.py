"""Length units: the ones lfdkit knows, and exact conversion factors between them.

Every length lfdkit stores (demonstrations, paths, obstacles, clearances) is in
one unit, chosen by whoever recorded the data: a :class:`lfdkit.skill.Skill`
keeps it in its ``units`` parameter (and ``skill.json`` in ``"units"``), data
sets in their ``units`` attribute, and plots and tables show it. Quantities
derived from lengths follow: a reward's nominal weight ``Q`` and precisions
``P_c`` are in 1/units², squared errors (e1, MSE) in units².

The module is plain Python (no NumPy), so the command line can read
:data:`UNITS` without loading the library.

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

from typing import Any

__all__ = ["UNITS", "check_units", "conversion_factor"]

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
