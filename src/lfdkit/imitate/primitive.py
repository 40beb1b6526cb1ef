"""The base of lfdkit's movement primitives: what the position and orientation DMPs share.

:class:`lfdkit.imitate.DMP` (positions) and :class:`lfdkit.imitate.QuaternionDMP`
(unit quaternions, a DMP of the orientation error) take the same seven
parameters — the basis (``n_basis``, ``basis_tol``), the spring (``k``, ``c``),
the canonical system's decay (``alpha``), the default temporal scaling
(``tau``) and the ridge term (``regularization``) — with one default each and
one check each, here (``_parameter_constraints``, checked when ``fit`` starts).
The orientation DMP hands them to the position DMP it wraps
(:meth:`Primitive.primitive_params`), so both refuse a bad value with the same
one-line message, and a change of default reaches both.

The defaults are the thesis's spring (``k = 156.25``, ``c = 25``, critically
damped: ``c² = 4k``) and the Skill's basis (``n_basis="auto"``: the smallest
count of :data:`lfdkit.imitate.BASIS_LADDER` within ``basis_tol = 1 %`` of the
path's extent). Both movements end at rest (``end="rest"``), which puts 3
constraints on each dimension's weights, so at least 4 basis functions.
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Any, ClassVar, Literal

import numpy as np

from lfdkit.core.constraints import Checked, Integer, Real
from lfdkit.core.estimator import Estimator
from lfdkit.core.options import SKILL_DEFAULTS
from lfdkit.core.validation import check_positive

__all__ = ["MAX_BASIS", "MAX_TAU", "PRIMITIVE_DEFAULTS", "Primitive", "check_tau"]

#: Most basis functions a caller may ask for, so that a typo is an error naming the
#: argument, not a MemoryError deep inside NumPy.
MAX_BASIS = 1000
#: Temporal scalings outside [1/MAX_TAU, MAX_TAU] are refused.
MAX_TAU = 1e6
#: The canonical system's default decay: ``Z`` falls to 0.01 at the end of the movement.
DEFAULT_ALPHA = float(np.log(100.0))
#: The one default of each shared parameter, read by both DMPs' signatures (read-only):
#: the thesis's critically damped spring and the Skill's basis (``alpha=None``: ln 100).
PRIMITIVE_DEFAULTS = MappingProxyType(
    {
        "n_basis": SKILL_DEFAULTS["n_basis"],
        "k": 156.25,
        "c": 25.0,
        "alpha": None,
        "tau": 1.0,
        "regularization": 1e-8,
        "basis_tol": 0.01,
    }
)


def check_tau(tau: Any, name: str = "tau") -> float:
    """Check a temporal scaling: finite, within ``[1/MAX_TAU, MAX_TAU]``; return it."""
    tau = check_positive(tau, name)
    if not 1.0 / MAX_TAU <= tau <= MAX_TAU:
        raise ValueError(f"{name}: expected {1.0 / MAX_TAU:g} to {MAX_TAU:g}, got {tau:g}")
    return tau


class Primitive(Estimator):
    """The parameters, checks and phase shared by the position and orientation DMPs.

    Parameters
    ----------
    n_basis : int or "auto", default "auto"
        Basis functions per dimension, 1 to :data:`MAX_BASIS`, or ``"auto"``
        (the smallest count of the basis ladder within ``basis_tol``).
    k, c : float
        Spring and damping in normalised time (thesis: 156.25 and 25).
    alpha : float, optional
        Decay rate of the canonical system (default ``ln 100``).
    tau : float
        Default temporal scaling of rollouts (1e-6 to 1e6).
    regularization : float
        Ridge term relative to the mean diagonal of ``XᵀX`` (>= 0).
    basis_tol : float
        With ``n_basis="auto"``: the largest reproduction error accepted, as a
        fraction of the path's extent (``0 < basis_tol <= 1``).
    """

    _parameter_constraints: ClassVar[dict[str, Any]] = {
        "n_basis": Integer(maximum=MAX_BASIS, options=("auto",)),
        "basis_tol": Real(maximum=1.0, meaning="a fraction of the path's extent"),
        "k": Real(),
        "c": Real(),
        "alpha": Real(optional=True),
        "tau": Checked(check_tau),
        "regularization": Real(allow_zero=True),
    }

    def __init__(
        self,
        n_basis: int | Literal["auto"] = PRIMITIVE_DEFAULTS["n_basis"],
        k: float = PRIMITIVE_DEFAULTS["k"],
        c: float = PRIMITIVE_DEFAULTS["c"],
        alpha: float | None = PRIMITIVE_DEFAULTS["alpha"],
        tau: float = PRIMITIVE_DEFAULTS["tau"],
        regularization: float = PRIMITIVE_DEFAULTS["regularization"],
        basis_tol: float = PRIMITIVE_DEFAULTS["basis_tol"],
    ) -> None:
        self.n_basis = n_basis
        self.k = k
        self.c = c
        self.alpha = alpha
        self.tau = tau
        self.regularization = regularization
        self.basis_tol = basis_tol

    def primitive_params(self) -> dict[str, Any]:
        """The seven shared parameters by name (for the DMP an orientation DMP wraps)."""
        names = ("n_basis", "k", "c", "alpha", "tau", "regularization", "basis_tol")
        return {name: getattr(self, name) for name in names}

    @property
    def _auto_basis(self) -> bool:
        return isinstance(self.n_basis, str) and self.n_basis == "auto"

    def _check_rest_basis(self, end: str) -> None:
        """An end at rest constrains the weights three times: at least 4 basis functions."""
        if end == "rest" and not self._auto_basis and self.n_basis < 4:
            raise ValueError(
                f"n_basis: end='rest' puts 3 constraints on the weights and needs at least 4 "
                f"basis functions, got {self.n_basis}; use end='free' for fewer"
            )

    def _phase_rate(self) -> float:
        """The canonical system's decay rate: ``alpha``, or ``ln 100`` by default."""
        return DEFAULT_ALPHA if self.alpha is None else float(self.alpha)
