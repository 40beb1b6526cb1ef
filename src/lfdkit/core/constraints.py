"""Declarative parameter checks: what an estimator's parameters must be, as a table.

An estimator lists its constructor parameters with one constraint each in a
class attribute, as scikit-learn's ``_parameter_constraints`` does::

    class DMP(Primitive):
        _parameter_constraints = {"scaling": OneOf(SCALINGS), "end": OneOf(("rest", "free"))}

and :meth:`lfdkit.core.estimator.Estimator._validate_params` checks them all,
once, when ``fit`` starts, in the order listed (a base class's table first, so
a subclass adds only its own rows). Each constraint is a callable
``constraint(value, name)`` that returns the value checked (an ``int`` for an
integer, a ``float`` for a number) or raises the one-line error of
:mod:`lfdkit.core.validation`, "name: what is wrong", naming the value. What
ties two parameters together (a DMP ending at rest needs 4 basis functions)
stays a line of code after the table.

Why a table: the same ten checks were written by hand in every estimator's
``_check_params``, each choice with its own wording of "expected one of"; the
table says what a parameter may be where the parameters are listed, and one
wording serves all.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from lfdkit.core.validation import MAX_POINTS, check_count, check_positive

__all__ = ["Checked", "InstanceOf", "Integer", "OneOf", "Real", "choices_text"]


def choices_text(choices: tuple[Any, ...]) -> str:
    """``'a', 'b', 'c'``: the choices as an error message lists them."""
    return ", ".join(map(repr, choices))


@dataclass(frozen=True)
class Real:
    """A finite number above 0 (or at 0 with ``allow_zero``), at most ``maximum``.

    Parameters
    ----------
    allow_zero : bool
        Accept 0.
    maximum : float, optional
        The largest value accepted.
    meaning : str
        What the bounded value is ("a fraction of the path's extent"), said
        when it exceeds ``maximum``.
    optional : bool
        Accept None (a default computed later).
    options : tuple of str
        Strings accepted as they are (``"auto"``).
    """

    allow_zero: bool = False
    maximum: float | None = None
    meaning: str = ""
    optional: bool = False
    options: tuple[str, ...] = ()

    def __call__(self, value: Any, name: str) -> float | str | None:
        if value is None and self.optional:
            return None
        if self.options and isinstance(value, str):
            if value in self.options:
                return value
            raise ValueError(
                f"{name}: expected a number or {choices_text(self.options)}, got {value!r}"
            )
        value = check_positive(value, name, allow_zero=self.allow_zero)
        if self.maximum is not None and value > self.maximum:
            what = f"{self.meaning}, " if self.meaning else ""
            low = "0 <=" if self.allow_zero else "0 <"
            raise ValueError(
                f"{name}: expected {what}{low} {name} <= {self.maximum:g}, got {value:g}"
            )
        return value


@dataclass(frozen=True)
class Integer:
    """An integer (not a bool) from ``minimum`` to ``maximum``, or one of the strings ``options``.

    Parameters
    ----------
    minimum : int
        The smallest value accepted (0 or more).
    maximum : int, optional
        The largest (default: no bound for ``minimum`` 0 or 1, else
        :data:`~lfdkit.core.validation.MAX_POINTS`).
    options : tuple of str
        Strings accepted as they are (``"auto"``).
    """

    minimum: int = 1
    maximum: int | None = None
    options: tuple[str, ...] = ()

    def __call__(self, value: Any, name: str) -> int | str:
        if self.options and isinstance(value, str):
            if value in self.options:
                return value
            raise ValueError(
                f"{name}: expected an integer or {choices_text(self.options)}, got {value!r}"
            )
        if self.maximum is None and self.minimum <= 1:
            return check_positive(value, name, integer=True, allow_zero=self.minimum == 0)
        maximum = MAX_POINTS if self.maximum is None else self.maximum
        return check_count(value, name, minimum=self.minimum, maximum=maximum)


@dataclass(frozen=True)
class OneOf:
    """One of ``choices`` (compared with ``==``)."""

    choices: tuple[Any, ...]

    def __call__(self, value: Any, name: str) -> Any:
        if value not in self.choices:
            raise ValueError(f"{name}: expected one of {choices_text(self.choices)}, got {value!r}")
        return value


@dataclass(frozen=True)
class InstanceOf:
    """An instance of ``kind`` (or None with ``optional``); ``TypeError`` otherwise."""

    kind: type
    optional: bool = False

    def __call__(self, value: Any, name: str) -> Any:
        if value is None and self.optional:
            return None
        if not isinstance(value, self.kind):
            raise TypeError(f"{name}: expected a {self.kind.__name__}, got {type(value).__name__}")
        return value


@dataclass(frozen=True)
class Checked:
    """A check function of lfdkit's own, ``check(value, name)`` (or None with ``optional``)."""

    check: Callable[[Any, str], Any]
    optional: bool = False

    def __call__(self, value: Any, name: str) -> Any:
        if value is None and self.optional:
            return None
        return self.check(value, name)
