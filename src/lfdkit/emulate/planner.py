"""Forward planning: the path that maximises the learned reward in a scene (thesis §5.4).

Model
-----
The robot moves along the nominal path at constant speed (thesis §5.4): the
``k``-th planned point lies on the normal of the ``k``-th nominal point,

    x_k = x_k^N + N_kᵀ d_k,

with ``N_k`` (m, q), ``m = q − 1``, the orthonormal normals of the nominal
(the left normal in 2-D), and ``d_k`` the lateral offset. So the nominal
point matched to ``x_k`` is the one whose normal passes through it, as the
thesis defines it, by construction. The linear point model is
``d_{k+1} = d_k + a_k`` with actions in the box ``|a_k| ≤ max_step`` per
component (the thesis's polyhedral action set: bounded sideways steps;
default one nominal step length, a 45° slope at most). The plan maximises
``Σ_k R(x_k)`` (:class:`lfdkit.emulate.Reward`) over ``k = 1 … K−1`` from a
given start offset ``d_0``.

Solver
------
The cost ``Σ_k Q |d_k|² + Σ_o exp(…)`` is separable in ``d``: its Hessian is
block-diagonal (diagonal in 2-D). In the actions it is dense, but a projected
Newton method (Bertsekas) needs it only on the free actions: actions held at
a bound lock neighbouring offsets together, the free ones move whole groups,
and in 2-D the Newton system in the group moves is again diagonal, solved in
O(K). In 3-D the two normal components of a group couple through the 2×2
blocks, and the small dense reduced system is solved by an eigen-decomposition
(which also repairs negative curvature); 3-D plans are therefore slower.
Negative curvature (the flanks of an obstacle's bump) is replaced by its
magnitude to keep each step a descent step of sensible length; an Armijo
search along the
projection arc gives global convergence, and Newton steps near the optimum
converge quadratically.

The obstacle term is not convex: an obstacle can be passed on either side. The
full-horizon plan is solved from several starts (the nominal, every obstacle
passed on one side or the other, all of them on one side) and the best optimum
is kept. The receding-horizon plan (MPC, horizon ``H``) re-solves a window of
``H`` offsets at every step, warm-started from the previous window shifted by
one, and also from both sides when an obstacle is in the window.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from threadpoolctl import threadpool_limits

from lfdkit._validation import check_path, check_positive
from lfdkit.emulate.reward import Reward
from lfdkit.emulate.scene import Scene
from lfdkit.geometry import PolylineSet, normal_frames, point_tangents, resample

__all__ = ["Corridor", "Plan", "plan_path"]

#: Horizons the thesis found to work (§5.4).
MIN_HORIZON, MAX_HORIZON = 4, 12
#: Factor on the nominal weight at the goal when a plan must reach it (``goal_approach``).
GOAL_GAIN = 1e4


@dataclass(frozen=True, eq=False)
class Corridor:
    """A nominal path sampled at constant speed, with the normals a plan moves along.

    Attributes
    ----------
    points : ndarray, shape (K, q)
        Nominal points ``x_k^N``, equally spaced in arc length.
    normals : ndarray, shape (K, q − 1, q)
        Orthonormal normals ``N_k`` of each point (rows).
    tangents : ndarray, shape (K, q)
    step : float
        Arc length between consecutive points.
    """

    points: np.ndarray
    normals: np.ndarray
    tangents: np.ndarray
    step: float

    @classmethod
    def from_path(cls, nominal: Any, n_points: int = 100) -> Corridor:
        """Resample ``nominal`` (n, q), q 2 or 3, to ``n_points`` equally spaced points."""
        path = check_path(nominal, "nominal", min_points=2)
        if path.shape[1] not in (2, 3):
            raise ValueError(f"nominal: expected 2-D or 3-D points, got {path.shape[1]}")
        n_points = check_positive(n_points, "n_points", integer=True)
        if n_points < 3:
            raise ValueError(f"n_points: needs at least 3, got {n_points}")
        points = resample(path, n_points)
        tangents = point_tangents(points)
        frames = normal_frames(tangents)
        step = float(np.linalg.norm(points[1] - points[0]))
        return cls(points, frames[:, 1:, :], tangents, step)

    @property
    def n_points(self) -> int:
        return int(self.points.shape[0])

    @property
    def n_dims(self) -> int:
        return int(self.points.shape[1])

    def to_points(self, offsets: np.ndarray) -> np.ndarray:
        """World points ``x_k^N + N_kᵀ d_k`` for offsets (K, q − 1)."""
        return self.points + np.einsum("km,kmq->kq", offsets, self.normals)

    def offsets_of(self, demo: Any) -> tuple[np.ndarray, np.ndarray]:
        """Lateral offsets where a demonstration crosses each normal.

        Returns
        -------
        offsets : ndarray, shape (K, q − 1)
            ``N_k (p_k − x_k^N)`` with ``p_k`` the nearest crossing of the
            demonstration (travelled in the nominal's direction) with the
            normal hyperplane of point ``k``; 0 where there is none.
        found : ndarray of bool, shape (K,)
        """
        demo = check_path(demo, "demo", n_dims=self.n_dims)
        hits = PolylineSet([demo]).intersect(self.points, self.tangents, same_direction=True)
        found = hits.found[:, 0]
        rel = np.where(found[:, None], hits.points[:, 0] - self.points, 0.0)
        return np.einsum("kmq,kq->km", self.normals, rel), found


@dataclass
class Plan:
    """A planned path.

    Attributes
    ----------
    points : ndarray, shape (K, q)
        The path, first point the start.
    offsets : ndarray, shape (K, q − 1)
        Lateral offsets from the nominal.
    cost : float
        ``−Σ_k R(x_k)`` over ``k = 1 … K−1`` (lower is better).
    horizon : int or None
        MPC horizon, None for the full-horizon optimum.
    n_iter : int
        Newton iterations, summed over starts (and MPC steps).
    converged : bool
    """

    points: np.ndarray
    offsets: np.ndarray
    cost: float
    horizon: int | None
    n_iter: int
    converged: bool
    active: np.ndarray = field(repr=False, default_factory=lambda: np.zeros(0, bool))


# --------------------------------------------------------------------- problem
class _Problem:
    """Offsets ``d_1 … d_n`` after a fixed ``d_0``: the cost's ingredients.

    The exponent of obstacle ``l`` at point ``k`` is a quadratic in the offset,
    ``s = c + 2 bᵀd + dᵀA d`` with ``c = rᵀPr``, ``b = N P r``, ``A = N P Nᵀ``
    and ``r = x_k^N − O_l``: precomputed once, so each evaluation is a few
    element-wise operations.
    """

    def __init__(
        self,
        base: np.ndarray,
        normals: np.ndarray,
        obstacles: np.ndarray,
        precision: np.ndarray,
        weight: float | np.ndarray,
        max_step: float,
    ) -> None:
        self.base, self.normals = base, normals  # (n, q), (n, m, q)
        self.obstacles, self.precision = obstacles, precision  # (L, q), (L, q, q)
        # Nominal weight per offset: Q, or Q ramped up towards the goal.
        self.weight = np.broadcast_to(np.asarray(weight, dtype=np.float64), (base.shape[0],)).copy()
        self.max_step = float(max_step)
        rel = base[:, None, :] - obstacles[None]  # (n, L, q)
        pr = np.einsum("lij,klj->kli", precision, rel)
        self.c = np.einsum("kli,kli->kl", rel, pr)
        self.b = np.einsum("kmq,klq->klm", normals, pr)
        self.a = np.einsum("kmq,lqr,knr->klmn", normals, precision, normals)

    @property
    def n(self) -> int:
        return int(self.base.shape[0])

    @property
    def m(self) -> int:
        return int(self.normals.shape[1])

    @property
    def has_obstacles(self) -> bool:
        return bool(self.obstacles.shape[0])

    def window(self, start: int, stop: int) -> _Problem:
        """The sub-problem of offsets ``start … stop − 1`` (precomputed terms sliced)."""
        sub = object.__new__(_Problem)
        sub.base, sub.normals = self.base[start:stop], self.normals[start:stop]
        sub.obstacles, sub.precision = self.obstacles, self.precision
        sub.weight, sub.max_step = self.weight[start:stop], self.max_step
        sub.c, sub.b, sub.a = self.c[start:stop], self.b[start:stop], self.a[start:stop]
        return sub

    def bumps(self, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Obstacle terms ``e`` (n, L) and ``N P u = b + A d`` (n, L, m) at offsets (n, m)."""
        npu = self.b + np.einsum("klmn,kn->klm", self.a, d)
        exponent = self.c + np.einsum("klm,km->kl", self.b + npu, d)
        return np.exp(-exponent), npu

    def cost(self, d: np.ndarray) -> float:
        value = float(np.sum(self.weight[:, None] * d * d))
        if self.has_obstacles:
            value += float(self.bumps(d)[0].sum())
        return value

    def derivatives(self, d: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        """Cost, gradient (n, m) and Hessian blocks (n, m, m) in the offsets."""
        m = d.shape[1]
        cost = float(np.sum(self.weight[:, None] * d * d))
        gradient = 2.0 * self.weight[:, None] * d
        hessian = 2.0 * self.weight[:, None, None] * np.eye(m)[None]
        if self.has_obstacles:
            bump, npu = self.bumps(d)
            cost += float(bump.sum())
            gradient -= 2.0 * np.einsum("kl,klm->km", bump, npu)
            hessian += np.einsum(
                "kl,klmn->kmn", bump, 4.0 * npu[..., :, None] * npu[..., None, :] - 2.0 * self.a
            )
        return cost, gradient, hessian


def _groups(free: np.ndarray) -> tuple[np.ndarray, int]:
    """Reduced-variable index of each offset component; −1 where anchored to ``d_0``.

    ``free`` (n, m): action ``j`` (from offset ``j−1`` to ``j``) is free. Offsets
    linked by held actions move together; each free action starts a new group.
    """
    n, m = free.shape
    counts = np.cumsum(free, axis=0)  # groups started so far per component
    totals = counts[-1] if n else np.zeros(m, dtype=int)
    starts = np.concatenate([[0], np.cumsum(totals)[:-1]])
    index = np.where(counts > 0, counts - 1 + starts[None, :], -1)
    return index, int(totals.sum())


def _solve(
    problem: _Problem, d0: np.ndarray, init: np.ndarray, *, tol: float = 1e-10, max_iter: int = 100
) -> tuple[np.ndarray, float, int, bool]:
    """Projected Newton on the actions (compiled); returns offsets, cost, iterations, converged."""
    from lfdkit._kernels import offsets_newton  # numba compiles on first use

    d = np.array(init, dtype=np.float64, order="C").reshape(problem.n, problem.m)
    cost, n_iter, ok = offsets_newton(
        problem.c,
        problem.b,
        problem.a,
        problem.weight,
        problem.max_step,
        np.ascontiguousarray(d0, dtype=np.float64),
        d,
        tol,
        max_iter,
    )
    return d, float(cost), int(n_iter), bool(ok)


def _side_starts(problem: _Problem, d0: np.ndarray) -> list[np.ndarray]:
    """Initial offsets passing nearby obstacles on one side or the other.

    Each start holds the offset just beyond the obstacle's response (2.5 of its
    widths across the path) over the stretch where the response acts along the
    path, ramping in and out at the action bound. Starts: the nominal; all
    obstacles passed on one side; each obstacle alone on either side. In 3-D
    an obstacle sitting on the nominal is also passed along the second normal.
    """
    n, m = problem.n, problem.m
    starts = [np.zeros((n, m))]
    if not problem.has_obstacles:
        return starts
    rel = problem.obstacles[:, None, :] - problem.base[None]  # (L, n, q)
    nearest = np.argmin(np.einsum("lkq,lkq->lk", rel, rel), axis=1)
    step = float(np.linalg.norm(problem.base[1] - problem.base[0])) if n > 1 else 1.0
    position = np.arange(n) * step
    shapes: dict[tuple[int, float], list[np.ndarray]] = {}
    for o, k in enumerate(nearest):
        lateral = problem.normals[k] @ rel[o, k]  # the obstacle's offset (m,)
        across = problem.normals[k] @ problem.precision[o] @ problem.normals[k].T
        tangent = problem.base[min(k + 1, n - 1)] - problem.base[max(k - 1, 0)]
        length = float(np.linalg.norm(tangent))
        along = 0.0  # a one-point window has no direction
        if length > 0.0:
            tangent = tangent / length
            along = 2.5 / np.sqrt(tangent @ problem.precision[o] @ tangent)
        norm = float(np.linalg.norm(lateral))
        if m == 1 or norm > 0.0:
            first = lateral / norm if norm > 0.0 else np.eye(m)[0]
        else:
            first = np.eye(m)[0]
        directions = [first]
        if m > 1 and norm < 1.25 / np.sqrt(first @ across @ first):
            directions.append(np.array([-first[1], first[0]]) if m == 2 else np.eye(m)[1])
        for axis, direction in enumerate(directions):
            width = 2.5 / np.sqrt(direction @ across @ direction)
            for sign in (1.0, -1.0):
                target = lateral + sign * direction * width
                ramp = np.linalg.norm(target) * step / problem.max_step
                distance = np.abs(position - position[k])
                reach = np.clip(1.0 - (distance - along) / max(ramp, 1e-300), 0.0, 1.0)
                shape = reach[:, None] * target
                shapes.setdefault((axis, sign), []).append(shape)
                starts.append(shape)
    for group in shapes.values():
        combined = np.zeros((n, m))
        for shape in group:
            combined = np.where(np.abs(shape) > np.abs(combined), shape, combined)
        starts.append(combined)
    return starts


def goal_weights(corridor: Corridor, weight: float, goal_approach: float | None) -> np.ndarray:
    """Nominal weight of offsets 1 … K−1: ``Q``, ramped up over the last ``goal_approach``.

    Over the final stretch of length ``goal_approach`` the weight rises as
    ``Q (1 + GOAL_GAIN · r²(3 − 2r))`` with ``r`` from 0 to 1 (a smooth step),
    which draws the plan back onto the nominal so it ends at the goal.
    """
    n = corridor.n_points - 1
    if goal_approach is None:
        return np.full(n, float(weight))
    approach = check_positive(goal_approach, "goal_approach")
    position = np.arange(1, n + 1) * corridor.step
    r = np.clip((position - (n * corridor.step - approach)) / approach, 0.0, 1.0)
    return weight * (1.0 + GOAL_GAIN * r * r * (3.0 - 2.0 * r))


def _build(
    reward: Reward,
    corridor: Corridor,
    scene: Scene,
    max_slope: float = 1.0,
    goal_approach: float | None = None,
) -> _Problem:
    """The problem of offsets 1 … K−1 after the fixed start, steps up to ``max_slope`` · step."""
    precision = reward.precision_of(scene)
    obstacles = scene.positions if len(scene) else np.zeros((0, corridor.n_dims))
    if len(scene) and obstacles.shape[1] != corridor.n_dims:
        raise ValueError(
            f"scene: {obstacles.shape[1]}-D obstacles for a {corridor.n_dims}-D nominal path"
        )
    return _Problem(
        corridor.points[1:],
        corridor.normals[1:],
        obstacles,
        precision.reshape(-1, corridor.n_dims, corridor.n_dims),
        goal_weights(corridor, reward.nominal_weight, goal_approach),
        max_slope * corridor.step,
    )


def plan_path(
    reward: Reward,
    nominal: Any,
    scene: Scene,
    *,
    horizon: int | None = None,
    n_points: int = 100,
    start_offset: Any = None,
    init: Any = None,
    max_slope: float = 1.0,
    goal_approach: float | None = None,
) -> Plan:
    """The path maximising the reward along a nominal path in a scene.

    Parameters
    ----------
    reward : Reward
    nominal : array_like, shape (n, q) or Corridor
        Nominal path (e.g. a DMP rollout to the new goal), q 2 or 3.
    scene : Scene
        Obstacles; every class must be known to ``reward``.
    horizon : int, optional
        MPC horizon ``H`` with ``4 <= H <= 12``; None for the full-horizon optimum.
    n_points : int
        Points ``K`` of the plan (the nominal is resampled at constant speed).
    start_offset : array_like, shape (q − 1,), optional
        Lateral offset of the start from the nominal's first point (default 0).
    init : array_like, shape (K, q − 1), optional
        Initial offsets (full horizon only); replaces the multi-start.
    max_slope : float
        Largest sideways step per nominal step (the action box).
    goal_approach : float, optional
        Length (path units) before the goal over which the plan returns to the
        nominal, so it ends at the goal (see :func:`goal_weights`). None (the
        default) is the thesis's model, which has no goal term: a plan that
        swerves may end beside the goal.

    Returns
    -------
    Plan

    Raises
    ------
    ValueError
        For a horizon outside 4–12, an unknown obstacle class, a start inside
        an obstacle, or mismatched dimensions.
    """
    # One BLAS thread: the 3-D solver's eigen-solves are many and small, and
    # threaded BLAS makes them many times slower on a busy machine.
    with threadpool_limits(limits=1):
        return _plan(
            reward, nominal, scene, horizon, n_points, start_offset, init, max_slope, goal_approach
        )


def _plan(
    reward: Reward,
    nominal: Any,
    scene: Scene,
    horizon: int | None,
    n_points: int,
    start_offset: Any,
    init: Any,
    max_slope: float,
    goal_approach: float | None,
) -> Plan:
    corridor = nominal if isinstance(nominal, Corridor) else Corridor.from_path(nominal, n_points)
    m = corridor.n_dims - 1
    d0 = np.zeros(m) if start_offset is None else np.asarray(start_offset, float).reshape(m)
    problem = _build(reward, corridor, scene, check_positive(max_slope, "max_slope"), goal_approach)
    start_point = corridor.points[0] + d0 @ corridor.normals[0]
    _check_start(start_point, problem, scene.radii if len(scene) else np.zeros(0))
    if horizon is None:
        starts = (
            [np.asarray(init, float).reshape(problem.n + 1, m)[1:]]
            if init is not None
            else (_side_starts(problem, d0))
        )
        best = None
        total_iter = 0
        for guess in starts:
            d, cost, n_iter, ok = _solve(problem, d0, guess)
            total_iter += n_iter
            if best is None or cost < best[1] - 1e-12 * abs(best[1]):
                best = (d, cost, ok)
        if init is None and problem.has_obstacles:
            # The best plan mirrored through the nominal: the other side of everything.
            d, cost, n_iter, ok = _solve(problem, d0, 2.0 * d0 - best[0])
            total_iter += n_iter
            if cost < best[1] - 1e-12 * abs(best[1]):
                best = (d, cost, ok)
        d, cost, ok = best
        offsets = np.vstack([d0[None], d])
        return Plan(corridor.to_points(offsets), offsets, cost, None, total_iter, ok)
    horizon = check_positive(horizon, "horizon", integer=True)
    if not MIN_HORIZON <= horizon <= MAX_HORIZON:
        raise ValueError(
            f"horizon: expected {MIN_HORIZON} <= H <= {MAX_HORIZON} (thesis §5.4), got {horizon}"
        )
    return _receding_horizon(problem, corridor, d0, horizon)


def _receding_horizon(problem: _Problem, corridor: Corridor, d0: np.ndarray, horizon: int) -> Plan:
    n, m = problem.n, problem.m
    offsets = np.zeros((n + 1, m))
    offsets[0] = d0
    guess = np.zeros((min(horizon, n), m))
    total_iter, all_ok = 0, True
    for k in range(n):
        stop = min(k + horizon, n)
        window = problem.window(k, stop)
        guess = guess[: stop - k]
        if guess.shape[0] < stop - k:
            guess = np.vstack([guess, np.repeat(guess[-1:], stop - k - guess.shape[0], axis=0)])
        d, _, n_iter, ok = _best_window(window, offsets[k], guess)
        total_iter += n_iter
        all_ok &= ok
        offsets[k + 1] = d[0]
        guess = np.vstack([d[1:], d[-1:]]) if d.shape[0] > 1 else d
    cost = problem.cost(offsets[1:])
    return Plan(corridor.to_points(offsets), offsets, cost, horizon, total_iter, all_ok)


def _best_window(
    window: _Problem,
    anchor: np.ndarray,
    guess: np.ndarray,
    extra: tuple[np.ndarray, ...] = (),
    *,
    sides: bool = True,
) -> tuple[np.ndarray, float, int, bool]:
    """Solve one MPC window from the warm start (and both sides when an obstacle is near).

    Returns the lowest-cost optimum found, its cost, the summed iterations and
    whether that optimum converged.
    """
    candidates = [guess, *extra]
    if sides and window.has_obstacles and window.bumps(guess)[0].max() > 1e-6:
        candidates += _side_starts(window, anchor)[1:]
    best, total = None, 0
    for candidate in candidates:
        d, cost, n_iter, ok = _solve(window, anchor, candidate)
        total += n_iter
        if best is None or cost < best[1]:
            best = (d, cost, ok)
    return best[0], best[1], total, best[2]


def _check_start(point: np.ndarray, problem: _Problem, radii: np.ndarray) -> None:
    """Refuse a start inside an obstacle: its physical radius, or one response width if 0."""
    if not problem.has_obstacles:
        return
    rel = point[None] - problem.obstacles
    distance = np.linalg.norm(rel, axis=1)
    depth = np.einsum("li,lij,lj->l", rel, problem.precision, rel)
    inside = np.flatnonzero(np.where(radii > 0, distance < radii, depth < 1.0))
    if inside.size:
        o = int(inside[0])
        what = f"its radius {radii[o]:g}" if radii[o] > 0 else "one width of its response"
        raise ValueError(
            f"start: lies inside obstacle {o} (within {what}); move the start or the obstacle"
        )
