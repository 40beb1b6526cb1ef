"""Time parameterisation of a joint-space path within joint velocity and acceleration limits.

The robot has to follow waypoints ``q_0 .. q_{n-1}`` (joint angles, rad) as
fast as its joints allow, starting and ending at rest. The limits are the
arm's (``arm.max_joint_speed`` and ``arm.max_joint_acceleration`` of an
:class:`lfdkit.execute.arm.Arm`; by default the UR5 of the thesis, §6.4,
Table 6.2: 3.2 rad/s and 15 rad/s² on every joint) unless given explicitly,
one number for all joints or one per joint. The path-parameter method:

1. *Path.* ``s`` is the cumulative joint-space distance through the waypoints
   (the piecewise-linear arc length, rad). A natural cubic spline ``q(s)``
   through the waypoints at those ``s`` makes the path C2, so it can be
   followed without stopping at each waypoint. It passes through every
   waypoint exactly; between waypoints it may bulge off the straight segment
   (at sharp corners), never on a straight run: collinear waypoints give a
   straight line.
2. *Profile.* Along the path ``q̇ = q'(s) ṡ`` and ``q̈ = q'(s) s̈ + q''(s) ṡ²``,
   so with ``x = ṡ²`` and ``u = s̈`` (``dx/ds = 2u``) every limit is linear in
   ``(x, u)``. On a fine grid of ``s`` with ``u`` constant on each interval,
   a backward pass computes the largest ``x`` at each grid point from which
   the robot can still stop at the end, and a forward pass from rest
   accelerates as hard as allowed without leaving that set (the discrete
   forward–backward or "TOPP-RA" scheme). The acceleration limits are
   imposed at both ends of every interval, the velocity limits at every grid
   point.
3. *Margin.* The profile is planned against the limits times
   ``1 − SAFETY_MARGIN`` (1 %), then checked at five instants per interval
   against the full limits; should anything still exceed them (between grid
   points) the whole trajectory is slowed uniformly until nothing does. A
   straight single-joint move comes out within about 1 % of the closed-form
   minimum time.

Backends. ``backend="toppra"`` computes step 2 with toppra (``pip install
toppra``, the field's maintained TOPP-RA) on the same spline and grid; steps
1 and 3 are shared, so both give the same kind of :class:`Timing`.
On the same grid the two agree to 1e-7 in duration (a random 200-waypoint UR5
path: 23.1573718 s both; toppra about 10 times slower there, one small QP per
grid point). ``benchmarks/robot.py --arms-only`` (A4) also runs toppra on its
own, coarser grid: durations within 0.5 %, 5–17 times faster than this
module's profile. The default stays lfdkit's: no extra dependency, the same
answer.

``speed_fraction`` slows the trajectory the way the speed slider of a UR
controller does: velocity limits times ``f``, acceleration limits times
``f²``. The path is the same and every time is exactly ``1/f`` longer.

Repeated waypoints (consecutive ones less than ``DUPLICATE_TOL`` apart) are
dropped: the later copy is removed and :attr:`Timing.waypoint_index` says
which input rows were kept.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lfdkit.core.geometry import arc_length
from lfdkit.core.validation import check_path
from lfdkit.execute.arm import UR5, Arm, check_arm, per_joint
from lfdkit.execute.joint_motion import JointMotion
from lfdkit.model.timed_path import TimedPath

__all__ = [
    "DUPLICATE_TOL",
    "SAFETY_MARGIN",
    "Timing",
    "time_parameterize",
]

SAFETY_MARGIN = 0.01
"""Fraction of each limit kept in reserve when planning the profile."""

DUPLICATE_TOL = 1e-9
"""Consecutive waypoints closer than this (rad, Euclidean in joint space) are merged."""

#: Slowest speed setting accepted: 0.1 % of the limits (the UR slider's lowest step is 1 %);
#: below it the acceleration limits (scaled by its square) underflow toward 0 and the
#: profile stalls.
MIN_SPEED_FRACTION = 1e-3
_GRID_INTERVALS = 2000  # about this many s-intervals over the whole path
_MIN_PER_SEGMENT = 4  # and at least this many between two waypoints
_CHECK_FRACTIONS = np.array([0.0, 0.25, 0.5, 0.75, 1.0])  # where each interval is verified


@dataclass(frozen=True, eq=False)
class Timing(JointMotion):
    """A joint-space trajectory: a smooth path through waypoints and its timing.

    ``n_joints`` and ``resample`` are :class:`~lfdkit.execute.joint_motion.JointMotion`'s.

    Attributes
    ----------
    times : ndarray, shape (n_kept,)
        When each kept waypoint is passed (s); starts at 0, strictly increasing.
    waypoints : ndarray, shape (n_kept, n_joints)
        The waypoints (rad) after dropping repeated ones.
    waypoint_index : ndarray of int, shape (n_kept,)
        Row of the input ``q`` that each kept waypoint came from.
    max_velocity : ndarray, shape (n_joints,)
        Velocity limits the trajectory respects (rad/s), ``speed_fraction`` included.
    max_acceleration : ndarray, shape (n_joints,)
        Acceleration limits the trajectory respects (rad/s²), ``speed_fraction`` included.
    """

    times: np.ndarray
    waypoints: np.ndarray
    waypoint_index: np.ndarray
    max_velocity: np.ndarray
    max_acceleration: np.ndarray
    _spline: Any = field(repr=False)  # scipy.interpolate.CubicSpline
    _s: np.ndarray = field(repr=False)  # (N+1,) grid of path positions
    _t: np.ndarray = field(repr=False)  # (N+1,) time at each grid position
    _sd: np.ndarray = field(repr=False)  # (N+1,) path speed ṡ at each grid position
    _u: np.ndarray = field(repr=False)  # (N,) path acceleration s̈ on each interval

    @property
    def duration(self) -> float:
        """Time from start to stop (s): the end of the profile's grid."""
        return float(self._t[-1])

    def sample(self, t: Any) -> TimedPath:
        """Joint positions, velocities and accelerations at given times.

        Parameters
        ----------
        t : float or array_like, shape (m,)
            Times (s), non-decreasing (a number is one time). Before 0 the
            robot is at rest at the first waypoint, after :attr:`duration`
            at rest at the last.

        Returns
        -------
        TimedPath
            ``times`` (m,) and joint ``positions`` (rad), ``velocities``
            (rad/s) and ``accelerations`` (rad/s²), each (m, n_joints). The
            acceleration is piecewise continuous; at a jump the value on the
            later side is returned.
        """
        try:
            tt = np.asarray(t, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"t: expected a number or a 1-D array of times, got {t!r}") from exc
        if tt.ndim > 1:
            raise ValueError(f"t: expected a number or a 1-D array, got shape {tt.shape}")
        if np.isnan(tt).any():
            raise ValueError("t: contains NaN")
        tt = np.atleast_1d(tt)
        s, sd, sdd = self._path_state(tt)
        q, qd, qdd = self._joint_state(s, sd, sdd)
        return TimedPath(tt, q, qd, accelerations=qdd)

    # ------------------------------------------------------------------ internals
    def _path_state(self, tt: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Path position, speed and acceleration at times ``tt`` (m,)."""
        t_grid, s_grid, sd, u = self._t, self._s, self._sd, self._u
        i = np.clip(np.searchsorted(t_grid, tt, side="right") - 1, 0, len(u) - 1)
        tau = tt - t_grid[i]
        s = np.clip(s_grid[i] + sd[i] * tau + 0.5 * u[i] * tau * tau, s_grid[i], s_grid[i + 1])
        v = np.maximum(sd[i] + u[i] * tau, 0.0)
        a = u[i].copy()
        before, after = tt < 0.0, tt > t_grid[-1]
        s[before], s[after] = s_grid[0], s_grid[-1]
        v[before | after] = 0.0
        a[before | after] = 0.0
        return s, v, a

    def _joint_state(
        self, s: np.ndarray, sd: np.ndarray, sdd: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        q = self._spline(s)
        qp = self._spline(s, 1)
        qpp = self._spline(s, 2)
        return q, qp * sd[:, None], qp * sdd[:, None] + qpp * (sd * sd)[:, None]


# --------------------------------------------------------------------------- #
# Validation
# --------------------------------------------------------------------------- #


def _check_limits(value: Any, name: str, n_joints: int, arm: Arm, field: str) -> np.ndarray:
    """A positive scalar or one positive value per joint, as an array of shape (n_joints,).

    ``None`` takes the arm's limits (``getattr(arm, field)``), which the arm checked
    when it was made; only their number must match the path's joints.
    """
    if value is None:
        if arm.n_joints != n_joints:
            raise ValueError(
                f"q: has {n_joints} joints, the {arm.name} {arm.n_joints}; pass the arm "
                "with this many joints, or max_velocity and max_acceleration"
            )
        return getattr(arm, field)
    return per_joint(value, name, n_joints, positive=True, scalar_ok=True)


def _check_speed_fraction(value: Any) -> float:
    try:
        f = float(value)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"speed_fraction: expected a number, got {value!r}") from exc
    if not (MIN_SPEED_FRACTION <= f <= 1.0):  # also rejects NaN
        raise ValueError(
            f"speed_fraction: must be in [{MIN_SPEED_FRACTION:g}, 1], got {value!r}"
            + ("; a smaller fraction stops the arm (its squared limits vanish)" if 0 < f else "")
        )
    return f


# --------------------------------------------------------------------------- #
# Profile
# --------------------------------------------------------------------------- #


def _grid(knots: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Fine grid of path positions containing every knot; returns (grid, knot positions in it)."""
    lengths = np.diff(knots)
    h = knots[-1] / _GRID_INTERVALS
    per = np.maximum(_MIN_PER_SEGMENT, np.ceil(lengths / h)).astype(int)
    pieces = [np.linspace(knots[j], knots[j + 1], per[j] + 1)[:-1] for j in range(len(lengths))]
    grid = np.concatenate([*pieces, knots[-1:]])
    return grid, np.concatenate(([0], np.cumsum(per)))


def _u_bounds(
    c_u: np.ndarray, c_x: np.ndarray, limit: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Turn ``|c_u u + c_x x| <= limit`` into bounds on ``u`` linear in ``x``.

    All arrays (N, k). Returns ``lower = α + β x``, ``upper = γ + δ x`` (±inf
    where a row does not bound ``u``) and a bound on ``x`` alone (N,) from rows
    whose ``u`` coefficient vanishes.
    """
    tiny = 1e-12 * np.maximum(np.abs(c_u).max(axis=1, keepdims=True), 1e-300)
    active = np.abs(c_u) > tiny
    cu = np.where(active, c_u, 1.0)
    pos = cu > 0
    # c_u > 0: (−a − c_x x)/c_u <= u <= (a − c_x x)/c_u; c_u < 0 swaps the two.
    lo_const = np.where(pos, -limit, limit) / cu
    hi_const = np.where(pos, limit, -limit) / cu
    slope = -c_x / cu
    alpha = np.where(active, lo_const, -np.inf)
    gamma = np.where(active, hi_const, np.inf)
    beta = np.where(active, slope, 0.0)
    delta = np.where(active, slope, 0.0)
    with np.errstate(divide="ignore"):
        x_only = np.where(active | (c_x == 0), np.inf, limit / np.abs(c_x))
    return alpha, beta, gamma, delta, x_only.min(axis=1)


def _profile(
    qp: np.ndarray, qpp: np.ndarray, ds: np.ndarray, vmax: np.ndarray, amax: np.ndarray
) -> np.ndarray:
    """Squared path speeds ``x = ṡ²`` (N+1,) on the grid; rest at both ends.

    ``qp``, ``qpp``: (N+1, n_joints) path derivatives at the grid points;
    ``ds``: (N,) interval lengths.
    """
    n = len(ds)
    with np.errstate(divide="ignore"):
        speed = np.abs(qp)
        x_vel = np.where(speed > 0, (vmax / np.where(speed > 0, speed, 1.0)) ** 2, np.inf).min(1)
    two_d = 2.0 * ds[:, None]
    # Rows per interval i: the limits at its start (x_i, u_i) and at its end, where
    # x_{i+1} = x_i + 2 ds u_i, so q'' x_{i+1} + q' u = q'' x_i + (q' + 2 ds q'') u.
    c_u = np.concatenate((qp[:-1], qp[1:] + two_d * qpp[1:]), axis=1)
    c_x = np.concatenate((qpp[:-1], qpp[1:]), axis=1)
    limit = np.concatenate((amax, amax))[None, :]
    alpha, beta, gamma, delta, x_only = _u_bounds(c_u, c_x, limit)

    with np.errstate(divide="ignore", invalid="ignore"):
        # Some u exists: α_k + β_k x <= γ_l + δ_l x for every pair (k, l).
        p = beta[:, :, None] - delta[:, None, :]
        r = gamma[:, None, :] - alpha[:, :, None]
        pair = np.where(p > 0, r / np.where(p > 0, p, 1.0), np.inf).reshape(n, -1).min(axis=1)
        # x_{i+1} >= 0 with the largest u: x + 2 ds (γ_l + δ_l x) >= 0.
        pn = -(1.0 + two_d * delta)
        nonneg = np.where(pn > 0, two_d * gamma / np.where(pn > 0, pn, 1.0), np.inf).min(axis=1)
    static = np.minimum.reduce([x_vel[:-1], x_only, pair, nonneg])

    # Backward: K_i = largest x_i from which some allowed u reaches x_{i+1} <= K_{i+1},
    # i.e. x + 2 ds (α_k + β_k x) <= K_{i+1} for every lower bound k.
    p_back = 1.0 + two_d * beta
    use = p_back > 0
    p_back = np.where(use, p_back, 1.0)
    k_set = np.empty(n + 1)
    k_set[n] = 0.0
    for i in range(n - 1, -1, -1):
        with np.errstate(invalid="ignore"):
            reach = np.where(use[i], (k_set[i + 1] - two_d[i] * alpha[i]) / p_back[i], np.inf)
        k_set[i] = max(0.0, min(static[i], reach.min()))

    # Forward from rest: the largest u allowed at x_i, capped by the backward set.
    x = np.empty(n + 1)
    x[0] = 0.0
    for i in range(n):
        u_max = float(np.min(gamma[i] + delta[i] * x[i]))
        x[i + 1] = max(0.0, min(k_set[i + 1], x[i] + 2.0 * ds[i] * u_max))
    return x


def _profile_toppra(
    knots: np.ndarray, way: np.ndarray, s: np.ndarray, vmax: np.ndarray, amax: np.ndarray
) -> np.ndarray:
    """Squared path speeds on the grid ``s`` from toppra's TOPP-RA, same spline and limits."""
    try:
        import toppra
        import toppra.algorithm
        import toppra.constraint
    except ImportError:
        raise ImportError("backend: 'toppra' needs toppra: python -m pip install toppra") from None
    toppra.setup_logging("WARNING")
    path = toppra.SplineInterpolator(knots, way, bc_type="natural")
    limits = [
        toppra.constraint.JointVelocityConstraint(np.column_stack([-vmax, vmax])),
        toppra.constraint.JointAccelerationConstraint(np.column_stack([-amax, amax])),
    ]
    instance = toppra.algorithm.TOPPRA(limits, path, gridpoints=s)
    sd = instance.compute_parameterization(0.0, 0.0)[1]
    if sd is None or not np.isfinite(sd).all():  # pragma: no cover - toppra's own failure
        raise RuntimeError("backend toppra: found no parameterisation of the path")
    return np.maximum(sd, 0.0) ** 2


def time_parameterize(
    q: Any,
    *,
    arm: Arm = UR5,
    max_velocity: Any = None,
    max_acceleration: Any = None,
    speed_fraction: float = 1.0,
    backend: str = "lfdkit",
) -> JointMotion:
    """Time a joint-space path through waypoints, within joint velocity and acceleration limits.

    See the module notes for the method (cubic spline in joint-space arc
    length, forward–backward velocity profile, 1 % margin and a final check).

    Parameters
    ----------
    q : array_like, shape (n, n_joints)
        Waypoints (rad), at least 2 distinct ones; ``arm.n_joints`` joints
        unless both limits are given.
    arm : Arm
        Gives the limits not passed explicitly (default: the UR5's).
    max_velocity : float or array_like, shape (n_joints,), optional
        Joint speed limits (rad/s), one for all joints or one per joint;
        by default ``arm.max_joint_speed``.
    max_acceleration : float or array_like, shape (n_joints,), optional
        Joint acceleration limits (rad/s²); by default ``arm.max_joint_acceleration``.
    speed_fraction : float
        In ``(0, 1]``; velocity limits are multiplied by it and acceleration
        limits by its square, so the same path takes ``1 / speed_fraction``
        times as long (the thesis played back at 0.2).
    backend : {"lfdkit", "toppra", "ruckig"}
        Who computes the velocity profile (module notes); ``"toppra"`` needs
        ``pip install toppra``. ``"ruckig"`` (``pip install ruckig``) also
        limits the jerk and returns a
        :class:`lfdkit.execute.jerk_limited.JerkLimitedTrajectory` (the same
        ``times``, ``duration``, ``sample``, ``resample``).

    Returns
    -------
    Timing
        Starts and ends at rest; passes waypoint ``k`` at ``times[k]``.

    Raises
    ------
    ValueError
        If ``q`` is not 2-D, has NaN/inf or fewer than 2 distinct waypoints, a
        limit is not positive (or has the wrong length), ``q`` has another
        number of joints than the arm whose limits are used, or
        ``speed_fraction`` is outside ``(0, 1]``.
    TypeError
        If ``arm`` is not an :class:`~lfdkit.execute.arm.Arm`.
    """
    arm = check_arm(arm)
    if backend not in ("lfdkit", "toppra", "ruckig"):
        raise ValueError(f"backend: expected 'lfdkit', 'toppra' or 'ruckig', got {backend!r}")
    if backend == "ruckig":  # jerk-limited: lfdkit's timing, then ruckig through its waypoints
        from lfdkit.execute.jerk_limited import time_parameterize_ruckig

        return time_parameterize_ruckig(  # type: ignore[return-value]
            q,
            arm=arm,
            max_velocity=max_velocity,
            max_acceleration=max_acceleration,
            speed_fraction=speed_fraction,
        )
    arr = check_path(q, "q", min_dims=1)
    n_joints = arr.shape[1]
    f = _check_speed_fraction(speed_fraction)
    vmax = _check_limits(max_velocity, "max_velocity", n_joints, arm, "max_joint_speed") * f
    amax = _check_limits(
        max_acceleration, "max_acceleration", n_joints, arm, "max_joint_acceleration"
    ) * (f * f)

    # Drop repeats: a zero-length step has no direction and would give two knots at one s.
    step = np.linalg.norm(np.diff(arr, axis=0), axis=1)
    keep = np.concatenate(([True], step > DUPLICATE_TOL))
    index = np.flatnonzero(keep)
    way = arr[keep]
    if len(way) < 2:
        raise ValueError(
            f"q: all {len(arr)} waypoints coincide (within {DUPLICATE_TOL:g} rad); nothing to move"
        )
    knots = arc_length(way)
    # Natural end conditions: two waypoints, or collinear ones, give a straight line.
    from scipy.interpolate import CubicSpline  # here: a batch worker that only plans skips it

    spline = CubicSpline(knots, way, bc_type="natural", axis=0)

    s, knot_at = _grid(knots)
    ds = np.diff(s)
    qp, qpp = spline(s, 1), spline(s, 2)
    keep_frac = 1.0 - SAFETY_MARGIN
    if backend == "toppra":
        x = _profile_toppra(knots, way, s, vmax * keep_frac, amax * keep_frac)
    else:
        x = _profile(qp, qpp, ds, vmax * keep_frac, amax * keep_frac)

    sd = np.sqrt(x)
    with np.errstate(divide="ignore"):
        dt = 2.0 * ds / (sd[:-1] + sd[1:])
    if not np.all(np.isfinite(dt)):  # pragma: no cover - x > 0 inside by construction
        raise RuntimeError("time_parameterize: the velocity profile stalled inside the path")
    t = np.concatenate(([0.0], np.cumsum(dt)))
    u = (x[1:] - x[:-1]) / (2.0 * ds)

    # Check against the full limits between grid points; slow down uniformly if needed.
    tau = dt[:, None] * _CHECK_FRACTIONS[None, :]
    ss = np.minimum(s[:-1, None] + sd[:-1, None] * tau + 0.5 * u[:, None] * tau**2, s[1:, None])
    vv = np.maximum(sd[:-1, None] + u[:, None] * tau, 0.0).ravel()
    ss = ss.ravel()
    aa = np.repeat(u, len(_CHECK_FRACTIONS))
    qd = spline(ss, 1) * vv[:, None]
    qdd = spline(ss, 1) * aa[:, None] + spline(ss, 2) * (vv * vv)[:, None]
    v_ratio = float((np.abs(qd) / vmax).max())
    a_ratio = float((np.abs(qdd) / amax).max())
    stretch = max(1.0, v_ratio, np.sqrt(a_ratio))
    if stretch > 1.0:
        # Time × k divides velocities by k and accelerations by k².
        t, sd, u = t * stretch, sd / stretch, u / stretch**2

    return Timing(
        times=t[knot_at],
        waypoints=way,
        waypoint_index=index,
        max_velocity=vmax,
        max_acceleration=amax,
        _spline=spline,
        _s=s,
        _t=t,
        _sd=sd,
        _u=u,
    )
