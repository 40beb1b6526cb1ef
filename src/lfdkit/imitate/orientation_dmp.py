"""A DMP of the tool's orientation on the rotation manifold (unit quaternions).

Formulation (Koutras & Doulgeri 2020, "A correct formulation for the
orientation dynamic movement primitives for robot control in the Cartesian
space"): the state is the orientation error to the goal in the tangent
space, ``e(t) = log(q(t) ⊗ g⁻¹)`` (:func:`lfdkit.core.rotations.log`: ``θ/2 ·
axis``), and ``e`` obeys the position DMP's transformation system with goal
``0``::

    e'' = k (0 − e) − c e' + f(s),        q(t) = exp(e(t)) ⊗ g.

Its forcing, canonical system, basis and fit are those of
:class:`lfdkit.imitate.DMP` (one implementation; ``scaling="translate"``,
``end="rest"``). As ``e`` returns to exactly ``0`` at rest at the end of
every rollout (the position DMP's end condition), the orientation reaches
the new goal ``g`` *exactly*, whatever the start; and ``q = exp(e) ⊗ g`` is
unit by construction. Unlike Ude et al. 2014 (whose error ``2 log(g ⊗ q̄)``
is integrated through quaternion kinematics), the learned forcing acts in a
frame attached to the goal, so a new goal rotates the whole movement with
it, and the reproduction is exact in the same sense as for positions.

The training orientations must stay less than π from their goal (``|e|``
below π/2) so the logarithm is continuous; a movement that turns further
is refused with the sample at fault.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from lfdkit.core.rotations import check_quaternions, conjugate, continuous, exp, log, multiply
from lfdkit.imitate.dmp import DMP
from lfdkit.imitate.primitive import PRIMITIVE_DEFAULTS, Primitive
from lfdkit.model.timed_path import TimedPath

__all__ = ["QuaternionDMP", "orientation_error"]

#: Largest |e| (θ/2 to the goal, radians) accepted in training: just under π/2.
_MAX_HALF_ANGLE = 0.5 * np.pi - 1e-6


class QuaternionDMP(Primitive):
    """Orientation DMP: unit quaternions to a new start and goal orientation.

    Parameters
    ----------
    n_basis : int or "auto"
        Basis functions per rotation axis, as :class:`lfdkit.imitate.DMP`.
    k, c, alpha, tau, regularization, basis_tol
        As :class:`lfdkit.imitate.DMP`.

    Attributes
    ----------
    dmp_ : DMP
        The position DMP of the error ``e = log(q ⊗ g⁻¹)`` (shape (n, 3)).
    start_, goal_ : ndarray, shape (4,)
        The training start and goal orientations.
    times_ : ndarray, shape (n_points,)
        Training times in seconds.
    """

    def __init__(
        self,
        n_basis: int | str = PRIMITIVE_DEFAULTS["n_basis"],
        k: float = PRIMITIVE_DEFAULTS["k"],
        c: float = PRIMITIVE_DEFAULTS["c"],
        alpha: float | None = PRIMITIVE_DEFAULTS["alpha"],
        tau: float = PRIMITIVE_DEFAULTS["tau"],
        regularization: float = PRIMITIVE_DEFAULTS["regularization"],
        basis_tol: float = PRIMITIVE_DEFAULTS["basis_tol"],
    ) -> None:
        super().__init__(
            n_basis=n_basis,
            k=k,
            c=c,
            alpha=alpha,
            tau=tau,
            regularization=regularization,
            basis_tol=basis_tol,
        )

    def fit(self, quaternions: Any, times: Any = None) -> QuaternionDMP:
        """Learn from one orientation trajectory.

        Parameters
        ----------
        quaternions : array_like, shape (n_points, 4)
            Unit quaternions ``[x, y, z, w]`` (signs may flip between samples).
        times : array_like, shape (n_points,), optional
            Sample times in seconds, strictly increasing; default evenly over 1 s.

        Raises
        ------
        ValueError
            If a quaternion is not unit or NaN, the times are malformed, or the
            orientation turns π or more away from its goal.
        """
        q = continuous(check_quaternions(quaternions, "quaternions"))
        if len(q) < 2:
            raise ValueError("quaternions: need at least 2 samples")
        t = np.linspace(0.0, 1.0, len(q)) if times is None else times
        goal = q[-1]
        e = orientation_error(q, goal)
        far = np.linalg.norm(e, axis=1) >= _MAX_HALF_ANGLE
        if far.any():
            raise ValueError(
                f"quaternions: sample {int(np.argmax(far))} is π or more away from the goal "
                "orientation; an orientation DMP learns movements within π of their goal"
            )
        # The error returns to 0 at the goal: translated, never scaled, and at rest.
        dmp = DMP(scaling="translate", end="rest", **self.primitive_params())
        self.dmp_ = dmp.fit(e, t)
        # The error is bounded (|e| <= π/2), so the position DMP's overflow guard, scaled
        # by the training movement, must not refuse a new start when the demonstrated
        # orientation barely turned (a constant orientation has scale 0).
        self.dmp_.scale_ = max(self.dmp_.scale_, 0.5 * np.pi)
        self.start_ = q[0].copy()
        self.goal_ = goal.copy()
        self.times_ = self.dmp_.times_
        return self

    def to_state(self) -> dict[str, Any]:
        """The fitted state as plain data (:meth:`DMP.to_state` of :attr:`dmp_`, start, goal)."""
        if not hasattr(self, "dmp_"):
            raise ValueError("QuaternionDMP: call fit before to_state")
        return {
            "params": self.get_params(),
            "start": self.start_,
            "goal": self.goal_,
            "dmp": self.dmp_.to_state(),
        }

    @classmethod
    def from_state(cls, state: Mapping[str, Any], where: str = "orientation_dmp") -> QuaternionDMP:
        """The fitted orientation DMP of :meth:`to_state`, without refitting.

        Raises
        ------
        ValueError
            One line starting with ``where`` for a missing or malformed field
            (:meth:`DMP.from_state` for the inner DMP).
        """
        for key in ("params", "start", "goal", "dmp"):
            if key not in state:
                raise ValueError(f"{where}.{key}: missing field")
        try:
            made = cls(**dict(state["params"]))
        except TypeError as exc:
            raise ValueError(f"{where}.params: {exc}") from None
        for key in ("start", "goal"):
            check_quaternions(state[key], f"{where}.{key}")  # checked; kept as stored, to the bit
        made.dmp_ = DMP.from_state(state["dmp"], f"{where}.dmp")
        made.start_ = np.array(state["start"], dtype=np.float64)
        made.goal_ = np.array(state["goal"], dtype=np.float64)
        made.times_ = made.dmp_.times_
        return made

    def rollout(
        self,
        start: Any = None,
        goal: Any = None,
        tau: float | None = None,
        n_steps: int | None = None,
    ) -> TimedPath:
        """The orientation movement from ``start`` to ``goal``.

        Parameters
        ----------
        start, goal : array_like, shape (4,), optional
            Unit quaternions; default the training start and goal.
        tau : float, optional
            Temporal scaling (default ``self.tau``).
        n_steps : int, optional
            Samples, ends included (default as many as the training).

        Returns
        -------
        TimedPath
            ``times`` (n_steps,), seconds from 0 to ``tau * duration``;
            ``orientations`` (n_steps, 4), unit quaternions, signs continuous,
            the last ``goal`` (to rounding: the error ``e`` ends at exactly 0);
            ``positions``, ``velocities`` and ``accelerations`` (n_steps, 3)
            are the state the DMP integrates, the error ``e = log(q ⊗ g⁻¹)``
            (rad, ``θ/2 · axis``) and its derivatives.
        """
        if not hasattr(self, "dmp_"):
            raise ValueError("QuaternionDMP: call fit before rollout")
        q0 = self.start_ if start is None else check_quaternions(start, "start")[0]
        g = self.goal_ if goal is None else check_quaternions(goal, "goal")[0]
        e0 = log(multiply(q0, conjugate(g)))
        traj = self.dmp_.rollout(start=e0, goal=np.zeros(3), tau=tau, n_steps=n_steps)
        q = multiply(exp(traj.positions), g)
        q = continuous(q if q[0] @ q0 >= 0.0 else -q)
        return dataclasses.replace(traj, orientations=q)


def orientation_error(q: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """The error an orientation DMP learns: ``log(q ⊗ g⁻¹)``, half the rotation to the goal.

    Parameters
    ----------
    q : ndarray of shape (n_samples, 4)
        Unit quaternions (x, y, z, w), in the order of the movement.
    goal : ndarray of shape (4,)
        The goal orientation.

    Returns
    -------
    ndarray of shape (n_samples, 3)
        Rotation vectors of half the angle (radians), the sign of ``q ⊗ g⁻¹`` kept
        continuous from the goal.
    """
    rel = multiply(q, conjugate(goal))
    rel = continuous(rel[::-1])[::-1]  # the goal's row is the identity, w = 1
    rel = rel * np.sign(rel[-1:, 3:4])
    v = rel[..., :3]
    s = np.linalg.norm(v, axis=-1)
    half = np.arctan2(s, rel[..., 3])  # in [0, π]: continuous along the movement
    scale = np.where(s > 1e-12, half / np.where(s > 1e-12, s, 1.0), 1.0)
    return v * scale[..., None]
