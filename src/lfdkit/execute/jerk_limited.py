"""Jerk-limited joint trajectories with ruckig: through timed states, within v, a and jerk limits.

The two other timings (:func:`lfdkit.execute.timing.time_parameterize`,
lfdkit's TOPP-RA or toppra's; :func:`lfdkit.execute.trajectory.keep_timing`,
the person's timing) bound velocity and acceleration only: their
accelerations jump (a bang-bang profile, or a cubic spline's piecewise-linear
acceleration with kinks), so the jerk is unbounded at the switches. ruckig
(``pip install ruckig``, the field's maintained online trajectory generator)
bounds the jerk too.

ruckig's free version plans from one state to one target state; intermediate
waypoints are its commercial version's. So :func:`through_states` chains
state-to-state problems: waypoint ``k`` (position, velocity and acceleration
of a reference trajectory at time ``t_k``) is the target of segment ``k``,
all joints synchronised in time, within velocity, acceleration and jerk
limits, and lasting at least the reference's ``t_{k+1} - t_k``
(``minimum_duration``): the reference's timing is kept where the jerk limit
allows it and stretched where it does not. Every waypoint is passed exactly,
with the reference's velocity and acceleration; between waypoints each joint
follows its own jerk profile (for 100 Hz waypoints within micro-radians of
the reference, ``benchmarks/timing_backends.py``).

* :func:`time_parameterize_ruckig` is the ``backend="ruckig"`` of
  :func:`~lfdkit.execute.timing.time_parameterize`: the time-optimal
  reference (lfdkit's), then jerk-limited through its waypoints.
* :func:`through_states` on the samples of a
  :class:`~lfdkit.execute.trajectory.JointTrajectory` jerk-limits the
  person's timing.

Jerk limits. Arms' data sheets rarely give one and URDFs never do: the
default is :data:`JERK_PER_ACCELERATION` (50 /s) times each acceleration
limit, full acceleration reached in 20 ms (a Franka Panda's published
limits: 15 rad/s² and 7500 rad/s³, 500 /s). A speed fraction ``f`` scales it
by ``f³``, as it scales velocities by ``f`` and accelerations by ``f²``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lfdkit.core.validation import MAX_POINTS, check_path, check_positive
from lfdkit.execute.arm import UR5, Arm

__all__ = [
    "JERK_PER_ACCELERATION",
    "JerkLimitedTrajectory",
    "through_states",
    "time_parameterize_ruckig",
]

#: Default jerk limit per unit of acceleration limit (1/s): full acceleration in 20 ms.
JERK_PER_ACCELERATION = 50.0
_FINE = 1e-9  # rad: ruckig's positions at a segment's end against its target


def _ruckig() -> Any:
    try:
        import ruckig
    except ImportError:
        raise ImportError(
            "backend: 'ruckig' needs ruckig: python -m pip install ruckig "
            '(or pip install "lfdkit[robot]")'
        ) from None
    return ruckig


@dataclass(frozen=True, eq=False)
class JerkLimitedTrajectory:
    """A chain of ruckig segments through waypoints: the interface of a timing.

    Attributes
    ----------
    times : ndarray, shape (n,)
        When each waypoint is passed (s), from 0, strictly increasing.
    planned_times : ndarray, shape (n,)
        The reference's times of the waypoints (s).
    waypoints : ndarray, shape (n, n_joints)
    waypoint_index : ndarray of int, shape (n,)
        Row of the input each waypoint came from.
    max_velocity, max_acceleration, max_jerk : ndarray, shape (n_joints,)
        The limits kept (rad/s, rad/s², rad/s³; speed fraction included).
    """

    times: np.ndarray
    planned_times: np.ndarray
    waypoints: np.ndarray
    waypoint_index: np.ndarray
    max_velocity: np.ndarray
    max_acceleration: np.ndarray
    max_jerk: np.ndarray
    _segments: tuple[Any, ...] = field(repr=False)  # ruckig.Trajectory per segment

    @property
    def duration(self) -> float:
        """Seconds from start to stop."""
        return float(self.times[-1])

    @property
    def planned_duration(self) -> float:
        """The reference's duration (s)."""
        return float(self.planned_times[-1])

    @property
    def n_joints(self) -> int:
        """Number of joints."""
        return int(self.waypoints.shape[1])

    def sample(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Positions, velocities and accelerations at times ``t``; at rest outside the motion.

        Parameters
        ----------
        t : float or array_like, shape (m,)

        Returns
        -------
        q, qd, qdd : ndarray, shape (n_joints,) or (m, n_joints)
        """
        tt = np.asarray(t, dtype=np.float64)
        if tt.ndim > 1 or np.isnan(tt).any():
            raise ValueError(f"t: expected a number or a 1-D array of times, got shape {tt.shape}")
        single = tt.ndim == 0
        tt = np.atleast_1d(tt)
        out = np.empty((3, len(tt), self.n_joints))
        k = np.clip(np.searchsorted(self.times, tt, side="right") - 1, 0, len(self._segments) - 1)
        for i, (when, seg) in enumerate(zip(tt, k, strict=True)):
            local = min(max(when - self.times[seg], 0.0), self._segments[seg].duration)
            out[:, i] = self._segments[seg].at_time(local)
        outside = (tt < 0.0) | (tt > self.duration)
        out[0, tt < 0.0] = self.waypoints[0]
        out[0, tt > self.duration] = self.waypoints[-1]
        out[1:, outside] = 0.0
        if single:
            return out[0, 0], out[1, 0], out[2, 0]
        return out[0], out[1], out[2]

    def resample(self, rate_hz: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Fixed-rate samples ``k / rate_hz`` up to the first at or after the end.

        Returns
        -------
        times : ndarray, shape (m,)
        q, qd, qdd : ndarray, shape (m, n_joints)
        """
        rate = check_positive(rate_hz, "rate_hz")
        wanted = self.duration * rate
        if not wanted < MAX_POINTS:
            raise ValueError(
                f"rate_hz: {rate_hz!r} Hz over {self.duration:.6g} s gives {wanted:.3g} samples; "
                f"at most {MAX_POINTS:,}: lower the rate"
            )
        times = np.arange(int(np.ceil(wanted - 1e-9)) + 1) / rate
        return (times, *self.sample(times))


def _limit(value: Any, name: str, n_joints: int) -> np.ndarray:
    arr = np.broadcast_to(np.asarray(value, dtype=np.float64), (n_joints,)).copy()
    if not (np.isfinite(arr).all() and (arr > 0).all()):
        raise ValueError(f"{name}: expected {n_joints} finite limits > 0, got {value!r}")
    return arr


def through_states(
    times: Any,
    q: Any,
    qd: Any,
    qdd: Any,
    *,
    max_velocity: Any,
    max_acceleration: Any,
    max_jerk: Any = None,
    keep_times: bool = True,
    waypoint_index: Any = None,
) -> JerkLimitedTrajectory:
    """A jerk-limited trajectory through timed states, one ruckig problem per segment.

    Parameters
    ----------
    times : array_like, shape (n,)
        The reference's times of the states (s), strictly increasing.
    q, qd, qdd : array_like, shape (n, n_joints)
        Positions (rad), velocities (rad/s) and accelerations (rad/s²) to
        pass at each state; the first is where the trajectory starts. Give
        zero velocity and acceleration at both ends for a trajectory at
        rest before and after (:meth:`JerkLimitedTrajectory.sample`'s outside).
    max_velocity, max_acceleration : float or array_like, shape (n_joints,)
    max_jerk : float or array_like, shape (n_joints,), optional
        Default :data:`JERK_PER_ACCELERATION` times ``max_acceleration``.
    keep_times : bool
        Each segment lasts at least the reference's (its timing kept where
        the limits allow); False: each is ruckig's time-optimal one.
    waypoint_index : array_like of int, shape (n,), optional
        Carried to :attr:`JerkLimitedTrajectory.waypoint_index` (default ``0 … n-1``).

    Returns
    -------
    JerkLimitedTrajectory

    Raises
    ------
    ValueError
        Shapes that disagree, non-finite states, times that do not increase,
        a state beyond the velocity or acceleration limits (ruckig cannot
        reach it; the message names the state and joint).
    ImportError
        Without ruckig.
    """
    ruckig = _ruckig()
    t = np.asarray(times, dtype=np.float64)
    pos = check_path(q, "q", min_dims=1)
    n, dof = pos.shape
    vel = np.asarray(qd, dtype=np.float64)
    acc = np.asarray(qdd, dtype=np.float64)
    if t.shape != (n,) or vel.shape != pos.shape or acc.shape != pos.shape:
        raise ValueError(
            f"times, q, qd, qdd: expected shapes ({n},) and {pos.shape}, got {t.shape}, "
            f"{vel.shape}, {acc.shape}"
        )
    if not (np.isfinite(t).all() and np.isfinite(vel).all() and np.isfinite(acc).all()):
        raise ValueError("times, qd, qdd: must be finite")
    if n < 2 or (np.diff(t) <= 0.0).any():
        raise ValueError("times: expected at least 2, strictly increasing")
    vmax = _limit(max_velocity, "max_velocity", dof)
    amax = _limit(max_acceleration, "max_acceleration", dof)
    jmax = _limit(JERK_PER_ACCELERATION * amax if max_jerk is None else max_jerk, "max_jerk", dof)
    over = np.maximum(np.abs(vel) / vmax, np.abs(acc) / amax)
    if (over > 1.0 + 1e-9).any():
        k, j = np.unravel_index(int(np.argmax(over)), over.shape)
        raise ValueError(
            f"qd, qdd: state {k} (t = {t[k]:.3f} s) is at {over[k, j]:.3g} x joint {j + 1}'s "
            "limits; time the reference within the limits first"
        )
    generator = ruckig.Ruckig(dof)
    problem = ruckig.InputParameter(dof)
    problem.max_velocity, problem.max_acceleration, problem.max_jerk = vmax, amax, jmax
    segments = []
    passed = np.empty(n)
    passed[0] = 0.0
    for k in range(n - 1):
        problem.current_position, problem.target_position = pos[k], pos[k + 1]
        problem.current_velocity, problem.target_velocity = vel[k], vel[k + 1]
        problem.current_acceleration, problem.target_acceleration = acc[k], acc[k + 1]
        if keep_times:
            problem.minimum_duration = float(t[k + 1] - t[k])
        segment = ruckig.Trajectory(dof)
        result = generator.calculate(problem, segment)
        if result not in (ruckig.Result.Working, ruckig.Result.Finished):
            raise ValueError(
                f"q: ruckig found no trajectory from state {k} to {k + 1} "
                f"(t = {t[k]:.3f}-{t[k + 1]:.3f} s): {result}; lower the jerk limit's demand "
                "(a larger max_jerk) or space the states further"
            )
        segments.append(segment)
        passed[k + 1] = passed[k] + segment.duration
    index = np.arange(n) if waypoint_index is None else np.asarray(waypoint_index, dtype=int)
    return JerkLimitedTrajectory(
        times=passed,
        planned_times=t - t[0],
        waypoints=pos,
        waypoint_index=index,
        max_velocity=vmax,
        max_acceleration=amax,
        max_jerk=jmax,
        _segments=tuple(segments),
    )


def time_parameterize_ruckig(
    q: Any,
    *,
    arm: Arm = UR5,
    max_velocity: Any = None,
    max_acceleration: Any = None,
    max_jerk: Any = None,
    speed_fraction: float = 1.0,
) -> JerkLimitedTrajectory:
    """Time a path through waypoints within joint velocity, acceleration and jerk limits.

    lfdkit's time-optimal timing (:func:`lfdkit.execute.timing.time_parameterize`,
    same arguments) gives each waypoint's time, velocity and acceleration;
    :func:`through_states` then jerk-limits it with ruckig, keeping each
    segment's time where the jerk limit allows (``time_parameterize(...,
    backend="ruckig")`` calls this).

    Parameters
    ----------
    q : array_like, shape (n, n_joints)
        Waypoints (rad).
    arm, max_velocity, max_acceleration, speed_fraction
        As in :func:`~lfdkit.execute.timing.time_parameterize`.
    max_jerk : float or array_like, shape (n_joints,), optional
        Jerk limits at full speed (rad/s³; times ``speed_fraction³``);
        default :data:`JERK_PER_ACCELERATION` times the acceleration limits.

    Returns
    -------
    JerkLimitedTrajectory
    """
    from lfdkit.execute.timing import time_parameterize

    _ruckig()  # refused before any work
    reference = time_parameterize(
        q,
        arm=arm,
        max_velocity=max_velocity,
        max_acceleration=max_acceleration,
        speed_fraction=speed_fraction,
    )
    f = float(speed_fraction)
    # The reference's acceleration limits carry f²: the jerk's f³ is one f more.
    jerk = JERK_PER_ACCELERATION * reference.max_acceleration * f
    if max_jerk is not None:
        jerk = _limit(max_jerk, "max_jerk", reference.n_joints) * f**3
    q_at, qd_at, qdd_at = reference.sample(reference.times)
    # At rest at both ends: the bang-bang reference still brakes at full acceleration as it stops.
    qd_at[[0, -1]], qdd_at[[0, -1]] = 0.0, 0.0
    return through_states(
        reference.times,
        q_at,
        qd_at,
        qdd_at,
        max_velocity=reference.max_velocity,
        max_acceleration=reference.max_acceleration,
        max_jerk=jerk,
        waypoint_index=reference.waypoint_index,
    )
