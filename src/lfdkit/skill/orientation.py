"""The tool's orientation in a skill: orientation data checked, its DMP, orientations along a plan.

The mean orientation along the path is learned by an orientation DMP
(:class:`lfdkit.imitate.QuaternionDMP`) that must reproduce it within
0.5 degrees; plans carry the orientation from a start to a goal orientation,
through oriented via-points where given.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

from lfdkit.core.geometry import (
    arc_length,
    path_length,
)
from lfdkit.core.rotations import check_quaternions, continuous, exp, multiply, slerp
from lfdkit.imitate import QuaternionDMP
from lfdkit.imitate.orientation_dmp import orientation_error
from lfdkit.imitate.via_points import (
    check_via,
    check_via_orientations,
    orientations_through_via,
)

#: How closely (a rotation angle, degrees) the orientation DMP must reproduce the mean orientation.
_ORIENTATION_TOLERANCE_DEG = 0.5


class SkillOrientation:
    """The tool's orientation in a skill: its DMP and the orientations along a plan."""

    def _fit_orientation_dmp(self, orientations: np.ndarray) -> QuaternionDMP:
        """The orientation DMP on the mean orientations, on the path DMP's clock.

        The mean orientation is a function of the path's arc-length fraction
        ``ℓ`` (one per path point); the DMP learns it composed with the
        skill's speed law, ``q(t) = Q(ℓ(t / T))`` (as the position DMP
        composes the path with it), sampled densely in time: the movement is
        at rest at both ends without the roughness of a few demonstrations'
        mean being magnified where the path starts and ends slowly. A plan's
        point reached at ``t`` then gets the mean orientation of the path
        point at the same fraction of the way. With ``n_basis="auto"`` the
        basis count is the fewest that reproduce it within 1 % of the turn,
        or :data:`_ORIENTATION_TOLERANCE_DEG` (a rotation angle) if looser.
        """
        from scipy.interpolate import make_interp_spline  # here: lfdkit.skill loads fast

        n_basis = self.n_basis if isinstance(self.n_basis, str) else int(self.n_basis)
        goal = orientations[-1]
        # The error the DMP learns: half the rotation angle to the goal (radians).
        half = orientation_error(orientations, goal)
        extent = float(np.max(np.ptp(half, axis=0)))
        tolerance = 0.5 * np.radians(_ORIENTATION_TOLERANCE_DEG)
        basis_tol = min(1.0, max(0.01, tolerance / extent)) if extent > 0.0 else 1.0
        fraction = arc_length(self.path_) / path_length(self.path_)
        phase = np.linspace(0.0, 1.0, max(1000, 10 * len(fraction)))
        spline = make_interp_spline(fraction, half, k=min(3, len(fraction) - 1), axis=0)
        dense = multiply(exp(spline(self.timing_.progress(phase))), goal)
        dense[-1] = goal  # the spline passes through it: exactly, not to rounding
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", RuntimeWarning)
            try:
                dmp = QuaternionDMP(n_basis=n_basis, basis_tol=basis_tol).fit(
                    dense, phase * self.timing_.duration
                )
            except ValueError as exc:
                message = str(exc).removeprefix("quaternions: ")
                raise ValueError(f"orientations: the mean along the path: {message}") from None
        if caught:  # said for the orientation, in degrees, not the DMP's words for a path
            departure = 2.0 * dmp.dmp_.reproduction_error_ * extent
            warnings.warn(
                f"orientation DMP: reproduces the demonstrations' mean orientation within "
                f"{np.degrees(departure):.2g} deg at best ({dmp.dmp_.n_basis_} basis functions); "
                "the mean is rough where the demonstrations disagree or are noisy",
                RuntimeWarning,
                stacklevel=4,
            )
        return dmp

    def _orientation_ends(self, start: Any, goal: Any) -> tuple[np.ndarray, np.ndarray] | None:
        """The start and goal orientations checked (default the learned ones); None without."""
        self._check_fitted()
        if getattr(self, "orientation_dmp_", None) is None:
            for value, name in ((start, "start_orientation"), (goal, "goal_orientation")):
                if value is not None:
                    raise ValueError(
                        f"{name}: this skill has no orientation; learn it from demonstrations "
                        "with orientations (qx, qy, qz, qw)"
                    )
            return None
        first = self.orientations_[0] if start is None else None
        last = self.orientations_[-1] if goal is None else None
        if first is None:
            first = check_quaternions(start, "start_orientation", n=1)[0]
        if last is None:
            last = check_quaternions(goal, "goal_orientation", n=1)[0]
        return first, last

    def orientations_at(
        self,
        phases: Any,
        start_orientation: Any = None,
        goal_orientation: Any = None,
        via: Sequence[tuple[float, Any, Any]] | None = None,
    ) -> np.ndarray:
        """The orientation DMP's movement at normalised times ``phases`` (0 start, 1 goal).

        Parameters
        ----------
        phases : array_like, shape (n,)
            Fractions of the movement's duration, in [0, 1] (clipped).
        start_orientation, goal_orientation : array_like, shape (4,), optional
            Unit quaternions ``[x, y, z, w]``; default the learned first and last.
        via : sequence of (float, array_like (q,), array_like (4,)), optional
            :meth:`plan`'s via-points; those with an orientation (third item)
            bend the movement through it at their phase
            (:func:`lfdkit.imitate.via_points.orientations_through_via`);
            their points are not used here.

        Returns
        -------
        ndarray, shape (n, 4)
            Unit quaternions, signs continuous from the start's. At phase 0
            the start orientation, at phase 1 exactly the goal orientation;
            between, the rollout (exact at its samples, 8 per plan point and
            at least 1001) interpolated by slerp, bent through each
            via-point's orientation (exact at its phase).

        Raises
        ------
        ValueError
            For a skill without orientation, or an orientation that is not a
            unit quaternion.
        """
        ends = self._orientation_ends(start_orientation, goal_orientation)
        if ends is None:
            raise ValueError("skill: has no orientation (orientation_dmp_ is None)")
        u = np.clip(np.asarray(phases, dtype=np.float64).ravel(), 0.0, 1.0)
        if not np.all(np.isfinite(u)):
            raise ValueError("phases: contains NaN")
        return self._orientations_at(u, *ends, via=self._via_orientations(via, True))

    def _via_orientations(
        self, via: Sequence[tuple[Any, ...]] | None, oriented: bool
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """The via-points' orientations (phases, quaternions), checked; None if none given."""
        if via is None:
            return None
        check_via(via, self.n_dims_)  # the entries' shape, before their orientations
        phases, turns = check_via_orientations(via)
        if len(phases) == 0:
            return None
        if not oriented:
            first = [len(entry) > 2 and entry[2] is not None for entry in via].index(True)
            raise ValueError(
                f"via[{first}]: orientation: this skill has no orientation; drop it, or learn "
                "from demonstrations with orientations (qx, qy, qz, qw)"
            )
        return phases, turns

    def _orientations_at(
        self,
        phases: np.ndarray,
        start: np.ndarray,
        goal: np.ndarray,
        via: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> np.ndarray:
        """:meth:`orientations_at` from checked phases, start, goal and via-orientations."""
        n_steps = max(1001, 8 * int(self.n_points))
        run = self.orientation_dmp_.rollout(start=start, goal=goal, n_steps=n_steps)
        rollout = run.orientations

        def sampled(u: np.ndarray) -> np.ndarray:
            position = np.clip(u, 0.0, 1.0) * (n_steps - 1)
            k = np.minimum(np.floor(position).astype(int), n_steps - 2)
            return slerp(rollout[k], rollout[k + 1], position - k)

        out = sampled(phases)
        # The DMP's error ends at exactly 0: the last sample is the goal itself.
        end = phases >= 1.0
        out[end] = goal if goal @ rollout[-1] >= 0.0 else -goal
        if via is not None:
            at, turns = via
            out = orientations_through_via(phases, out, at, turns, sampled(at))
        out = continuous(out)
        return out if out[0] @ start >= 0.0 else -out


def check_orientations_list(
    orientations: Sequence[Any] | None, demos: list[np.ndarray]
) -> list[np.ndarray] | None:
    """One (n_j, 4) unit-quaternion array per demonstration, or None for none at all."""
    if orientations is None:
        return None
    if isinstance(orientations, np.ndarray) and orientations.ndim == 2:
        raise TypeError(
            "orientations: expected a sequence of (n_j, 4) arrays, one per demonstration"
        )
    orientations = list(orientations)
    if len(orientations) != len(demos):
        raise ValueError(
            f"orientations: {len(orientations)} arrays for {len(demos)} demonstrations; "
            "give one (n_j, 4) array per demonstration"
        )
    given = [o is not None for o in orientations]
    if not any(given):
        return None
    if not all(given):
        raise ValueError(
            f"orientations: orientations[{given.index(False)}] is None; give orientations for "
            "every demonstration or none"
        )
    return [
        check_quaternions(o, f"orientations[{j}]", n=len(demo))
        for j, (o, demo) in enumerate(zip(orientations, demos, strict=True))
    ]
