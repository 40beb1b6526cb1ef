"""Joint trajectories that keep the person's timing, slowed only where the arm needs it.

:func:`lfdkit.execute.timing.time_parameterize` times a path as fast as the
joints allow: the person's timing is lost (a skill learned from 6 s
demonstrations ran in 3.8 s). :func:`keep_timing` instead passes waypoint
``k`` at the plan's time ``t_k`` and changes that only where the arm's limits
(times a speed fraction) require:

1. a C² cubic spline ``q(t)`` through the waypoints at their times, at rest
   at both ends (clamped);
2. its velocity and acceleration checked at five instants per interval
   against ``f · v_max`` and ``f² · a_max``; every interval over a limit is
   stretched by ``max(v/v_max, sqrt(a/a_max))`` (1 % margin), the stretch
   spread over 0.25 s of plan time either side (moving maximum, then moving
   average: a step in the time scale would be an acceleration spike), and the
   spline fitted again, until nothing exceeds a limit (a few rounds; after 30
   the whole trajectory is stretched uniformly);
3. :attr:`JointTrajectory.slowdowns` lists each stretched stretch of the
   plan: when (plan time), by how much, and which joint and limit forced it;
   nothing is slowed when the plan is within the limits.

:meth:`JointTrajectory.resample` gives fixed-rate samples (e.g. 125 Hz for a
CB-series ``servoj``, 500 Hz for an e-Series) with the spline's exact
velocities and accelerations, and :meth:`JointTrajectory.ros_message` the
same as a ``trajectory_msgs/JointTrajectory``-shaped dict.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.interpolate import CubicSpline

from lfdkit.execute.joint_motion import RetimedMotion
from lfdkit.model.timed_path import TimedPath

__all__ = ["JointTrajectory", "Slowdown", "keep_timing"]

_MARGIN = 0.01
_CHECKS = np.linspace(0.0, 1.0, 5)
_ROUNDS = 30
_RAMP = 0.25  # s: a stretch rises and falls over this much plan time (no acceleration spike)


@dataclass(frozen=True)
class Slowdown:
    """A stretch of the plan slowed for the arm's limits.

    Attributes
    ----------
    start, end : float
        Plan time (s) where it starts and ends.
    factor : float
        How many times longer it takes than planned, > 1.
    joint : int
        The joint (0-based) that forced it at its worst point.
    limit : {"velocity", "acceleration"}
    """

    start: float
    end: float
    factor: float
    joint: int
    limit: str


@dataclass(frozen=True, eq=False)
class JointTrajectory(RetimedMotion):
    """A timed joint trajectory: waypoints, their times, and the spline through them.

    ``duration``, ``planned_duration``, ``n_joints`` and ``resample`` are
    :class:`~lfdkit.execute.joint_motion.RetimedMotion`'s.

    Attributes
    ----------
    times : ndarray, shape (m,)
        When each waypoint is passed (s), from 0, strictly increasing.
    planned_times : ndarray, shape (m,)
        When the plan passed it (s).
    waypoints : ndarray, shape (m, n_joints)
    max_velocity, max_acceleration : ndarray, shape (n_joints,)
        The limits kept (speed fraction included).
    slowdowns : tuple of Slowdown
        Where the plan's timing was stretched; empty when it is kept as planned.
    joint_names : tuple of str
    """

    times: np.ndarray
    planned_times: np.ndarray
    waypoints: np.ndarray
    max_velocity: np.ndarray
    max_acceleration: np.ndarray
    slowdowns: tuple[Slowdown, ...]
    joint_names: tuple[str, ...]
    _spline: CubicSpline = field(repr=False)

    def sample(self, t: Any) -> TimedPath:
        """Positions, velocities and accelerations at times ``t`` (m,), at rest outside.

        Returns
        -------
        TimedPath
            ``times`` (m,); joint ``positions``, ``velocities`` and
            ``accelerations`` (m, n_joints): the spline and its exact derivatives.
        """
        given = np.atleast_1d(np.asarray(t, dtype=np.float64))
        tt = np.clip(given, 0.0, self.duration)
        q, qd, qdd = self._spline(tt), self._spline(tt, 1), self._spline(tt, 2)
        outside = (given < 0.0) | (given > self.duration)
        qd[outside], qdd[outside] = 0.0, 0.0
        return TimedPath(given, q, qd, accelerations=qdd)

    def ros_message(self, rate_hz: float) -> dict[str, Any]:
        """The fixed-rate samples shaped like ROS's ``trajectory_msgs/JointTrajectory``.

        ``{"joint_names": [...], "points": [{"positions", "velocities",
        "accelerations", "time_from_start": {"sec", "nanosec"}}, ...]}``.
        """
        stream = self.resample(rate_hz)
        q, qd, qdd = stream.positions, stream.velocities, stream.accelerations
        points = []
        for k, t in enumerate(stream.times):
            nanos = round(float(t) * 1e9)
            points.append(
                {
                    "positions": q[k].tolist(),
                    "velocities": qd[k].tolist(),
                    "accelerations": qdd[k].tolist(),
                    "time_from_start": {"sec": nanos // 10**9, "nanosec": nanos % 10**9},
                }
            )
        return {"joint_names": list(self.joint_names), "points": points}

    def describe_slowdowns(self) -> str:
        """One line: kept as planned, or how much longer and where."""
        if not self.slowdowns:
            return f"the plan's timing is kept ({self.duration:.3f} s, within the limits)"
        worst = max(self.slowdowns, key=lambda s: s.factor)
        parts = "; ".join(
            f"{s.start:.2f}-{s.end:.2f} s x{s.factor:.2f} (joint {s.joint + 1} {s.limit})"
            for s in self.slowdowns[:5]
        )
        more = f"; and {len(self.slowdowns) - 5} more" if len(self.slowdowns) > 5 else ""
        return (
            f"slowed for the arm's limits: {self.planned_duration:.3f} s planned, "
            f"{self.duration:.3f} s executed (x{self.duration / self.planned_duration:.3f}; "
            f"at most x{worst.factor:.2f}): {parts}{more}"
        )


def _over(spline: CubicSpline, times: np.ndarray, vmax: np.ndarray, amax: np.ndarray) -> Any:
    """Per interval: the stretch it needs (>= 0), the joint and the limit that set it."""
    dt = np.diff(times)
    tt = (times[:-1, None] + dt[:, None] * _CHECKS[None, :]).ravel()
    v = np.abs(spline(tt, 1)).reshape(len(dt), len(_CHECKS), -1) / vmax
    a = np.abs(spline(tt, 2)).reshape(len(dt), len(_CHECKS), -1) / amax
    v_need, a_need = v.max(axis=1), np.sqrt(a.max(axis=1))  # (intervals, joints)
    need = np.maximum(v_need, a_need)
    joint = need.argmax(axis=1)
    rows = np.arange(len(dt))
    limit = np.where(v_need[rows, joint] >= a_need[rows, joint], "velocity", "acceleration")
    return need.max(axis=1), joint, limit


def keep_timing(
    times: Any,
    q: Any,
    max_velocity: Any,
    max_acceleration: Any,
    *,
    joint_names: tuple[str, ...] = (),
) -> JointTrajectory:
    """Time joint waypoints as planned, stretched only where the limits require.

    Parameters
    ----------
    times : array_like, shape (m,)
        The plan's time of each waypoint (s), strictly increasing, m >= 2.
    q : array_like, shape (m, n_joints)
        Joint waypoints (rad).
    max_velocity, max_acceleration : array_like, shape (n_joints,)
        Limits to keep (speed fraction already applied), > 0.
    joint_names : tuple of str, optional
        Names for the trajectory file; default ``q1 … qn``.

    Returns
    -------
    JointTrajectory
    """
    t = np.asarray(times, dtype=np.float64) - float(times[0])
    q = np.asarray(q, dtype=np.float64)
    if t.ndim != 1 or len(t) < 2 or q.shape[0] != len(t):
        raise ValueError(f"times: expected one per waypoint (>= 2), got {t.shape} for {q.shape}")
    if not (np.diff(t) > 0).all():
        raise ValueError("times: must be strictly increasing")
    vmax = np.asarray(max_velocity, dtype=np.float64)
    amax = np.asarray(max_acceleration, dtype=np.float64)
    names = tuple(joint_names) or tuple(f"q{j + 1}" for j in range(q.shape[1]))
    planned = t.copy()
    dt = np.diff(t)
    stretch = np.ones_like(dt)
    spline = CubicSpline(t, q, bc_type="clamped", axis=0)
    first = _over(spline, t, vmax, amax)
    need = first[0]
    width = max(1, round(_RAMP / float(np.median(dt))))
    for _ in range(_ROUNDS):
        if need.max() <= 1.0:
            break
        factor = _smooth(np.maximum(1.0, need * (1.0 + _MARGIN)), width)
        stretch *= factor
        t = np.concatenate(([0.0], np.cumsum(dt * stretch)))
        spline = CubicSpline(t, q, bc_type="clamped", axis=0)
        need = _over(spline, t, vmax, amax)[0]
    if need.max() > 1.0:  # pragma: no cover - the local stretches did not settle
        t = t * np.sqrt(need.max()) * (1.0 + _MARGIN)
        stretch = np.diff(t) / dt
        spline = CubicSpline(t, q, bc_type="clamped", axis=0)
    slowdowns = _slowdowns(planned, stretch, first[1], first[2])
    return JointTrajectory(
        times=t,
        planned_times=planned,
        waypoints=q,
        max_velocity=vmax,
        max_acceleration=amax,
        slowdowns=slowdowns,
        joint_names=names,
        _spline=spline,
    )


def _smooth(factor: np.ndarray, width: int) -> np.ndarray:
    """A factor profile raised to its moving maximum, then averaged, over ``width`` intervals.

    Never below ``factor``'s moving max averaged, so every interval gets at least
    roughly what it needs, and it changes over ``width`` intervals, not in a step.
    """
    padded = np.pad(factor, width, mode="edge")
    windows = np.lib.stride_tricks.sliding_window_view(padded, 2 * width + 1)
    peak = windows.max(axis=1)
    padded = np.pad(peak, width, mode="edge")
    kernel = np.full(2 * width + 1, 1.0 / (2 * width + 1))
    return np.maximum(np.convolve(padded, kernel, mode="valid"), factor)


def _slowdowns(
    planned: np.ndarray, stretch: np.ndarray, joint: np.ndarray, limit: np.ndarray
) -> tuple[Slowdown, ...]:
    """Runs of stretched intervals as :class:`Slowdown` records."""
    slowed = stretch > 1.0 + 1e-12
    out = []
    i = 0
    while i < len(stretch):
        if not slowed[i]:
            i += 1
            continue
        j = i
        while j + 1 < len(stretch) and slowed[j + 1]:
            j += 1
        worst = i + int(np.argmax(stretch[i : j + 1]))
        span = planned[j + 1] - planned[i]
        factor = float(np.sum(np.diff(planned)[i : j + 1] * stretch[i : j + 1]) / span)
        out.append(
            Slowdown(
                start=float(planned[i]),
                end=float(planned[j + 1]),
                factor=factor,
                joint=int(joint[worst]),
                limit=str(limit[worst]),
            )
        )
        i = j + 1
    return tuple(out)
