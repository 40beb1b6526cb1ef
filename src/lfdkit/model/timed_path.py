"""A timed path: points with their times and velocities, what a robot runs.

:class:`TimedPlan` is what :meth:`lfdkit.skill.Skill.plan` returns: the planned
points, the times at which the tool passes them (seconds from 0) and its
velocities there, with the planner's result (``details``) and, for a skill
that learned one, the tool's orientation at each point. It is a record of the
data model, so every floor above may take one (execution on a robot, plots,
files) without importing the skill. It stands for its points wherever NumPy
takes an array (``np.asarray(plan)`` is ``plan.points``), as the bare
``(n, q)`` array ``Skill.plan`` returned before timing was added did.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.lib.mixins import NDArrayOperatorsMixin

from lfdkit.core.rotations import angle_between, slerp
from lfdkit.core.validation import MAX_POINTS, check_positive

__all__ = ["TimedPlan", "fixed_rate_times"]


def fixed_rate_times(duration: float, rate_hz: Any) -> np.ndarray:
    """The fixed-rate time grid a controller streams: ``k / rate_hz`` seconds.

    The one home of the grid used by :meth:`TimedPlan.at_rate` and the joint
    trajectories of :mod:`lfdkit.execute` (``resample``): samples from 0 up to
    the first at or after ``duration`` (where the motion rests at its end).
    The count is decided before any array is made, so an absurd rate or
    duration is a one-line refusal, not a memory error.

    Parameters
    ----------
    duration : float
        Seconds of motion, >= 0.
    rate_hz : float
        Samples per second, e.g. 125 (a UR CB controller) or 500.

    Returns
    -------
    ndarray, shape (m,)
        ``k / rate_hz`` for ``k = 0 .. m-1``, ``m = ceil(duration * rate_hz) + 1``
        (1e-9 of a sample of slack, so round-off does not add one past the end).

    Raises
    ------
    ValueError
        If ``rate_hz`` is not positive, or gives more than
        :data:`~lfdkit.core.validation.MAX_POINTS` samples.
    """
    rate = check_positive(rate_hz, "rate_hz")
    wanted = duration * rate
    if not wanted < MAX_POINTS:  # also inf and nan
        raise ValueError(
            f"rate_hz: {rate:.6g} Hz over {duration:.6g} s gives {wanted:.3g} samples; "
            f"at most {MAX_POINTS:,}: lower the rate or split the motion"
        )
    return np.arange(int(np.ceil(wanted - 1e-9)) + 1) / rate


@dataclass(frozen=True, eq=False, repr=False)
class TimedPlan(NDArrayOperatorsMixin):
    """A planned path with its timing: what :meth:`~lfdkit.skill.Skill.plan` returns.

    The path is timed by its own arc length with the skill's speed profile
    (:attr:`lfdkit.skill.Skill.timing_`, :meth:`lfdkit.imitate.SpeedProfile.time_path`):
    a plan that swerves around an obstacle is longer than the nominal, and
    runs a little faster all along rather than fast where it swerves.

    Attributes
    ----------
    times : ndarray, shape (n_points,)
        Seconds, from 0 to :attr:`duration`.
    points : ndarray, shape (n_points, q)
        The path, first point the start (units of the skill).
    velocities : ndarray, shape (n_points, q)
        Units per second; zero at both ends (rest to rest) unless the skill's
        timing is ``"uniform"``.
    details : lfdkit.emulate.Plan
        The planner's result (:meth:`lfdkit.skill.Skill.plan_details`): ``clearance``,
        ``goal_error``, ``cost``, ``offsets``, ...
    orientations : ndarray, shape (n_points, 4), or None
        The tool's orientation at each point, unit quaternions ``[x, y, z,
        w]`` with continuous signs, when the skill learned one
        (:attr:`lfdkit.skill.Skill.orientation_dmp_`); None otherwise. The first is the
        start orientation, the last the goal orientation.

    Notes
    -----
    Before timing was added, :meth:`lfdkit.skill.Skill.plan` returned the points as an
    ndarray. A ``TimedPlan`` still stands for its points wherever NumPy
    takes an array: ``np.asarray(plan)`` is ``plan.points`` (``__array__``),
    arithmetic and comparisons act on the points and return arrays
    (``plan - start``, ``plan == other``), and ``len(plan)``,
    ``plan[i]``, iteration, ``plan.shape`` and ``plan.ndim`` are the
    points'. Its fields cannot be reassigned and in-place arithmetic
    (``plan += 1``) raises ``TypeError``: ``np.array(plan)`` is a copy to
    change, ``plan.points`` has the other array methods.
    """

    times: np.ndarray
    points: np.ndarray
    velocities: np.ndarray
    details: Any  # lfdkit.emulate.Plan (a floor above: typed by its docstring)
    orientations: np.ndarray | None = None

    @property
    def positions(self) -> np.ndarray:
        """The points, (n_points, q): the name :class:`lfdkit.imitate.Trajectory` uses."""
        return self.points

    @property
    def duration(self) -> float:
        """Seconds from the first point to the last."""
        return float(self.times[-1])

    @property
    def speeds(self) -> np.ndarray:
        """Speed along the path at each point, units per second, (n_points,)."""
        return np.linalg.norm(self.velocities, axis=1)

    def at_rate(self, rate_hz: float) -> TimedPlan:
        """The plan sampled at a fixed rate, as a robot controller streams it.

        Samples at ``k / rate_hz`` seconds, up to the first at or after the
        end (past the end the tool rests at the last point). Positions and
        velocities come from the cubic Hermite curve through the plan's
        points and velocities at their times (C¹: the acceleration may jump
        at a planned point), so the velocities are the exact derivative of
        the positions and the stream passes every planned point at its time.
        Orientations are slerped between the
        neighbouring points. ``details`` is kept (the planner's result for
        the same path).

        Parameters
        ----------
        rate_hz : float
            Samples per second, e.g. 125 (a UR CB controller) or 500.

        Returns
        -------
        TimedPlan
            With ``times`` ``k / rate_hz`` (k = 0, 1, ...), shape (m,).

        Raises
        ------
        ValueError
            If ``rate_hz`` is not positive, or gives more than
            :data:`~lfdkit.core.validation.MAX_POINTS` samples.
        """
        times = fixed_rate_times(self.duration, rate_hz)
        t = np.clip(times, self.times[0], self.times[-1])
        # The interval holding each sample (the last one for the end itself).
        i = np.clip(np.searchsorted(self.times, t, side="right") - 1, 0, len(self.times) - 2)
        t0, t1 = self.times[i], self.times[i + 1]
        h = np.maximum(t1 - t0, 1e-300)
        s = ((t - t0) / h)[:, None]
        p0, p1 = self.points[i], self.points[i + 1]
        m0, m1 = self.velocities[i] * h[:, None], self.velocities[i + 1] * h[:, None]
        s2, s3 = s * s, s * s * s
        points = (
            (2 * s3 - 3 * s2 + 1) * p0
            + (s3 - 2 * s2 + s) * m0
            + (-2 * s3 + 3 * s2) * p1
            + (s3 - s2) * m1
        )
        velocities = (
            (6 * s2 - 6 * s) * p0
            + (3 * s2 - 4 * s + 1) * m0
            + (-6 * s2 + 6 * s) * p1
            + (3 * s2 - 2 * s) * m1
        ) / h[:, None]
        velocities[times > self.times[-1]] = 0.0  # at rest after the end
        orientations = None
        if self.orientations is not None:
            orientations = slerp(self.orientations[i], self.orientations[i + 1], s[:, 0])
        return TimedPlan(times, points, velocities, self.details, orientations)

    # ----------------------------------------------- the points as an array
    def __array__(self, dtype: Any = None, copy: bool | None = None) -> np.ndarray:
        points = self.points if dtype is None else self.points.astype(dtype, copy=False)
        return points.copy() if copy else points

    def __array_ufunc__(self, ufunc: Any, method: str, *inputs: Any, **kwargs: Any) -> Any:
        if any(isinstance(o, TimedPlan) for o in kwargs.get("out", ())):
            return NotImplemented  # immutable: no in-place arithmetic
        args = [x.points if isinstance(x, TimedPlan) else x for x in inputs]
        return getattr(ufunc, method)(*args, **kwargs)

    def __len__(self) -> int:
        return len(self.points)

    def __getitem__(self, key: Any) -> Any:
        return self.points[key]

    def __iter__(self) -> Iterator[np.ndarray]:
        return iter(self.points)

    @property
    def shape(self) -> tuple[int, ...]:
        """The points' shape, (n_points, q)."""
        return self.points.shape

    @property
    def ndim(self) -> int:
        """2, as the points'."""
        return self.points.ndim

    def __repr__(self) -> str:
        n, q = self.points.shape
        turned = ""
        if self.orientations is not None:
            turn = float(angle_between(self.orientations[0], self.orientations[-1]))
            turned = f", turning {np.degrees(turn):.4g} deg"
        return (
            f"TimedPlan({n} points in {q}-D over {self.duration:.4g} s, "
            f"peak speed {float(np.max(self.speeds)):.4g} units/s{turned})"
        )
