"""A timed path: positions at times, with velocities — what a movement is everywhere.

One record for every timed movement in the package (issue 28: one home per
concept). :class:`TimedPath` holds the times (seconds), the positions, their
velocities where known, optionally accelerations and, for a tool that turns, orientations
as unit quaternions ``[x, y, z, w]``. A DMP's rollout
(:meth:`lfdkit.imitate.DMP.rollout`, positions possibly a batch
``(n_rollouts, n, q)``), a joint trajectory's samples
(:meth:`lfdkit.execute.timing.Timing.sample`) and a plan
(:class:`TimedPlan`, which adds the planner's ``details``) are all one; so
are a recording's poses (:class:`lfdkit.io.recordings.PoseRecording`) and an
obstacle's track (:class:`lfdkit.model.motion.Trajectory`), which have no
velocities and are linear between their samples.

The record is immutable: its fields cannot be reassigned and its arrays are
read-only views (``np.array(path.positions)`` is a copy to change). Its form is
checked once, when it is made: shapes and times (finite, non-decreasing), in
one-line errors; the values are the producer's (a rollout's positions are not
re-scanned, which would cost a tenth of a large batch rollout).

:meth:`TimedPath.sample` evaluates the cubic Hermite curve through the
positions and velocities (C¹; exact for a cubic motion), and
:meth:`TimedPath.at_rate` samples it on :func:`fixed_rate_times`, the one
fixed-rate grid of plans and joint trajectories.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from dataclasses import KW_ONLY, dataclass
from typing import Any

import numpy as np
from numpy.lib.mixins import NDArrayOperatorsMixin

from lfdkit.core.rotations import angle_between, slerp
from lfdkit.core.validation import MAX_POINTS, check_positive

__all__ = ["TimedPath", "TimedPlan", "fixed_rate_times"]


def fixed_rate_times(duration: float, rate_hz: Any) -> np.ndarray:
    """The fixed-rate time grid a controller streams: ``k / rate_hz`` seconds.

    The one home of the grid used by :meth:`TimedPath.at_rate` and the joint
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


def _frozen(value: Any, name: str) -> np.ndarray:
    """``value`` as a read-only float view (the caller's array keeps its flags)."""
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(
            f"{name}: expected an array of numbers, got {type(value).__name__}"
        ) from exc
    view = array.view()
    view.flags.writeable = False
    return view


@dataclass(frozen=True, eq=False, repr=False)
class TimedPath:
    """Positions at times with their velocities: a movement, sampled.

    Attributes
    ----------
    times : ndarray, shape (n,)
        Seconds, non-decreasing (a rollout's and a plan's start at 0).
    positions : ndarray, shape (n, q) or (n_rollouts, n, q)
        Where the point is at each time (units of the producer: a skill's
        units, radians for joints). A batch of rollouts shares the times.
    velocities : ndarray, same shape as ``positions``, or None
        Units per second; None where the producer has none (a recording, an
        obstacle's track), and the path is then linear between its samples.
    accelerations : ndarray, same shape as ``positions``, or None
        Units per second squared, where the producer has them (a DMP's rollout,
        a joint trajectory); None otherwise.
    orientations : ndarray, shape (n, 4), or None
        The tool's orientation at each time, unit quaternions ``[x, y, z, w]``
        with continuous signs (one path only, not a batch); None if not known.

    Raises
    ------
    ValueError
        When made with times that are not 1-D, finite and non-decreasing, or
        arrays whose shapes do not match them: one line naming the field.
    """

    times: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray | None = None
    _: KW_ONLY
    accelerations: np.ndarray | None = None
    orientations: np.ndarray | None = None

    def __post_init__(self) -> None:
        times = _frozen(self.times, "times")
        if times.ndim != 1 or times.size == 0:
            raise ValueError(
                f"times: expected a 1-D array of at least 1 time, got shape {times.shape}"
            )
        if not np.all(np.isfinite(times)):
            raise ValueError("times: contains NaN or infinite values; give finite seconds")
        if times.size > 1 and np.any(np.diff(times) < 0):
            raise ValueError("times: must not decrease; sort the samples by time")
        positions = _frozen(self.positions, "positions")
        n = times.size
        if positions.ndim not in (2, 3) or positions.shape[-2] != n:
            raise ValueError(
                f"positions: expected shape ({n}, q) or (n_rollouts, {n}, q) for {n} times, "
                f"got {positions.shape}"
            )
        fields = {"times": times, "positions": positions}
        for name in ("velocities", "accelerations"):
            value = getattr(self, name)
            if value is None:
                continue
            array = _frozen(value, name)
            if array.shape != positions.shape:
                raise ValueError(
                    f"{name}: expected the positions' shape {positions.shape}, got {array.shape}"
                )
            fields[name] = array
        if self.orientations is not None:
            orientations = _frozen(self.orientations, "orientations")
            if orientations.shape != (n, 4):
                raise ValueError(
                    f"orientations: expected shape ({n}, 4) (one [x, y, z, w] per time), "
                    f"got {orientations.shape}"
                )
            fields["orientations"] = orientations
        for name, array in fields.items():
            object.__setattr__(self, name, array)

    @property
    def duration(self) -> float:
        """Seconds from the first sample to the last."""
        return float(self.times[-1] - self.times[0])

    @property
    def speeds(self) -> np.ndarray:
        """Speed at each sample, units per second, shape (n,) or (n_rollouts, n)."""
        if self.velocities is None:
            raise ValueError("velocities: this path has none (a recording, a track); give them")
        return np.linalg.norm(self.velocities, axis=-1)

    def positions_at(self, times: Any) -> np.ndarray:
        """Positions at any times (in any order), as :meth:`sample` gives them.

        Parameters
        ----------
        times : array_like, shape (m,)
            Seconds.

        Returns
        -------
        ndarray, shape (m, q) or (n_rollouts, m, q)
        """
        return self._between(_frozen(times, "times"))[0]

    def sample(self, times: Any) -> TimedPath:
        """The movement at other times, between its samples.

        With velocities, positions and velocities come from the cubic Hermite
        curve through the positions and velocities at their times (C¹: the
        acceleration may jump at a sample), so the velocities are the exact
        derivative of the positions and the curve passes every sample at its
        time; before the first time and after the last the point rests there
        (velocity 0). Without velocities, positions are linear between the
        samples and held before and after (``np.interp``), and the result has
        no velocities either. Orientations are slerped between neighbouring
        samples. Accelerations are not given (the cubic curve's jump at the
        samples).

        Parameters
        ----------
        times : array_like, shape (m,)
            Seconds, non-decreasing.

        Returns
        -------
        TimedPath
            Of the same type (a :class:`TimedPlan` keeps its ``details``), with
            these ``times``.
        """
        times = _frozen(times, "times")
        positions, velocities, orientations = self._between(times)
        return dataclasses.replace(
            self,
            times=times,
            positions=positions,
            velocities=velocities,
            accelerations=None,
            orientations=orientations,
        )

    def _between(self, times: np.ndarray) -> tuple[np.ndarray, Any, Any]:
        """Positions, velocities (or None) and orientations (or None) at ``times`` (m,)."""
        own = self.times
        n = own.size
        t = np.clip(times, own[0], own[-1])
        # The interval holding each sample (the last one for the end itself).
        i = np.clip(np.searchsorted(own, t, side="right") - 1, 0, max(n - 2, 0))
        j = np.minimum(i + 1, n - 1)
        t0, t1 = own[i], own[j]
        h = np.maximum(t1 - t0, 1e-300)
        s = ((t - t0) / h)[:, None]
        orientations = None
        if self.orientations is not None:
            orientations = slerp(self.orientations[i], self.orientations[j], s[:, 0])
        if self.velocities is None:
            # Column by column with np.interp: the obstacle tracks' numbers, unchanged.
            columns = np.moveaxis(self.positions, -2, 0).reshape(n, -1)
            linear = np.column_stack([np.interp(times, own, c) for c in columns.T])
            batch, q = self.positions.shape[:-2], self.positions.shape[-1]
            positions = np.moveaxis(linear.reshape(times.size, *batch, q), 0, -2)
            return positions, None, orientations
        p0, p1 = self.positions[..., i, :], self.positions[..., j, :]
        m0 = self.velocities[..., i, :] * h[:, None]
        m1 = self.velocities[..., j, :] * h[:, None]
        s2, s3 = s * s, s * s * s
        positions = (
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
        velocities[..., (times > own[-1]) | (times < own[0]), :] = 0.0  # at rest outside
        return positions, velocities, orientations

    def at_rate(self, rate_hz: float) -> TimedPath:
        """The movement sampled at a fixed rate, as a robot controller streams it.

        Samples at ``k / rate_hz`` seconds from the first time
        (:func:`fixed_rate_times`), up to the first at or after the end (past
        the end the point rests at the last position), by :meth:`sample`.

        Parameters
        ----------
        rate_hz : float
            Samples per second, e.g. 125 (a UR CB controller) or 500.

        Returns
        -------
        TimedPath
            Of the same type, with ``times`` ``t0 + k / rate_hz`` (k = 0, 1, ...).

        Raises
        ------
        ValueError
            If ``rate_hz`` is not positive, or gives more than
            :data:`~lfdkit.core.validation.MAX_POINTS` samples.
        """
        return self.sample(self.times[0] + fixed_rate_times(self.duration, rate_hz))

    def __repr__(self) -> str:
        shape = self.positions.shape
        batch = f"{shape[0]} rollouts of " if len(shape) == 3 else ""
        turned = " with orientations" if self.orientations is not None else ""
        return (
            f"{type(self).__name__}({batch}{shape[-2]} samples in {shape[-1]}-D "
            f"over {self.duration:.4g} s{turned})"
        )


@dataclass(frozen=True, eq=False, repr=False)
class TimedPlan(TimedPath, NDArrayOperatorsMixin):
    """A planned path with its timing: what :meth:`~lfdkit.skill.Skill.plan` returns.

    A :class:`TimedPath` (one path, not a batch) with the planner's result.
    The path is timed by its own arc length with the skill's speed profile
    (:attr:`lfdkit.skill.Skill.timing_`, :meth:`lfdkit.imitate.SpeedProfile.time_path`):
    a plan that swerves around an obstacle is longer than the nominal, and
    runs a little faster all along rather than fast where it swerves.

    Attributes
    ----------
    times : ndarray, shape (n_points,)
        Seconds, from 0 to :attr:`duration`.
    positions : ndarray, shape (n_points, q)
        The path, first point the start (units of the skill); also
        :attr:`points`, the name every path of the package (``Demo``,
        :class:`lfdkit.emulate.Plan`) gives its points.
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

    details: Any = None  # lfdkit.emulate.Plan (a floor above: typed by its docstring)

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.positions.ndim != 2:
            raise ValueError(
                f"positions: a plan is one path of shape (n_points, q), got {self.positions.shape}"
            )

    @property
    def points(self) -> np.ndarray:
        """The path, (n_points, q): :attr:`positions` by the name paths have here."""
        return self.positions

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
