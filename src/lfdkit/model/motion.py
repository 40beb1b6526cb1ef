"""Moving obstacles: how an obstacle moves, and a tracker that predicts it (NumPy only).

The thesis plans around static obstacles and names moving ones, predicted
over the MPC horizon, as future work. Here an obstacle may carry a
:class:`Motion` (:attr:`lfdkit.model.scene.Obstacle.motion`): where its reference
point (its ``position``) is at a time, as a mean and a covariance, so the
planner can keep clear of where it *will* be and widen its margin with the
uncertainty.

Times are seconds from the start of the plan (``t = 0`` is when the tool is at
the plan's first point); positions are in the units of the paths.

Motions
-------
* :class:`ConstantVelocity` — ``p(t) = p(0) + v t``, known exactly;
* :class:`Trajectory` — a known path (a :class:`~lfdkit.model.timed_path.TimedPath`), linearly
  interpolated and held at its ends (a scripted obstacle, a replayed log);
* :class:`Observations` — noisy observations of the position up to now; a
  tracker (by default :class:`ConstantVelocityKalman`) estimates the state
  and predicts the position, with its covariance, at any later time;
* :class:`Tracked` — a live tracker fed by a control loop (not stored in files).

Trackers
--------
A tracker is anything with ``update(t, z)`` (an observation ``z`` (q,) at time
``t``, in time order) and ``predict(times) -> (means (n, q), covs (n, q, q))``
(:class:`Tracker`); :class:`Observations` takes a factory of them, so another
motion model (constant acceleration, a learned one, an IMM) plugs in without
touching the planner.

:class:`ConstantVelocityKalman` is a short, documented linear Kalman filter
for the state ``[p, v]`` with white-noise acceleration (the continuous
Wiener-process model, Bar-Shalom et al. 2001, §6.2): filterpy's
``KalmanFilter`` computes the same numbers (the tests compare them), but it is
an unmaintained, SciPy/matplotlib-importing package, and the planner calls the
prediction at every control step (a few microseconds here).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any, Protocol, runtime_checkable

import numpy as np

from lfdkit.model.timed_path import TimedPath

__all__ = [
    "ConstantVelocity",
    "ConstantVelocityKalman",
    "Motion",
    "Observations",
    "Tracked",
    "Tracker",
    "Trajectory",
]


@runtime_checkable
class Tracker(Protocol):
    """Estimates a moving point from noisy observations and predicts it."""

    def update(self, t: float, z: Any) -> None:
        """Take an observation ``z`` (q,) at time ``t`` (s, not before the last one)."""

    def predict(self, times: Any) -> tuple[np.ndarray, np.ndarray]:
        """Predicted positions (n, q) and their covariances (n, q, q) at ``times`` (n,)."""


class Motion:
    """How an obstacle's reference point moves: its position's mean and covariance over time.

    Subclasses implement :meth:`predict` and :meth:`transformed`.
    """

    #: Name in scene files.
    kind: str = ""

    def predict(self, origin: np.ndarray, times: Any) -> tuple[np.ndarray, np.ndarray]:
        """Mean positions (n, q) and covariances (n, q, q) at ``times`` (n,) s.

        ``origin`` (q,) is the obstacle's ``position`` (its place at ``t = 0``
        for a motion relative to it).
        """
        raise NotImplementedError

    def position_at(self, origin: np.ndarray, t: float) -> np.ndarray:
        """The mean position (q,) at time ``t``."""
        return self.predict(origin, np.array([float(t)]))[0][0]

    def transformed(self, factor: float, flip: np.ndarray) -> Motion:
        """The motion with every point ``p`` mapped to ``factor · flip · p``."""
        raise NotImplementedError


def _times(value: Any, name: str = "times") -> np.ndarray:
    times = np.asarray(value, dtype=np.float64).reshape(-1)
    if not np.all(np.isfinite(times)):
        raise ValueError(f"{name}: must be finite")
    return times


def _track(times: Any, positions: Any, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Checked ``times`` (n,) strictly increasing and ``positions`` (n, q), q 2 or 3."""
    times = _times(times, f"{name} times")
    points = np.asarray(positions, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] not in (2, 3) or points.shape[0] != times.size:
        raise ValueError(
            f"{name} positions: expected shape ({times.size}, 2 or 3), got {points.shape}"
        )
    if times.size < 1:
        raise ValueError(f"{name} times: need at least one")
    if not np.all(np.isfinite(points)):
        raise ValueError(f"{name} positions: must be finite")
    if np.any(np.diff(times) <= 0.0):
        raise ValueError(f"{name} times: must be strictly increasing")
    times.setflags(write=False)
    points.setflags(write=False)
    return times, points


class ConstantVelocity(Motion):
    """``p(t) = p(0) + v t``: a known, constant velocity (units/s).

    Parameters
    ----------
    velocity : array_like, shape (q,)
    """

    kind = "velocity"

    def __init__(self, velocity: Any) -> None:
        v = np.asarray(velocity, dtype=np.float64).reshape(-1)
        if v.size not in (2, 3) or not np.all(np.isfinite(v)):
            raise ValueError(f"velocity: expected 2 or 3 finite numbers, got {velocity!r}")
        v.setflags(write=False)
        self.velocity = v

    def predict(self, origin: np.ndarray, times: Any) -> tuple[np.ndarray, np.ndarray]:
        t = _times(times)
        q = origin.size
        if self.velocity.size != q:
            raise ValueError(f"velocity: {self.velocity.size} components for a {q}-D position")
        means = origin[None] + t[:, None] * self.velocity[None]
        return means, np.zeros((t.size, q, q))

    def transformed(self, factor: float, flip: np.ndarray) -> ConstantVelocity:
        return ConstantVelocity(factor * flip * self.velocity)

    def __repr__(self) -> str:
        return f"ConstantVelocity({self.velocity.tolist()})"


class Trajectory(Motion):
    """A known path: positions at times, linearly interpolated, held before and after.

    The path is a :class:`lfdkit.model.timed_path.TimedPath` without
    velocities (:attr:`path`), so an obstacle's track is the same record as a
    robot's movement; this class adds what a planner asks of a motion.

    Parameters
    ----------
    times : array_like, shape (n,)
        Seconds, strictly increasing.
    positions : array_like, shape (n, q)
        Where the reference point is (absolute, units).

    Attributes
    ----------
    path : TimedPath
        The times and positions, read-only.
    """

    kind = "trajectory"

    def __init__(self, times: Any, positions: Any) -> None:
        self.path = TimedPath(*_track(times, positions, "trajectory"))

    @property
    def times(self) -> np.ndarray:
        """Seconds, (n,)."""
        return self.path.times

    @property
    def positions(self) -> np.ndarray:
        """Positions, (n, q)."""
        return self.path.positions

    def predict(self, origin: np.ndarray, times: Any) -> tuple[np.ndarray, np.ndarray]:
        means = self.path.positions_at(_times(times))
        return means, np.zeros((means.shape[0], means.shape[1], means.shape[1]))

    def transformed(self, factor: float, flip: np.ndarray) -> Trajectory:
        return Trajectory(self.times, factor * flip * self.positions)

    def __repr__(self) -> str:
        first, last = self.times[0], self.times[-1]
        return f"Trajectory(<{self.times.size} samples, {first:g} to {last:g} s>)"


class Observations(Motion):
    """Noisy observations of the position so far; a tracker predicts the rest.

    The tracker (``model(noise)``, default :class:`ConstantVelocityKalman`) is
    run over every observation; its prediction at a time before the last
    observation is the last state's extrapolated backwards (what a controller
    that knows only the latest estimate would use).

    A single observation shows no velocity: the default tracker's prior
    (0.5 m/s either way) would grow the allowance by a metre per second and
    block every plan, so the obstacle is taken as *standing* where it was
    seen, with the observation noise as its uncertainty, and a warning says
    so (a snapshot of a cup is what a static scene is). A plugged ``model``
    is used as given.

    Parameters
    ----------
    times : array_like, shape (n,)
        Seconds, strictly increasing.
    positions : array_like, shape (n, q)
        Observed positions (absolute, units).
    noise : float
        Standard deviation of each coordinate's observation error (units, > 0).
    model : callable, optional
        ``model(noise) -> Tracker``; default :class:`ConstantVelocityKalman`.
    """

    kind = "observations"

    def __init__(
        self,
        times: Any,
        positions: Any,
        noise: float,
        model: Callable[[float], Tracker] | None = None,
    ) -> None:
        self.times, self.positions = _track(times, positions, "observations")
        noise = float(noise)
        if not np.isfinite(noise) or noise <= 0.0:
            raise ValueError(f"noise: must be a positive number, got {noise!r}")
        self.noise = noise
        self.model = model
        self._tracker: Tracker | None = None
        if self.standing:
            warnings.warn(
                "observations: a single observation shows no velocity; the obstacle is "
                "planned as standing where it was seen (its noise the uncertainty); give "
                "two or more observations to track its motion",
                stacklevel=2,
            )

    @property
    def standing(self) -> bool:
        """Whether the obstacle is taken as standing (one observation, the default tracker)."""
        return self.times.size == 1 and self.model is None

    def tracker(self) -> Tracker:
        """The tracker after every observation (built once)."""
        if self._tracker is None:
            factory = ConstantVelocityKalman if self.model is None else self.model
            tracker = factory(self.noise)
            for t, z in zip(self.times, self.positions, strict=True):
                tracker.update(float(t), z)
            self._tracker = tracker
        return self._tracker

    def predict(self, origin: np.ndarray, times: Any) -> tuple[np.ndarray, np.ndarray]:
        t = _times(times)
        if self.standing:
            q = self.positions.shape[1]
            return np.repeat(self.positions[:1], t.size, axis=0), np.repeat(
                self.noise**2 * np.eye(q)[None], t.size, axis=0
            )
        return self.tracker().predict(t)

    def transformed(self, factor: float, flip: np.ndarray) -> Observations:
        with warnings.catch_warnings():  # said once, when the observations came in
            warnings.simplefilter("ignore")
            return Observations(
                self.times, factor * flip * self.positions, factor * self.noise, self.model
            )

    def __repr__(self) -> str:
        return f"Observations(<{self.times.size} samples>, noise={self.noise:g})"


class Tracked(Motion):
    """A live tracker's prediction (the closed loop: the tracker takes observations as they come).

    Not written to scene files (it has no fixed data); :class:`Observations`
    is the file form.

    Parameters
    ----------
    tracker : Tracker
        With at least one observation before the first prediction.
    """

    kind = "tracked"

    def __init__(self, tracker: Tracker) -> None:
        # (duck-typed: a runtime Protocol check costs more than a prediction)
        methods = (getattr(tracker, name, None) for name in ("update", "predict"))
        if not all(callable(method) for method in methods):
            raise TypeError(f"tracker: expected an update/predict tracker, got {tracker!r}")
        self.tracker = tracker

    def predict(self, origin: np.ndarray, times: Any) -> tuple[np.ndarray, np.ndarray]:
        return self.tracker.predict(_times(times))

    def transformed(self, factor: float, flip: np.ndarray) -> Motion:
        raise ValueError("a live tracker cannot be scaled or mirrored; use Observations")

    def __repr__(self) -> str:
        return f"Tracked({type(self.tracker).__name__})"


class ConstantVelocityKalman:
    """A constant-velocity Kalman filter of a point in 2-D or 3-D (state ``[p, v]``).

    Model (per coordinate, independent): ``p' = p + v Δt``, ``v' = v`` plus a
    white-noise acceleration of spectral density ``acceleration²`` (the
    process noise ``Q = a² [[Δt³/3, Δt²/2], [Δt²/2, Δt]]``); observations
    ``z = p + e`` with ``e ~ N(0, noise² I)``. The first observation sets the
    position (covariance ``noise²``) and a zero velocity with standard
    deviation ``velocity_std``. Each coordinate is filtered by the same 2×2
    recursion (the covariance is shared, the model being isotropic), so an
    update is a handful of scalar operations.

    Manoeuvres. A white-noise acceleration is a statistical model; a cup
    that brakes hard does not follow it, and the filter's estimate lags
    (the issue-27 battery: a cup braking at 0.27 m/s² was predicted 23–40 mm
    off against a 2σ allowance of ~9 mm). With ``max_acceleration`` ``A``
    the filter also carries a *deterministic* bound on the error any
    acceleration ``|a(t)| ≤ A`` can cause: the error is linear in the
    acceleration history, ``e = Σ_j m_j a_j`` (each interval's influence
    ``m_j`` propagated through every later prediction and correction, the
    model being the same in every coordinate), so ``|e| ≤ A Σ_j |m_j|``, and
    ``τ`` s ahead the unseen future adds ``A τ²/2``. :meth:`predict` reports
    the standard deviation ``σ + b/2`` (``σ`` the noise's, ``b`` that bound):
    a 2σ allowance is then the noise's 2σ *plus* the worst bias, for any
    acceleration up to ``A`` (piecewise constant between observations), turns
    included (``v²/R ≤ A``). ``A = 0`` (the default) is the plain filter.

    Parameters
    ----------
    noise : float
        Observation standard deviation per coordinate (units, > 0).
    acceleration : float
        Process-noise intensity (units/s^1.5): how much the velocity may
        wander; 0 for a velocity that never changes.
    velocity_std : float
        Prior standard deviation of the velocity (units/s).
    max_acceleration : float
        Largest acceleration (units/s², ≥ 0) the prediction's allowance
        covers (above); 0: none.
    bound_horizon : float
        Seconds ahead (> 0) up to which the bound is carried; beyond, it
        stays at its value there (the worst case grows as ``τ²`` and would
        block every plan a second ahead; a closed loop re-plans long before).
        Default: no limit.

    Attributes
    ----------
    time : float
        Time of the last observation (s); NaN before the first.
    mean : ndarray, shape (2, q)
        Position and velocity estimates (rows).
    cov : ndarray, shape (2, 2)
        Covariance of ``[p, v]`` of each coordinate (units², units²/s, units²/s²).
    n_updates : int
    influence : ndarray, shape (j, 2)
        With ``max_acceleration``: the position and velocity error per unit
        of acceleration in each of the last :attr:`MEMORY` intervals
        (s², s); empty otherwise.
    """

    #: Intervals whose influence on the error bound is kept (older ones have decayed).
    MEMORY = 200

    def __init__(
        self,
        noise: float,
        acceleration: float = 0.02,
        velocity_std: float = 0.5,
        max_acceleration: float = 0.0,
        bound_horizon: float = float("inf"),
    ) -> None:
        for name, value in (("noise", noise), ("velocity_std", velocity_std)):
            if not (np.isfinite(value) and value > 0.0):
                raise ValueError(f"{name}: must be a positive number, got {value!r}")
        for name, value in (("acceleration", acceleration), ("max_acceleration", max_acceleration)):
            if not (np.isfinite(value) and value >= 0.0):
                raise ValueError(f"{name}: must be >= 0, got {value!r}")
        self.noise = float(noise)
        self.acceleration = float(acceleration)
        self.velocity_std = float(velocity_std)
        self.max_acceleration = float(max_acceleration)
        if not bound_horizon > 0.0:
            raise ValueError(f"bound_horizon: must be > 0 s, got {bound_horizon!r}")
        self.bound_horizon = float(bound_horizon)
        self.time = float("nan")
        self.mean = np.zeros((2, 0))
        self.cov = np.zeros((2, 2))
        self.n_updates = 0
        self.influence = np.zeros((0, 2))

    def _propagated(self, dt: float) -> np.ndarray:
        """The state covariance ``F P Fᵀ + Q`` after ``dt`` s (dt ≥ 0)."""
        (p, c), (_, v) = self.cov
        q = self.acceleration**2
        return np.array(
            [
                [p + 2.0 * dt * c + dt * dt * v + q * dt**3 / 3.0, c + dt * v + q * dt * dt / 2.0],
                [c + dt * v + q * dt * dt / 2.0, v + q * dt],
            ]
        )

    def update(self, t: float, z: Any) -> None:
        """Predict to ``t`` and correct with the observation ``z`` (q,)."""
        z = np.asarray(z, dtype=np.float64).reshape(-1)
        t = float(t)
        r = self.noise**2
        if self.n_updates == 0:
            self.mean = np.vstack([z, np.zeros_like(z)])
            self.cov = np.diag([r, self.velocity_std**2])
        else:
            dt = t - self.time
            if not dt >= 0.0:
                raise ValueError(
                    f"t: observations must come in time order, got {t} after {self.time}"
                )
            if z.size != self.mean.shape[1]:
                raise ValueError(f"z: expected {self.mean.shape[1]} coordinates, got {z.size}")
            self.mean = np.vstack([self.mean[0] + dt * self.mean[1], self.mean[1]])
            cov = self._propagated(dt)
            gain = cov[:, 0] / (cov[0, 0] + r)  # (2,) Kalman gain of the position observation
            self.mean = self.mean + gain[:, None] * (z - self.mean[0])[None]
            self.cov = cov - np.outer(gain, cov[0])
            if self.max_acceleration > 0.0:
                self._propagate_influence(dt, gain)
        self.time = t
        self.n_updates += 1

    def predict(self, times: Any) -> tuple[np.ndarray, np.ndarray]:
        """Predicted positions (n, q) and covariances (n, q, q) at ``times`` (n,) s.

        Before the last observation the mean is extrapolated backwards and the
        covariance is the position covariance propagated by ``|Δt|``.
        """
        if self.n_updates == 0:
            raise ValueError("predict: the tracker has no observation yet")
        t = _times(times)
        dt = t - self.time
        means = self.mean[0] + dt[:, None] * self.mean[1]
        (p, c), (_, v) = self.cov.tolist()  # floats: the same arithmetic, less overhead
        a = np.abs(dt)
        var = p + dt * (2.0 * c + dt * v)
        var += (self.acceleration**2 / 3.0) * a * a * a
        if self.max_acceleration > 0.0:
            # σ + b/2: a 2σ allowance is the noise's 2σ plus the worst bias (class notes)
            var = (np.sqrt(np.maximum(var, 0.0)) + 0.5 * self.bias_bound(dt)) ** 2
        q = self.mean.shape[1]
        covs = np.zeros((t.size, q, q))
        diagonal = np.arange(q)
        covs[:, diagonal, diagonal] = var[:, None]
        return means, covs

    def _propagate_influence(self, dt: float, gain: np.ndarray) -> None:
        """Carry each past interval's error per unit acceleration through this update."""
        # prediction: e_p += dt e_v (+ dt²/2 a over the new interval); e_v += (dt a);
        # correction with the observation: e ← (I − g Hᵀ) e
        m = np.vstack([self.influence, [[0.0, 0.0]]])
        m[:, 0] += dt * m[:, 1]
        m[-1] = [0.5 * dt * dt, dt]
        position = m[:, 0].copy()
        m[:, 0] = (1.0 - gain[0]) * position
        m[:, 1] -= gain[1] * position
        # old intervals' influence decays geometrically: drop what no longer counts
        size = np.abs(m).sum(axis=1)
        self.influence = m[size > 1e-12 * size.max()][-self.MEMORY :]

    def bias_bound(self, ahead: Any) -> np.ndarray:
        """The largest position error (units) an acceleration up to ``max_acceleration`` causes.

        Parameters
        ----------
        ahead : array_like, shape (n,)
            Seconds after the last observation (negative: before it).

        Returns
        -------
        ndarray, shape (n,)
            ``A (Σ_j |m_j,p + τ m_j,v| + τ²/2)``, ``τ`` limited to ``±bound_horizon``;
            0 without ``max_acceleration``.
        """
        tau = np.asarray(ahead, dtype=np.float64).reshape(-1)
        # (np.clip's dispatch costs more than the two comparisons it makes)
        tau = np.minimum(np.maximum(tau, -self.bound_horizon), self.bound_horizon)
        if self.max_acceleration == 0.0:
            return np.zeros(tau.size)
        m = self.influence
        past = np.abs(m[None, :, 0] + tau[:, None] * m[None, :, 1]).sum(axis=1)
        return self.max_acceleration * (past + 0.5 * tau * tau)

    @property
    def velocity(self) -> np.ndarray:
        """The velocity estimate (q,)."""
        return self.mean[1].copy()

    @property
    def state_covariance(self) -> np.ndarray:
        """Covariance of the full state ``[p, v]`` (2q, 2q), coordinates blocked as p then v."""
        q = self.mean.shape[1]
        return np.kron(self.cov, np.eye(q))
