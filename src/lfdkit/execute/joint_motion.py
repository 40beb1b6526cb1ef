"""What every timed joint motion shares: its duration, its joint count, fixed-rate samples.

Three classes time a joint path: :class:`lfdkit.execute.timing.Timing` (as fast
as the limits allow), :class:`lfdkit.execute.trajectory.JointTrajectory` (the
person's timing, slowed where the arm needs it) and
:class:`lfdkit.execute.jerk_limited.JerkLimitedTrajectory` (ruckig, jerk
limited). Each samples itself its own way (:meth:`JointMotion.sample`); the
rest is one definition here, so the three answer ``duration``, ``n_joints`` and
``resample`` alike (the fixed-rate grid is
:func:`lfdkit.model.timed_path.fixed_rate_times`, the one grid of plans and
joint trajectories). The two that retime a plan also answer
``planned_duration`` (:class:`RetimedMotion`).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Any

import numpy as np

from lfdkit.model.timed_path import TimedPath, fixed_rate_times

__all__ = ["JointMotion", "RetimedMotion"]


class JointMotion(ABC):
    """A timed joint motion through waypoints: a base for frozen dataclasses.

    Subclasses hold ``times`` (s, from 0, strictly increasing: when each
    waypoint is passed) and ``waypoints`` (rad, shape (n, n_joints)) and
    define :meth:`sample`.
    """

    times: np.ndarray
    waypoints: np.ndarray

    @property
    def duration(self) -> float:
        """Seconds from start to stop."""
        return float(self.times[-1])

    @property
    def n_joints(self) -> int:
        """Number of joints."""
        return int(self.waypoints.shape[1])

    @abstractmethod
    def sample(self, t: Any) -> TimedPath:
        """Joint positions, velocities and accelerations at times ``t`` (s), at rest outside."""

    def resample(self, rate_hz: float) -> TimedPath:
        """The motion at a fixed rate, e.g. 125 Hz (500 Hz on e-Series) for ``servoj``.

        Parameters
        ----------
        rate_hz : float
            Samples per second.

        Returns
        -------
        TimedPath
            :meth:`sample` at ``times`` ``k / rate_hz`` for ``k = 0 .. m-1``
            (:func:`~lfdkit.model.timed_path.fixed_rate_times`); the last is
            the first sample at or after :attr:`duration`, where the arm is at
            rest at the last waypoint.
        """
        return self.sample(fixed_rate_times(self.duration, rate_hz))


class RetimedMotion(JointMotion):
    """A joint motion retimed from a plan: also holds ``planned_times`` (s), the plan's own."""

    planned_times: np.ndarray

    @property
    def planned_duration(self) -> float:
        """The plan's duration (s)."""
        return float(self.planned_times[-1])
