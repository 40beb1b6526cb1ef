"""Numbers as people type them: one strict parser for the command line and the CSV readers.

Python's ``float`` reads more than decimal numbers: ``1_0`` is 10 (a digit
separator), ``nan``, ``inf`` and ``infinity`` are numbers, and so are digits of
other scripts. A goal typed ``1_0,0.5`` then plans to a point 10 m away
without a word. Every number lfdkit reads from text goes through
:func:`parse_decimal` (or :func:`parse_whole` for counts), which accepts the
decimal spellings only (``12``, ``-0.5``, ``.5``, ``1.``, ``1e-3``).

Import-free (standard library only): the command line parses its options
before NumPy is loaded.
"""

from __future__ import annotations

import math
import re

__all__ = ["DECIMAL", "WHOLE", "parse_decimal", "parse_whole"]

#: A decimal number: no digit separators, inner spaces, hexadecimal or nan/inf words.
DECIMAL = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
#: A whole number in decimal digits.
WHOLE = re.compile(r"[+-]?[0-9]+")


def parse_decimal(text: str, *, finite: bool = True) -> float:
    """``text`` (surrounding spaces ignored) as a float, strictly.

    Raises
    ------
    ValueError
        If ``text`` is not a decimal number (the message says why: a digit
        separator, NaN or infinity), or, with ``finite``, overflows to infinity
        (``1e999``).
    """
    cell = text.strip() if isinstance(text, str) else text
    if not isinstance(cell, str) or DECIMAL.fullmatch(cell) is None:
        if isinstance(cell, str) and "_" in cell:
            raise ValueError(f"{text!r} is not a number: digit separators ('_') are not allowed")
        if isinstance(cell, str) and cell.lower().lstrip("+-") in ("nan", "inf", "infinity"):
            raise ValueError(f"{text!r} is not finite; NaN and infinity are not allowed")
        raise ValueError(f"{text!r} is not a decimal number")
    value = float(cell)
    if finite and not math.isfinite(value):
        raise ValueError(f"{text!r} is not finite (too large); NaN and infinity are not allowed")
    return value


def parse_whole(text: str) -> int:
    """``text`` (surrounding spaces ignored) as an int, strictly (no ``1_000``, no ``1e3``)."""
    cell = text.strip() if isinstance(text, str) else text
    if not isinstance(cell, str) or WHOLE.fullmatch(cell) is None:
        hint = ": digit separators ('_') are not allowed" if "_" in str(cell) else ""
        raise ValueError(f"{text!r} is not a whole number{hint}")
    return int(cell)
