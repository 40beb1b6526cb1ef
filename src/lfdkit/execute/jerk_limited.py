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
state-to-state problems: state ``k`` (position, velocity and acceleration
of a reference trajectory at time ``t_k``) is the target of segment ``k``,
all joints synchronised in time, within velocity, acceleration and jerk
limits, lasting the reference's ``t_{k+1} - t_k`` (``minimum_duration``).
Every state is passed exactly. Where a segment cannot keep its time, the
whole reference is slowed uniformly (velocities ``/k``, accelerations
``/k²``, times ``·k``) by the least ``k`` that lets every segment keep it
(bisection): a segment stretched alone would arrive late with the
reference's speed and wander off the path (0.33 rad on the reach below).

* :func:`time_parameterize_ruckig` is the ``backend="ruckig"`` of
  :func:`~lfdkit.execute.timing.time_parameterize`: lfdkit's time-optimal
  (bang-bang) timing, then jerk-limited through those of its waypoints that
  the jerk limit can join: a bang-bang reference switches from +a to -a
  between two waypoints 1 ms apart, so passing every waypoint with its
  acceleration would slow the whole motion about 4 times; each next state is
  the first whose acceleration change half the jerk limit allows.
* :func:`through_states` on the samples of a
  :class:`~lfdkit.execute.trajectory.JointTrajectory` jerk-limits the
  person's timing (its cubic spline's jerk is finite already: usually the
  timing is kept exactly).

Measured (``python benchmarks/timing_backends.py``; a loaded 2-core machine,
so wall times are rough). T1, time-optimal, the same limits: lfdkit's and
toppra's durations agree (to 1e-4 or better), and their accelerations jump
(bang-bang) at every switch; the jerk-limited timing (50 /s) lasts 1.07-1.15
times theirs on random 200-waypoint UR5 walks and 1.30 times on a 6 s
reach's 601 joint waypoints (UR5, UR5e, Panda, at speed fractions 1 and
0.2), stays within 0.6-2.6 mrad of their path on the reach and 23-35 mrad on
the walks (where it cuts their sharp corners), and takes 1.5-7 times
lfdkit's time (lfdkit's timing included). T2, the person's timing: the
cubic spline of :func:`~lfdkit.execute.trajectory.keep_timing` already
stays within the jerk limit (0.005-0.26 of it on the reach); ruckig keeps
its timing exactly (x1.0000, within 6e-7 rad) but fills each 10 ms segment
with a jerk-limit bang-bang profile (jerk at the limit, acceleration peaks
up to 1.4 times the spline's). So lfdkit's stays the default everywhere;
ruckig is there for a controller that needs a bounded jerk on a
time-optimal motion.

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

from lfdkit.core.validation import check_path
from lfdkit.execute.arm import UR5, Arm, per_joint
from lfdkit.execute.joint_motion import RetimedMotion
from lfdkit.model.timed_path import TimedPath

__all__ = [
    "JERK_PER_ACCELERATION",
    "JerkLimitedTrajectory",
    "through_states",
    "time_parameterize_ruckig",
]

#: Default jerk limit per unit of acceleration limit (1/s): full acceleration in 20 ms.
JERK_PER_ACCELERATION = 50.0
_STRETCH_TOL = 1e-6  # relative: a segment longer than its time by more is stretched
_MAX_SLOWDOWN = 1e3  # beyond this the jerk limit is taken for a mistake
_JERK_SHARE = 0.5  # of the jerk limit a step between two passed states may ask for


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
class JerkLimitedTrajectory(RetimedMotion):
    """A chain of ruckig segments through waypoints: the interface of a timing.

    ``duration``, ``planned_duration``, ``n_joints`` and ``resample`` are
    :class:`~lfdkit.execute.joint_motion.RetimedMotion`'s.

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
    slowdown : float
        How many times slower than the reference it runs (1: its timing kept).
    """

    times: np.ndarray
    planned_times: np.ndarray
    waypoints: np.ndarray
    waypoint_index: np.ndarray
    max_velocity: np.ndarray
    max_acceleration: np.ndarray
    max_jerk: np.ndarray
    slowdown: float
    _segments: tuple[Any, ...] = field(repr=False)  # ruckig.Trajectory per segment

    def sample(self, t: Any) -> TimedPath:
        """Positions, velocities and accelerations at times ``t``; at rest outside the motion.

        Parameters
        ----------
        t : float or array_like, shape (m,)
            Seconds; a single number gives a one-sample path.

        Returns
        -------
        TimedPath
            ``positions``, ``velocities`` and ``accelerations`` of shape
            (m, n_joints), as :meth:`lfdkit.execute.timing.Timing.sample`.
        """
        tt = np.asarray(t, dtype=np.float64)
        if tt.ndim > 1 or np.isnan(tt).any():
            raise ValueError(f"t: expected a number or a 1-D array of times, got shape {tt.shape}")
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
        return TimedPath(tt, out[0], out[1], accelerations=out[2])


def _limit(value: Any, name: str, n_joints: int) -> np.ndarray:
    return per_joint(value, name, n_joints, positive=True, scalar_ok=True)


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
    dt = np.diff(t)

    def chain(slow: float, strict: bool) -> list[Any] | None:
        """The segments with the reference slowed ``slow`` times; None if one needs longer."""
        segments = []
        for k in range(n - 1):
            problem.current_position, problem.target_position = pos[k], pos[k + 1]
            problem.current_velocity = vel[k] / slow
            problem.target_velocity = vel[k + 1] / slow
            problem.current_acceleration = acc[k] / slow**2
            problem.target_acceleration = acc[k + 1] / slow**2
            if keep_times:
                problem.minimum_duration = float(dt[k] * slow)
            segment = ruckig.Trajectory(dof)
            result = generator.calculate(problem, segment)
            if result not in (ruckig.Result.Working, ruckig.Result.Finished):
                raise ValueError(
                    f"q: ruckig found no trajectory from state {k} to {k + 1} "
                    f"(t = {t[k]:.3f}-{t[k + 1]:.3f} s): {result}; space the states further "
                    "or raise max_jerk"
                )
            if strict and segment.duration > dt[k] * slow * (1 + _STRETCH_TOL):
                return None
            segments.append(segment)
        return segments

    slow = 1.0
    segments = chain(1.0, strict=keep_times)
    if segments is None:
        # A segment stretched alone would arrive late with the reference's speed and wander
        # off the path; instead the whole reference is slowed, by the least factor that lets
        # every segment keep its (slowed) time, as time_parameterize's final check does.
        low, high = 1.0, 2.0
        while chain(high, strict=True) is None:
            low, high = high, 2.0 * high
            if high > _MAX_SLOWDOWN:
                raise ValueError(
                    f"max_jerk: the states need the reference slowed over {_MAX_SLOWDOWN:g} "
                    "times to keep the jerk limit; raise max_jerk or space the states further"
                )
        while high - low > _STRETCH_TOL * high:
            middle = 0.5 * (low + high)
            low, high = (low, middle) if chain(middle, strict=True) is not None else (middle, high)
        slow = high
        segments = chain(slow, strict=False)
        assert segments is not None
    passed = np.concatenate(([0.0], np.cumsum([segment.duration for segment in segments])))
    index = np.arange(n) if waypoint_index is None else np.asarray(waypoint_index, dtype=int)
    return JerkLimitedTrajectory(
        times=passed,
        planned_times=t - t[0],
        waypoints=pos,
        waypoint_index=index,
        max_velocity=vmax,
        max_acceleration=amax,
        max_jerk=jmax,
        slowdown=slow,
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
    times = reference.times
    at_waypoints = reference.sample(times)
    qd_at, qdd_at = np.array(at_waypoints.velocities), np.array(at_waypoints.accelerations)
    q_at = reference.waypoints  # exactly, not the spline's value there (equal to rounding)
    # At rest at both ends: the bang-bang reference still brakes at full acceleration as it stops.
    qd_at[[0, -1]], qdd_at[[0, -1]] = 0.0, 0.0
    chosen = _jerk_spaced(times, qdd_at, jerk)
    return through_states(
        times[chosen],
        q_at[chosen],
        qd_at[chosen],
        qdd_at[chosen],
        max_velocity=reference.max_velocity,
        max_acceleration=reference.max_acceleration,
        max_jerk=jerk,
        waypoint_index=reference.waypoint_index[chosen],
    )


def _jerk_spaced(times: np.ndarray, acc: np.ndarray, jerk: np.ndarray) -> np.ndarray:
    """Indices of the states to pass: each next one whose acceleration change half the jerk
    limit allows (the bang-bang reference switches from +a to -a within one 1 ms waypoint step;
    forced through every waypoint, ruckig would need the whole motion about 4 times slower)."""
    chosen, last = [0], 0
    for k in range(1, len(times)):
        step = np.abs(acc[k] - acc[last]) <= _JERK_SHARE * jerk * (times[k] - times[last])
        if k == len(times) - 1 or step.all():
            chosen.append(k)
            last = k
    end = len(times) - 1  # the stop: the states before it must leave room to reach rest too
    while len(chosen) > 2:
        k = chosen[-2]
        if (np.abs(acc[end] - acc[k]) <= _JERK_SHARE * jerk * (times[end] - times[k])).all():
            break
        chosen.pop(-2)
    return np.array(chosen)
