"""What every mimicking method promises, and the registry that lists them.

The contract
------------
A mimicking method is a scikit-learn style estimator: parameters in the
constructor, ``fit(demos)`` returns ``self``, and a fitted one has

* ``path_`` : ndarray, shape (n_points, q), the generalized path, from the
  demonstrations' start to their end, in their units;
* ``reversed_`` : ndarray of bool, shape (n_demos,), the demonstrations it
  turned round to the majority's direction (:func:`lfdkit.mimic.orient_demos`);
* ``length_ratio_`` : float, the path's length over the median
  demonstration's (:func:`lfdkit.mimic.check_one_motion`);
* ``converged_`` : bool, whether its fit converged.

:class:`Mimic` states this as a :class:`typing.Protocol`. A method whose
``fit`` also takes ``check_input=False`` (every built-in one) says so with
:attr:`MimicMethod.check_input`: a caller that has validated the
demonstrations already (:meth:`lfdkit.skill.Skill.fit_path`) then hands them
over without a second check.

The registry
------------
:data:`MIMIC_METHODS` maps a short key (``"mean_path"``) to a
:class:`MimicMethod`: how to build the estimator from a few common settings,
the name shown in tables, legends and messages, its colour in every figure,
and which of its fitted values a skill records. The skill
(:class:`lfdkit.skill.Skill`, its ``mimic`` parameter), the command line's
``--mimic`` choices, the method comparison (:mod:`lfdkit.app.evaluation`) and the
figures' colours (:mod:`lfdkit.app.plot`) all read it, so a new method is its
module plus one :func:`register` call there, and the import of that module in
:mod:`lfdkit.mimic`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

import numpy as np

__all__ = ["MIMIC_METHODS", "Mimic", "MimicMethod", "MimicSettings", "register"]


@runtime_checkable
class Mimic(Protocol):
    """A fitted mimicking estimator (see the module notes)."""

    path_: np.ndarray
    reversed_: np.ndarray
    length_ratio_: float
    converged_: bool

    def fit(self, demos: list[np.ndarray], y: None = None) -> Mimic: ...


@dataclass(frozen=True)
class MimicSettings:
    """The settings a caller has for any method; each method takes what it uses.

    Parameters
    ----------
    n_points : int
        Points of the generalized path.
    random_state : int or None
        Seed of any random initialisation.
    n_components : int
        Mixture components, for methods that have them (GMR).
    length_scale : float
        One metre in the demonstrations' units (1000 for millimetres), for
        methods that are not scale-invariant and fit in a fixed unit (GMR's
        ``length_scale``); the others are scale-invariant and ignore it.
    """

    n_points: int = 100
    random_state: int | None = None
    n_components: int = 10
    length_scale: float = 1.0


@dataclass(frozen=True)
class MimicMethod:
    """One registered mimicking method.

    Parameters
    ----------
    key : str
        Short name used in code, skill files and on the command line.
    label : str
        Name shown in tables, legends and messages.
    color : str
        Matplotlib colour of its path in every figure.
    build : callable
        ``build(settings)`` → an unfitted estimator following :class:`Mimic`.
    diagnostics : callable
        ``diagnostics(fitted)`` → a JSON-ready dict of what a skill records
        about the fit (iterations, residual, ...).
    uses : tuple of str
        Which :class:`MimicSettings` fields ``build`` reads; a comparison need
        not choose the others (e.g. a number of components) for it.
    check_input : bool
        Whether the estimator's ``fit(demos, check_input=False)`` skips checking
        demonstrations its caller validated already (:func:`lfdkit.core.validation.check_demos`:
        a list of finite float64 arrays of one dimension). False (the default): ``fit``
        is always called with the demonstrations alone.
    """

    key: str
    label: str
    color: str
    build: Callable[[MimicSettings], Mimic]
    diagnostics: Callable[[Any], dict[str, Any]] = field(default=lambda fitted: {})
    uses: tuple[str, ...] = ("n_points",)
    check_input: bool = False

    def fit(self, estimator: Mimic, demos: list[np.ndarray]) -> Mimic:
        """``estimator.fit(demos)`` for demonstrations validated already (see ``check_input``)."""
        if self.check_input:
            return estimator.fit(demos, check_input=False)
        return estimator.fit(demos)


MIMIC_METHODS: dict[str, MimicMethod] = {}
"""Every registered method by key, in registration order."""


def register(method: MimicMethod) -> MimicMethod:
    """Add a method to :data:`MIMIC_METHODS` (its key and label must be new).

    Returns
    -------
    MimicMethod
        ``method``, so that a module can keep it under a name.
    """
    if method.key in MIMIC_METHODS:
        raise ValueError(f"method: the key {method.key!r} is already registered")
    if any(m.label == method.label for m in MIMIC_METHODS.values()):
        raise ValueError(f"method: the label {method.label!r} is already registered")
    unknown = set(method.uses) - set(MimicSettings.__dataclass_fields__)
    if unknown:
        raise ValueError(f"method: uses unknown settings {sorted(unknown)}")
    MIMIC_METHODS[method.key] = method
    return method
