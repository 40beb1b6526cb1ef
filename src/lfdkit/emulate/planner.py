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
given start offset ``d_0``. These coordinates, the cost and its Newton solver
are :mod:`lfdkit.emulate.problem` (:class:`~lfdkit.emulate.problem.Corridor`,
:class:`~lfdkit.emulate.problem.Problem`), shared with the IOC; this module
adds the global search (compiled in :mod:`._planner_kernels`), the receding
horizon and the safety checks.

Solver
------
The cost ``Σ_k Q |d_k|² + Σ_o exp(…)`` is separable in ``d``: its Hessian is
block-diagonal (diagonal in 2-D). In the actions it is dense, but a projected
Newton method (Bertsekas) needs it only on the free actions: actions held at
a bound lock neighbouring offsets together, the free ones move whole groups,
and in 2-D the Newton system in the group moves is again diagonal, solved in
O(K). In 3-D the two normal components of a group couple through the 2×2
blocks, and the reduced system is a forest solved in O(K) (``block_tree_solve``):
with the blocks as they are where it is definite (each pivot above a floor),
else with each block made positive definite first (eigenvalues by their
magnitude; making them so always had slowed 3-D solves to a linear crawl
where a group's point curved down). As in 2-D, negative curvature the
group cannot carry (the flanks of an obstacle's bump) is replaced by its
magnitude to keep each step a descent step of sensible length; an Armijo
search along the projection arc gives global convergence, and Newton steps
near the optimum converge quadratically
(:meth:`Problem.solve <lfdkit.emulate.problem.Problem.solve>`).

The obstacle term is not convex: an obstacle can be passed on either side,
and a concave group of obstacles has a pocket to fall into. So the plan is
first searched globally: a dynamic programme over a lateral grid of offsets
(spacing a fraction of the action bound, every offset reachable from the
previous one) finds the best grid path over every combination of passing
sides in ``O(K G w)`` (``G`` grid values, ``w`` cells per step; ``G²`` in
3-D). The grid has at most 30 cells a side in 3-D (800 in 2-D), each at
least one action bound wide; where that does not cover the scene (a fine
path: at 250 points on a 0.6 m path 30 bounds are 8 cm, less than a box's
reach, and feasible three-box scenes were refused), the full horizon's grid
route is also searched over every ``s``-th point with an ``s`` times wider
bound and interpolated, where the grid's own is blocked or runs along its
edge (:func:`_coarse_stride`; issue 34). Newton then polishes
that path, the same path with each nearby obstacle forced to its other
side (the grid ranks near-ties only to its resolution), and the nominal;
the lowest cost wins.

The receding-horizon plan (MPC, horizon ``H``) polishes, at every step, the
warm start (the previous window shifted by one) and a grid path from the
current offset. A window alone is myopic: before a concave pocket deeper
than the horizon, the best ``H`` points head straight in. So by default
(``lookahead``) the grid path is the whole path's global route from the
current offset, from a backward dynamic programme computed once per plan,
and the candidate executed is the one with least window cost plus the
route's cost-to-go from the window's end. With ``lookahead=False`` it is
the thesis's MPC: the window's own grid optimum, and the least window cost;
its horizon counts steps of a 100-point path (the thesis's), so at ``K``
points the window spans ``⌈H K / 100⌉`` points
(:func:`~lfdkit.emulate.problem.horizon_points`; the IOC's MPC stage the
same): with 8 points at 500 it saw a 0.1 m ball on a 1 m path too late
and ran 14 mm from the 100-point plan (within 2 mm now; among three boxes
in 3-D at 250 points, 6 of 10 folds of ``benchmarks/boxes3d.py`` within
0.25 cm of the 100-point plan and a seventh 2.7 cm, where they were
0.2–14 cm, at about 5× the plan's time; one fold still passes a box on
another side, 22 cm from the 100-point plan: the window's own 3-D grid is
at most 30 action bounds a side). Either way, a candidate from whose end
the rest of the path is blocked is never executed. In 3-D the thesis's
window may swerve beyond the route's grid, whose edge lies inside a box's
reach: judged from there every candidate looked blocked and two of those
ten folds were refused (at 100 points, and one at 250 too). Where that
happens the check is redone once on a route whose grid spans the anchor
and the scene (:func:`_wider_look_ahead`; no warning: the same plan
semantics), and only where every window optimum still leads into a dead
end does the step take the look-ahead's candidate (``lookahead=True``'s
ranking), with a warning naming the points (both folds now plan, 3.4 and
1.3 cm between their 100- and 250-point plans). 2-D plans are unchanged
(the compiled loop). The route's grid has the global search's cell budget: where
it cannot cover the scene and its route is blocked or runs along its edge,
the route is that over every ``s``-th point (:func:`_coarse_look_ahead`),
consulted wherever an obstacle is within ``H s`` points, and at least
within the share of the path ``H`` points are at 100 (``⌈H K / 100⌉`` of
``K``; :func:`_look_ahead_reach`). So the look-ahead spans the same length
of path at 100, 250 or 500 points (issue 34: among three boxes at 250
points in 3-D, horizon 8 refused 2 of 10 scenes and went round the other
side of a third; now all 10 plan within 0.35 cm of the whole path's plan,
as at 100 points, and within 1.1 cm at 500; in 2-D at 500 points, with the
route 8 points ahead, a ball of 0.2 m on a 1 m path was refused, and now is
passed within 2.5 mm of the 100-point plan). Plans of 100 points or fewer
are unchanged by this.

A slow return (``return_fraction`` ``r < 1``, receding horizon only): each
executed step back toward the nominal is at most ``r · max_step`` per
component, a step away still ``max_step``
(:func:`lfdkit.emulate._planner_kernels.return_clamped`, in the compiled
loop and the Python one alike). A late, reactive person swerves at the
bound and comes back slowly; the thesis's model has no action cost, so
below the bound that cannot be expressed (the skill learns ``r``:
:mod:`lfdkit.skill.selection`). The windows still plan with the symmetric
box and each starts where the bounded step ended, so a window may count on
a way back it cannot take: where the next obstacle then blocks every move,
the plan without the bound is made instead, warned (the fidelity
benchmark's late person, seed 2: one of 14 held-out scenes, an S-curve
new task). There the windows' foresight is not what refuses: the route
passes the first obstacle 5.1 cm below the nominal and must pass the next
above it; at 0.21 of the bound the way across takes 27 steps, so the walk
is refused 34 points in whatever the windows plan. Tried and not adopted:
each window's Newton solve with a box per action (toward the nominal at
most ``r · max_step`` on its start's side) moved the plans by round-off
and fell back in the same 4 plans of that run; adding that a step whose
window crosses the nominal is a swerve (the whole bound) passes the
S-curve bounded, but its slow return after the last obstacle scored Pr
−195 % there instead of the fallback's −128 % (pooled 44 → 36 %; medians,
sides and gaps unchanged on seeds 0–3), and the gap in that scene is
threaded by both receding-horizon plans alike (the same sides). What decides
that scene is the side of the second box: the person, still 4.5 cm below the
nominal when it meets it (returning slowly), goes under it; the windows'
route goes over it (the shorter way from the nominal), which only the whole
bound can reach. So where the bounded plan is refused, the whole path's plan
(``horizon=None``, the whole bound) is made instead of the windows' where it
passes some obstacle on the other side and its steps toward the nominal go
less far beyond ``r · max_step``, in all, by more than one such step
(:func:`fast_return`); there it passes that box underneath, as the person
(Pr −129 → 63 %, the gap no longer threaded). Elsewhere the windows' plan, as
before: in the same run two pockets were refused bounded too, where the whole
path's plan (no nearer the slow return) scored 77 and 84 % against the
windows' 91 and 93 %; and an arc of three cups the late person hardly swerves
round (seed 0), where the whole path's plan passes them on the same sides,
returning more slowly but farther out (Pr −1655 → −2395 %): the side is what
a slow return decides, so only a change of side counts.

Safety
------
A plan a robot can execute must reach its goal and keep out of obstacles:

* **Goal.** Reaching the goal leaves the route alone. The route is
  planned without the goal term (the thesis's model, ``goal_approach=None``,
  which may end beside the goal), then joined to the goal
  (:func:`_connect_to_goal`). With ``goal_approach="auto"`` the join is the
  goal-reaching path nearest the route (:func:`_nearest_join`): the route
  itself until the action bound forces the way back. Where that enters a
  hard radius or changes a side, and for a given approach length, the
  nominal weight rises smoothly to
  ``Q (1 + GOAL_GAIN)`` (:func:`~lfdkit.emulate.problem.goal_weights`,
  re-exported here) only over the tail after the last obstacle that shapes
  the route (or the default stretch, where that is later), and the tail
  must pass every obstacle on the route's side. Only where the way back
  does not fit there (the action bound) does the tail start earlier; where
  none does, with ``return_slope`` the join may return more steeply (the
  skill: as steeply as its demonstrations swerved; a late swerver's clutter
  scene on the fidelity benchmark, seed 2, went from 1 of 5 sides and Pr
  −65 % to 5 of 5 and 98 %); only where no tail keeps the route is the
  goal-reaching optimum planned from the start. So the goal never changes
  a passing side it can keep, never moves the plan before the last
  obstacle when the way back fits after it, and never refuses a scene the
  route passes (issue 26: with the goal term in the search, a curved task
  with four obstacles was passed on the other side, or ran into a dead end
  22 points before the goal). On 100 random scenes with curved nominals and
  obstacles near the goal
  (``tests/emulate/test_planner_goal.py``) the sides are the route's in 99
  (the other: an obstacle too far aside, two steps before the goal, for
  any way back on its side), and none is refused.
* **Clearance.** With ``clearance`` given, every obstacle's physical radius
  plus the clearance is a hard constraint on the plan, on top of the learned
  reward: a barrier ``μ t³/(1 − t)`` that is exactly zero outside a thin zone
  around the radius (so the plan is unchanged where the reward alone keeps
  it clear) and infinite at it. The radius is widened by half a segment's
  length (``√(r² + L²/4)``) so that the straight segments between plan points
  stay out too. Every returned plan is checked segment by segment; a plan
  that cannot be made safe within the action bounds raises
  :class:`UnsafePlanError`, never returns.
"""

from __future__ import annotations

import copy
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from typing import Any

import numpy as np

from lfdkit.core.kernels import kernel, use_compiled
from lfdkit.core.memo import DigestMemo, array_digest
from lfdkit.core.options import MAX_HORIZON, MIN_HORIZON  # the horizons the thesis found to work
from lfdkit.core.progress import Progress, ProgressLike, as_progress
from lfdkit.core.threads import map_on_threads, one_blas_thread
from lfdkit.core.validation import check_horizon, check_positive
from lfdkit.emulate.fidelity import passing_sides
from lfdkit.emulate.problem import (
    PLAN_POINTS,
    UNCERTAINTY_MARGIN,
    Corridor,
    Problem,
    check_times,
    goal_weights,
    horizon_points,
    longest_segment,
    predicted_sigma,
)
from lfdkit.emulate.reward import Reward
from lfdkit.model.scene import Obstacle, Scene

#: A round obstacle's distance (shapes override it): :func:`timed_gaps` has its closed form.
_ROUND_DISTANCE = Obstacle.distance

# goal_weights is the problem's (lfdkit.emulate.problem); listed here too, as the
# planner's goal approach that plan_path documents.
__all__ = [
    "GOAL_TOLERANCE",
    "MAX_HORIZON",
    "MIN_HORIZON",
    "Plan",
    "UnsafePlanError",
    "best_window",
    "fast_return",
    "goal_weights",
    "moving_clearance",
    "plan_path",
    "timed_gaps",
]

#: A plan ends at its goal when its last point is this close (fraction of the path's extent).
GOAL_TOLERANCE = 1e-3


class UnsafePlanError(ValueError):
    """No plan within the action bounds keeps out of every obstacle (or reaches the goal)."""


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
    clearance : ndarray, shape (n_obstacles,)
        Distance from the path (its segments) to each obstacle's surface minus
        the tool clearance, in units; never negative for a returned plan.
        Empty for a scene without obstacles.
    goal_error : float
        Distance from the last point to the nominal's last point (the goal).
    """

    points: np.ndarray
    offsets: np.ndarray
    cost: float
    horizon: int | None
    n_iter: int
    converged: bool
    clearance: np.ndarray = field(repr=False, default_factory=lambda: np.zeros(0))
    goal_error: float = float("nan")


def _lateral_levels(
    problem: Problem,
    d0: np.ndarray,
    fine: bool = False,
    widest: Callable[[float], float] | None = None,
) -> tuple[np.ndarray, int]:
    """The grid of the global search: offsets ``h·j``, ``|j| ≤ J``, and cells per step.

    It spans the start and, for every obstacle whose response or radius
    reaches the nominal, its lateral position plus that reach, so that every
    way around it is on the grid; the spacing is a quarter of the action bound
    (half in 3-D) unless the span needs more than the cell budget.
    ``widest``: :func:`_widest` of the span and ``problem``'s
    :func:`_obstacle_reaches`, where known (:meth:`_WindowReaches.widest`).
    """
    step = problem.max_step
    span = _grid_span(problem, d0, widest)
    cells_per_step, budget = _grid_budget(problem.m, fine)
    window = max(1, min(cells_per_step, int(budget * step / span)))
    spacing = step / window
    count = min(int(np.ceil(span / spacing)), budget)
    return spacing * np.arange(-count, count + 1), window


def _grid_span(
    problem: Problem, d0: np.ndarray, widest: Callable[[float], float] | None = None
) -> float:
    """The lateral extent :func:`_lateral_levels`' grid should cover (units)."""
    step = problem.max_step
    farthest = float(np.abs(d0).max())
    span = max(farthest, 2.0 * step)
    if problem.has_obstacles:
        span = _widest(span, *_obstacle_reaches(problem)) if widest is None else widest(span)
    return min(span, farthest + problem.n * step)


def _grid_budget(m: int, fine: bool = False) -> tuple[int, int]:
    """Cells per action bound and most cells a side of :func:`_lateral_levels`' grid."""
    cells_per_step, budget = (4, 400) if m == 1 else (2, 30)
    return (2 * cells_per_step, 2 * budget) if fine else (cells_per_step, budget)


def _coarse_stride(problem: Problem, d0: np.ndarray, fine: bool = False) -> int:
    """Every how many points the grid search must look so that its grid covers the scene.

    The grid has at most a budget of cells a side, each no narrower than
    ``spacing = max_step / cells per step`` and at least one cell per
    step: it covers ``budget · max_step`` at most. A fine path (3-D: 30
    action bounds, 8 cm at 250 points on a 0.6 m path) may need more to go round an
    obstacle; its grid route is then searched over every ``stride``-th point
    (:func:`_subsampled`, whose action bound is ``stride`` times as wide) and
    interpolated (:func:`_interpolated`). 1 where the grid covers the span
    (the plan then the same as without this, bit for bit).
    """
    if not problem.has_obstacles:
        return 1
    budget = _grid_budget(problem.m, fine)[1]
    reach = budget * problem.max_step
    span = _grid_span(problem, d0)
    if span <= reach:
        return 1
    return min(int(np.ceil(span / reach)), max(1, problem.n // 2))


def _subsampled(problem: Problem, stride: int) -> Problem:
    """``problem`` at its points ``stride − 1, 2 stride − 1, …`` (a coarse route's problem).

    The action bound is ``stride`` times as wide (``stride`` steps between
    points) and each hard radius is widened so that the straight line between
    two coarse points keeps the fine problem's own barrier radius: the
    fine points interpolated on it (:func:`_interpolated`) are outside every
    hard radius, a finite-cost start for Newton.
    """
    sub = problem.window(stride - 1, stride * (problem.n // stride), stride)
    sub.max_step = stride * problem.max_step
    # Problem's segment (the longest between fine points), stride times as long.
    segment = longest_segment(problem.step, problem.max_step, problem.m) * stride
    sub.inner2 = problem.inner2 + 0.25 * segment**2
    smallest = np.sqrt(sub.inner2)
    sub.outer2 = (smallest + 0.25 * np.maximum(smallest, stride * problem.step)) ** 2
    return sub


def _interpolated(coarse: np.ndarray, stride: int, n: int, d0: np.ndarray) -> np.ndarray:
    """Offsets (n, m) of a :func:`_subsampled` problem's path (n // stride, m), linear from ``d0``.

    Within the action bound (a coarse step of at most ``stride`` bounds over
    ``stride`` points); after the last coarse point the path holds it.
    """
    at = np.arange(coarse.shape[0] + 1) * stride - 1.0
    points = np.arange(n, dtype=np.float64)
    values = np.vstack([d0[None], coarse])
    return np.stack([np.interp(points, at, values[:, i]) for i in range(coarse.shape[1])], axis=1)


def _obstacle_reaches(problem: Problem) -> tuple[np.ndarray, np.ndarray]:
    """Each obstacle's and hard ball's lateral offset (L, m) at its nearest point, and reach (L,).

    The reach of a response is four of its widths across the nominal there,
    of a hard ball its outer radius (:func:`_lateral_levels`).
    """
    # All anchors at once (a closed loop builds a grid every step: a loop with an
    # eigvalsh per anchor was a tenth of the moving MPC's step); the same numbers
    # as one anchor at a time (batched matmul, eigvalsh of a 1 x 1 is its entry).
    # The responses' centres and the hard balls' in one pass where they stack (each
    # row's numbers are its own: the same as two passes; fewer NumPy calls, which
    # are most of this function's time in an MPC step).
    obstacles = problem.obstacles
    hard = problem.hard_centres[..., problem.hard, :]
    n_obs = obstacles.shape[-2]
    if hard.ndim == obstacles.ndim:
        nearest, laterals = _nearest_lateral_arrays(
            problem, np.concatenate([obstacles, hard], axis=-2)
        )
        nearest, hard_laterals = nearest[:n_obs], laterals[n_obs:]
        laterals = laterals[:n_obs]
    else:
        nearest, laterals = _nearest_lateral_arrays(problem, obstacles)
        hard_laterals = _nearest_lateral_arrays(problem, hard)[1]
    width = _widths(problem.normals[nearest], problem.precision)
    return (
        np.concatenate([laterals, hard_laterals]),
        np.concatenate([4.0 * width, np.sqrt(problem.outer2)]),
    )


def _widths(normals: np.ndarray, precision: np.ndarray) -> np.ndarray:
    """Each response's width across the nominal: normals (L, m, q) there, precision (L, q, q)."""
    across = normals @ precision @ np.swapaxes(normals, 1, 2)  # (L, m, m)
    smallest = across[:, 0, 0] if normals.shape[1] == 1 else np.linalg.eigvalsh(across)[:, 0]
    return 1.0 / np.sqrt(np.maximum(smallest, 1e-300))


class _WindowReaches:
    """:func:`_obstacle_reaches` of every window of a static problem, from one pass.

    The thesis's MPC builds a window's grid at every step near an obstacle;
    the squared distances, lateral offsets and widths of every centre at
    every nominal point are computed once per plan, element by element the
    same numbers as per window (issue 26: the window's grid was two fifths of
    an MPC step). Each window takes the first nearest point among its own.
    In 3-D too (issue 34: 1.1 of the 20 s of CPU of ``benchmarks/boxes_sides.py``'s
    slowest fold, whose model choice replans with the thesis's MPC).
    """

    def __init__(self, problem: Problem) -> None:
        obstacles = problem.obstacles
        centres = np.concatenate([obstacles, problem.hard_centres[problem.hard]], axis=-2)
        n, n_all = problem.n, centres.shape[0]
        self.n_obs = obstacles.shape[0]
        rel = centres[:, None, :] - problem.base[None]  # (L, n, q)
        self.distance2 = np.einsum("lkq,lkq->lk", rel, rel)
        points = np.tile(np.arange(n), n_all)
        normals = problem.normals[points]  # (L n, m, q)
        laterals = (normals @ rel.reshape(n_all * n, -1)[..., None])[..., 0]
        self.laterals = laterals.reshape(n_all, n, problem.m)
        widths = _widths(normals[: self.n_obs * n], np.repeat(problem.precision, n, axis=0))
        self.width4 = 4.0 * widths.reshape(self.n_obs, n)
        self.outer = np.sqrt(problem.outer2)
        self.rows = np.arange(n_all)
        # _widest's numbers, element by element: each centre's distance from the nominal
        # and largest lateral component at each point, and its reach there.
        self.norms = np.sqrt(np.einsum("lkm,lkm->lk", self.laterals, self.laterals))
        self.largest = np.abs(self.laterals).max(axis=2)
        self.reach = np.concatenate([self.width4, np.repeat(self.outer[:, None], n, axis=1)])

    @classmethod
    def usable(cls, problem: Problem) -> bool:
        """Whether ``problem`` is one this covers (static, with obstacles)."""
        return (
            problem.m in (1, 2)
            and not problem.moving
            and problem.has_obstacles
            and problem.hard_centres.ndim == 2
        )

    def widest(self, start: int, stop: int, span: float) -> float:
        """:func:`_widest` of ``span`` and the window's :meth:`at`."""
        nearest = np.argmin(self.distance2[:, start:stop], axis=1) + start
        reach = self.reach[self.rows, nearest]
        inside = self.norms[self.rows, nearest] < reach
        if not inside.any():
            return span
        return max(span, float((self.largest[self.rows, nearest][inside] + reach[inside]).max()))

    def at(self, start: int, stop: int) -> tuple[np.ndarray, np.ndarray]:
        """:func:`_obstacle_reaches` of ``problem.window(start, stop)``."""
        nearest = np.argmin(self.distance2[:, start:stop], axis=1) + start
        laterals = self.laterals[self.rows, nearest]
        width4 = self.width4[self.rows[: self.n_obs], nearest[: self.n_obs]]
        return laterals, np.concatenate([width4, self.outer])


def _widest(span: float, laterals: np.ndarray, reach: np.ndarray) -> float:
    """``span`` grown to ``max|lateral| + reach`` of each centre whose lateral is within reach."""
    inside = np.sqrt(np.einsum("lm,lm->l", laterals, laterals)) < reach
    if not inside.any():
        return span
    return max(span, float((np.abs(laterals[inside]).max(axis=1) + reach[inside]).max()))


def _nearest_lateral_arrays(problem: Problem, centres: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each centre (L, q): its nearest nominal point (L,) and its lateral offset there (L, m).

    Moving obstacles have a centre per point, (n, L, q): the nearest point is
    where the point and that point's centre are closest.
    """
    if centres.ndim == 3:
        rel = np.swapaxes(centres, 0, 1) - problem.base[None]  # (L, n, q)
    else:
        rel = centres[:, None, :] - problem.base[None]  # (L, n, q)
    nearest = np.argmin(np.einsum("lkq,lkq->lk", rel, rel), axis=1)
    closest = rel[np.arange(rel.shape[0]), nearest]  # (L, q)
    return nearest, (problem.normals[nearest] @ closest[..., None])[..., 0]


def _nearest_laterals(problem: Problem, centres: np.ndarray) -> list[tuple[int, np.ndarray]]:
    """:func:`_nearest_lateral_arrays` as a list of ``(k, lateral)`` pairs."""
    nearest, laterals = _nearest_lateral_arrays(problem, centres)
    return list(zip(nearest.tolist(), laterals, strict=True))


def _grid_kernel(name: str) -> Any:
    """The grid search's kernel ``name``: numba's or its NumPy form (:mod:`lfdkit.core.kernels`)."""
    return kernel(name, "lfdkit.emulate._planner_kernels", "lfdkit.emulate._planner_numpy")


#: The grid states' costs without the hard radii (:func:`._planner_kernels.grid_state_costs`),
#: by a digest of the reward's arrays, the levels and the kernel's form (NumPy's exp may
#: differ from numba's in the last bit), at most 64 MB of them (issue 34). A skill's model
#: choice plans each training scene a dozen times with one reward and other floors and
#: side blockers: the hard radii differ, the obstacles' terms (nine tenths of the states'
#: costs in 3-D: 3,721 states × 99 points × a dozen response terms) do not; the stress
#: set's 3-D fit computes 22 distinct ones in 82 plans (2.7 → 0.8 s).
_STATE_COSTS: DigestMemo[np.ndarray] = DigestMemo(max_bytes=64 << 20)


def _node_costs(problem: Problem, levels: np.ndarray) -> np.ndarray:
    """The states' costs (n, G^m) of ``problem`` on ``levels`` (``grid_node_costs``'s).

    On rising finite levels (the lateral grid's) the obstacles' terms come
    from :data:`_STATE_COSTS` and the hard radii's are added, the same numbers.
    """
    arguments = problem.kernel_arguments()
    width = levels.size**problem.m
    if not (np.all(np.isfinite(levels)) and np.all(np.diff(levels) > 0.0)):
        out = np.empty((problem.n, width))
        _grid_kernel("grid_node_costs")(*arguments, levels, out)
        return out
    state_costs = _grid_kernel("grid_state_costs")
    key = array_digest(*arguments[:4], levels, label=f"{state_costs.__module__} {width}")
    found = _STATE_COSTS.get(key)
    if found is None:
        found = np.empty((problem.n, width))
        state_costs(*arguments[:4], levels, found)
        found = _STATE_COSTS.put(key, found)
    out = found.copy()  # the hard radii's terms are added to it
    _grid_kernel("grid_hard_costs")(*arguments[4:], levels, out)
    return out


def _global_start(
    problem: Problem,
    d0: np.ndarray,
    end_on_nominal: bool,
    levels: tuple[np.ndarray, int] | None = None,
    extra: np.ndarray | None = None,
    node: np.ndarray | None = None,
) -> np.ndarray | None:
    """The best path on the lateral grid (:func:`._planner_kernels.lateral_dp`), None if blocked.

    ``extra`` (n, G^m) is added to the grid states' costs (``+inf`` forbids one).
    ``node`` (n, G^m): the states' costs on ``levels`` where known
    (:class:`_WindowNodes`), for lateral_dp's backward programme and walk alone.
    """
    lateral_dp = _grid_kernel("lateral_dp")

    grid, cells = levels if levels is not None else _lateral_levels(problem, d0)
    if problem.m == 1 and not end_on_nominal and extra is None:
        grid = _reachable(grid, cells, problem.max_step, d0, problem.n)
    out = np.zeros((problem.n, problem.m))
    if node is not None:  # lateral_dp's two steps after the states' costs
        table = np.empty_like(node)
        _grid_kernel("grid_backward")(
            node,
            grid.size,
            cells,
            end_on_nominal,
            np.zeros((0, 0)) if extra is None else extra,
            table,
        )
        d0 = np.ascontiguousarray(d0, dtype=np.float64)
        total = _grid_kernel("grid_walk")(table, grid, cells, problem.max_step, d0, out)
        return out if np.isfinite(total) else None
    total = lateral_dp(
        *problem.kernel_arguments(),
        problem.max_step,
        np.ascontiguousarray(d0, dtype=np.float64),
        grid,
        cells,
        end_on_nominal,
        np.zeros((0, 0)) if extra is None else extra,
        out,
    )
    return out if np.isfinite(total) else None


def _reachable(levels: np.ndarray, cells: int, max_step: float, d0: np.ndarray, n: int):
    """The levels a grid path from ``d0`` over ``n`` points can reach (2-D, free end).

    The search's first state is within the action bound of ``d0`` and each
    next one within ``cells`` levels of the last, so a path never leaves the
    levels ``cells · (n − 1)`` beyond those first states; the dynamic
    programme's costs there do not depend on the levels outside. So the search
    over these alone finds the same path and cost, bit for bit (same states,
    same order), on a smaller grid: a window's grid spans ``|d0| + n · max_step``
    on both sides of the nominal, the path only ``n · max_step`` around ``d0``
    (about half the grid where the tool is far aside, as in a moving-obstacle
    swerve). ``levels`` itself where no level is within reach of ``d0``.
    """
    first = np.flatnonzero(np.abs(levels - d0[0]) <= max_step * (1.0 + 1e-12))  # grid_walk's
    if first.size == 0:
        return levels
    spread = cells * (n - 1)
    return levels[max(0, int(first[0]) - spread) : int(first[-1]) + spread + 1]


class _WindowNodes:
    """A 3-D receding horizon's grid states' costs per point, while its windows' levels stay.

    A window's rows are the whole problem's (:meth:`Problem.window`) and
    each point's states' costs depend on its own row and the levels alone
    (:func:`._planner_kernels.grid_node_costs`), so the next window on the
    same levels computes only the points it has new: about half the windows
    of the stress set's side-blocked plans, each of ``H`` points (issue 34).

    A window's levels that are levels of the whole path's grid (``whole``:
    its levels and states' costs; the same spacing, or twice it, within its
    span) take their costs from there, the same numbers: 3,539 of 4,490
    windows of ``benchmarks/boxes_sides.py``'s slowest fold (seed 0, fold 6),
    whose states' costs had been a sixth of its fit.
    """

    def __init__(self, problem: Problem, whole: tuple[np.ndarray, np.ndarray] | None = None):
        self.problem = problem
        self.levels: bytes | None = None
        self.first = self.stop = 0
        self.node = np.empty((0, 0))
        self.whole = whole

    def costs(self, start: int, stop: int, levels: np.ndarray) -> np.ndarray:
        """The states' costs (stop − start, G²) of points ``start … stop − 1`` on ``levels``."""
        if self.whole is not None:
            shared = _shared_states(*self.whole, start, stop, levels)
            if shared is not None:
                return shared
        key = levels.tobytes()
        if key != self.levels or not self.first <= start <= self.stop:
            self.levels, self.first, self.stop = key, start, start
            self.node = np.empty((0, levels.size**2))
        if stop > self.stop:
            new = _node_costs(self.problem.window(self.stop, stop), levels)
            self.node = np.concatenate([self.node[start - self.first :], new])
            self.first, self.stop = start, stop
        return np.ascontiguousarray(self.node[start - self.first : stop - self.first])


def _shared_states(
    whole_levels: np.ndarray, whole_node: np.ndarray, start: int, stop: int, levels: np.ndarray
) -> np.ndarray | None:
    """Points ``start … stop − 1``'s states' costs on 3-D ``levels`` from a wider grid's, or None.

    ``whole_node`` (n, G²): the states' costs on ``whole_levels``. ``levels``
    must be every level, or every other one, of ``whole_levels`` round zero
    (exactly equal: ``s·2j`` and ``2s·j`` round alike, as ``s·2`` is exact);
    a state's cost depends on its point and levels alone, so the slice holds
    the same numbers as :func:`_node_costs` on ``levels``.
    """
    centre, half = (whole_levels.size - 1) // 2, (levels.size - 1) // 2
    if half < 1 or levels.size != 2 * half + 1 or whole_levels.size != 2 * centre + 1:
        return None
    stride = 1 if levels[half + 1] == whole_levels[centre + 1] else 2
    first, last = centre - stride * half, centre + stride * half + 1
    if first < 0 or not np.array_equal(whole_levels[first:last:stride], levels):
        return None
    size = whole_levels.size
    states = whole_node.reshape(-1, size, size)[start:stop, first:last:stride, first:last:stride]
    return np.ascontiguousarray(states).reshape(stop - start, levels.size**2)


class _GridSearch:
    """The states' costs on one lateral grid, computed once, for several searches.

    In 2-D the grid is twice as fine as :func:`_lateral_levels`' and the
    coarse grid is every other level of it (sharing the costs); in 3-D there
    is only the coarse grid.
    """

    def __init__(self, problem: Problem, d0: np.ndarray) -> None:
        self.problem, self.d0, self.m = problem, d0, problem.m
        levels, window = _lateral_levels(problem, d0, fine=problem.m == 1)
        node = _node_costs(problem, levels)
        self.grids = {"fine": (levels, window, node)}
        if problem.m == 1 and window >= 2:
            half = levels.size // 2  # the zero level's index
            pick = np.arange(half % 2, levels.size, 2)
            # C order (a column pick is Fortran's): the kernels' one compiled version
            self.grids["coarse"] = (levels[pick], window // 2, np.ascontiguousarray(node[:, pick]))
        else:
            self.grids["coarse"] = self.grids["fine"]

    def best(
        self, end_on_nominal: bool, grid: str = "coarse", extra: np.ndarray | None = None
    ) -> np.ndarray | None:
        """The best path on a grid (None if every grid path is blocked)."""
        grid_backward, grid_walk = _grid_kernel("grid_backward"), _grid_kernel("grid_walk")

        levels, window, node = self.grids[grid]
        table = np.empty_like(node)
        grid_backward(
            node,
            levels.size,
            window,
            end_on_nominal,
            np.zeros((0, 0)) if extra is None else extra,
            table,
        )
        out = np.zeros((self.problem.n, self.m))
        total = grid_walk(table, levels, window, self.problem.max_step, self.d0, out)
        return out if np.isfinite(total) else None

    def flipped(self, end_on_nominal: bool, best: np.ndarray) -> list[np.ndarray]:
        """The best coarse path with one near obstacle passed on its other side, each.

        The grid ranks passing sides only to its resolution: where two ways
        round differ by less, the continuous optimum may lie on the other side
        of an obstacle. Each flipped path is forbidden, at the obstacle's
        nearest point, the side the best grid path takes there.
        """
        problem, m = self.problem, self.m
        levels = self.grids["coarse"][0]
        states = (
            levels[:, None]
            if m == 1
            else np.stack(np.meshgrid(levels, levels, indexing="ij"), axis=-1).reshape(-1, 2)
        )
        near = problem.obstacles[..., problem.bumps(best)[0].max(axis=0) > 1e-9, :]
        hard = problem.hard_centres[..., problem.hard, :]
        # A round obstacle's ball and anchor coincide: flip round it once.
        same = (hard[..., :, None, :] == near[..., None, :, :]).all(axis=-1)
        if same.ndim == 3:  # moving: a centre per point, the same at every point
            same = same.all(axis=0)
        hard = hard[..., ~same.any(axis=1), :]
        centres = np.concatenate([near, hard], axis=-2)
        starts = []
        for k, lateral in _nearest_laterals(problem, centres):
            side = best[k] - lateral
            if not np.any(side):
                side = np.ones(m)
            extra = np.zeros((problem.n, states.shape[0]))
            extra[k, (states - lateral) @ side >= 0.0] = np.inf
            flipped = self.best(end_on_nominal, "coarse", extra)
            if flipped is not None:
                starts.append(flipped)
        return starts


def plan_path(
    reward: Reward,
    nominal: Any,
    scene: Scene,
    *,
    horizon: int | None = None,
    n_points: int | None = None,
    start_offset: Any = None,
    init: Any = None,
    max_slope: float = 1.0,
    goal_approach: float | str | None = "auto",
    clearance: float | Any = 0.0,
    lookahead: bool = True,
    progress: ProgressLike = None,
    times: Any = None,
    margin: float = UNCERTAINTY_MARGIN,
    return_slope: float | None = None,
    return_fraction: float = 1.0,
) -> Plan:
    """The path maximising the reward along a nominal path in a scene, safely.

    Parameters
    ----------
    reward : Reward
    nominal : array_like, shape (n, q) or Corridor
        Nominal path (e.g. a DMP rollout to the new goal), q 2 or 3; its last
        point is the goal.
    scene : Scene
        Obstacles; every class must be known to ``reward``.
    horizon : int, optional
        MPC horizon ``H`` with ``4 <= H <= 12``, in steps of a 100-point path
        (without ``lookahead`` the window spans ``⌈H K / 100⌉`` of ``K > 100``
        points); None for the full-horizon optimum.
    n_points : int, optional
        Points ``K`` of the plan (the nominal is resampled at constant speed),
        3 to :data:`lfdkit.emulate.problem.MAX_POINTS`; ignored for a
        Corridor (its own points). Default
        :data:`~lfdkit.emulate.problem.PLAN_POINTS` (100) whatever the
        nominal's count, so that a plan does not depend on how finely its
        nominal was sampled; a nominal of more than twice as many points is
        then planned far more coarsely than it was sampled, with a warning:
        pass ``n_points=len(nominal)`` to plan at its own points.
    start_offset : array_like, shape (q − 1,), optional
        Lateral offset of the start from the nominal's first point (default 0).
    init : array_like, shape (K, q − 1), optional
        Initial offsets (full horizon only); replaces the global search.
    max_slope : float
        Largest sideways step per nominal step (the action box).
    goal_approach : float, "auto" or None
        Length (path units) before the goal over which the plan returns to the
        nominal so it ends at the goal (see :func:`goal_weights`); "auto" (the
        default): the route's nearest goal-reaching path (it returns as late
        as the action bound allows), else a ramp over
        :data:`~lfdkit.emulate.problem.GOAL_APPROACH_FRACTION` of the
        nominal's length.
        None is the thesis's model, which has no goal term: a plan that swerves
        may end beside the goal.
    clearance : float or array_like, shape (n_obstacles,)
        Clearance (units) added to every obstacle's radius, or to each
        obstacle's (e.g. the tool's margin plus the clearance the
        demonstrations kept from its class); radius plus clearance is a hard
        constraint (obstacles where both are 0 have none).
    lookahead : bool
        MPC only. True (default): each step executes the candidate (window
        optima, and the grid's global path) of least window cost plus the
        grid's cost-to-go for the rest of the path, so the plan does not walk
        into a concave pocket deeper than the horizon. False: the thesis's
        receding horizon, each window's globally best optimum (what the IOC's
        MPC stage fits); both skip candidates that lead into a dead end. In
        3-D, where every window optimum does, the thesis's takes the
        look-ahead's step there instead of refusing, with a warning.
    progress : Progress, callable, bool or None
        Reports the global search and the MPC steps over the plan's points (or
        the polished starts of the full horizon); default silent
        (:func:`lfdkit.core.progress.as_progress`).
    times : array_like, shape (K,), optional
        Seconds from the start at which the tool reaches each of the plan's
        ``K`` points (e.g. the skill's speed profile along the nominal);
        required when ``scene`` has moving obstacles, whose reward terms and
        hard radii at point ``k`` are then at their predicted positions at
        ``times[k]`` (an open-loop plan: the prediction made now; the closed
        loop is :class:`lfdkit.emulate.moving.MovingObstaclePlanner`).
        Ignored for a static scene.
    margin : float
        Moving obstacles: the hard radius grows by ``margin`` standard
        deviations of the prediction (:data:`~lfdkit.emulate.problem.UNCERTAINTY_MARGIN`).
    return_slope : float, optional
        With a goal approach: the largest sideways slope of the way back to
        the goal where no way back within ``max_slope`` keeps the route's
        passing sides (default ``max_slope``: none steeper). Only the join
        after the route (its last points) may be steeper; the route keeps
        ``max_slope``. The skill passes the slope its demonstrations swerved
        at (``ioc_info_["demonstrated_slope"]``), where steeper.
    return_fraction : float
        Receding horizon only: each executed step back toward the nominal is
        at most ``return_fraction · max_step`` per component; steps away keep
        ``max_step`` (default 1: symmetric, the thesis's). A person who swerves
        late and steeply and returns slowly (the skill learns it:
        ``ioc_info_["return_fraction"]``). The windows plan with the symmetric
        bound and each starts where the bounded step ended; the way back to
        the goal after the route keeps ``max_step``. Where no plan with it
        keeps out of the obstacles, the plan without it, warned: the receding
        horizon's, or the whole path's (``horizon=None``) where that passes
        an obstacle on the other side and comes back more slowly
        (:func:`fast_return`; static scenes).

    Returns
    -------
    Plan
        Its ``clearance`` is never negative, and with a goal approach it ends
        within :data:`GOAL_TOLERANCE` of the path's extent from the goal.

    Raises
    ------
    UnsafePlanError
        When no plan within the action bounds keeps out of the obstacles (or,
        with a goal approach, reaches the goal).
    ValueError
        For a horizon outside 4–12, an unknown obstacle class, a start (or,
        with a goal approach, a goal) inside an obstacle, non-finite or
        mismatched arguments.
    """
    # One BLAS thread: the 3-D solver's eigen-solves are many and small, and
    # threaded BLAS makes them many times slower on a busy machine.
    tracker = as_progress(progress)
    return_fraction = check_positive(return_fraction, "return_fraction")
    if return_fraction > 1.0:
        raise ValueError(
            f"return_fraction: expected a fraction of max_step in (0, 1], got {return_fraction:g}"
        )
    if return_fraction < 1.0 and horizon is None:
        raise ValueError(
            "return_fraction: bounds the receding horizon's return only; give a horizon, "
            "or return_fraction=1 for the full horizon"
        )

    def plan(steps: int | None = horizon, fraction: float = 1.0) -> Plan:
        """The plan over ``steps`` points ahead (None: the whole path) with ``fraction``."""
        return _plan(
            reward,
            nominal,
            scene,
            steps,
            n_points,
            start_offset,
            init,
            max_slope,
            goal_approach,
            clearance,
            lookahead,
            tracker,
            times,
            margin,
            return_slope,
            fraction,
        )

    with one_blas_thread():
        if return_fraction == 1.0:
            return plan()
        try:
            return plan(horizon, return_fraction)
        except UnsafePlanError:
            warnings.warn(
                f"plan: no plan that returns to the nominal at most {return_fraction:.2g} "
                "times the action bound per step (the demonstrations' return) keeps out of the "
                "obstacles; planned with the whole bound",
                UserWarning,
                stacklevel=2,
            )
            windows = plan()
            if times is not None:  # moving obstacles: the receding horizon's, as before
                return windows
            try:
                whole = plan(None)
            except UnsafePlanError:
                return windows
            corridor = (
                nominal
                if isinstance(nominal, Corridor)
                else Corridor.from_path(nominal, len(windows.points))
            )
            back = return_fraction * max_slope * corridor.step
            # The whole path's plan only where it passes an obstacle on the other side
            # (what a slow return decides) and keeps the slow return by a clear step more.
            sides = [np.sign(passing_sides(p.points, corridor, scene)) for p in (windows, whole)]
            slower = fast_return(whole.offsets, back) < fast_return(windows.offsets, back) - back
            if slower and np.any(sides[0] * sides[1] < 0.0):
                return whole
            return windows


def fast_return(offsets: np.ndarray, back: float) -> float:
    """How far a path's steps toward the nominal go beyond ``back`` each, in all (units).

    Parameters
    ----------
    offsets : ndarray, shape (K, m)
        Lateral offsets from the nominal (:attr:`Plan.offsets`).
    back : float
        The largest step toward the nominal the person takes (units).

    Returns
    -------
    float
        Per step and component, the part of the step that brings the offset
        nearer 0 (up to crossing it) beyond ``back``, summed.
    """
    d = np.asarray(offsets, dtype=np.float64)
    before, after = d[:-1], d[1:]
    toward = np.where(
        before > 0.0,
        before - np.maximum(after, 0.0),
        np.where(before < 0.0, np.minimum(after, 0.0) - before, 0.0),
    )
    return float(np.sum(np.clip(toward - back, 0.0, None)))


def _plan(
    reward: Reward,
    nominal: Any,
    scene: Scene,
    horizon: int | None,
    n_points: int | None,
    start_offset: Any,
    init: Any,
    max_slope: float,
    goal_approach: float | str | None,
    clearance: float,
    lookahead: bool,
    progress: Progress,
    times: Any = None,
    margin: float = UNCERTAINTY_MARGIN,
    return_slope: float | None = None,
    return_fraction: float = 1.0,
) -> Plan:
    if not isinstance(scene, Scene):
        raise TypeError(f"scene: expected an lfdkit.emulate.Scene, got {type(scene).__name__}")
    if isinstance(nominal, Corridor):
        corridor = nominal
    else:
        if n_points is None:
            n_points = _default_points(nominal)
        corridor = Corridor.from_path(nominal, n_points)
    m = corridor.n_dims - 1
    d0 = _vector(start_offset, "start_offset", m)
    clearance = clearance_per_obstacle(clearance, scene)
    if horizon is not None:
        horizon = check_horizon(horizon)
    reach_goal = goal_approach is not None
    times = check_times(times, corridor.n_points) if scene.moving else None
    max_slope = check_positive(max_slope, "max_slope")
    if return_slope is not None:
        return_slope = check_positive(return_slope, "return_slope")
    goal_w = goal_weights(corridor, reward.nominal_weight, goal_approach)  # checks it
    # The route is planned without the goal term (the thesis's model); the goal
    # is then joined within the route (_connect_to_goal).
    problem = Problem.from_scene(reward, corridor, scene, max_slope, None, clearance, times, margin)
    if times is None:
        _check_ends(corridor, d0, problem, scene, clearance, reach_goal)
    else:  # each end against the obstacles where they are when the tool is there
        for end, at in (("start", times[0]), ("goal", times[-1])):
            static = scene.at(at)
            end_problem = Problem.from_scene(reward, corridor, static, max_slope, None, clearance)
            _check_ends(corridor, d0, end_problem, static, clearance, reach_goal, (end,))
    if init is not None and horizon is None:
        init = np.asarray(init, dtype=np.float64)
        if init.size != (problem.n + 1) * m or not np.all(np.isfinite(init)):
            raise ValueError(f"init: expected {problem.n + 1}x{m} finite offsets")
        init = init.reshape(problem.n + 1, m)[1:]
    else:
        init = None  # the receding horizon has no initial plan
    # The receding horizon's largest step back toward the nominal (none: symmetric).
    back = problem.max_step * return_fraction if return_fraction < 1.0 else np.inf
    route = partial(_route, init=init, lookahead=lookahead, progress=progress, back=back)
    try:
        d, n_iter, ok = route(problem, d0, horizon, False)
    except UnsafePlanError:
        if not reach_goal:
            raise
        # The receding horizon can corner itself where the goal's pull keeps it
        # clear: then the goal-reaching plan (which raises if it finds none).
        d = None
    if reach_goal and d is None:
        problem.weight = goal_w.copy()
        d, n_iter, ok = route(problem, d0, horizon, True)
    elif reach_goal:
        join = partial(
            _connect_to_goal,
            d0=d0,
            route=d,
            goal_w=goal_w,
            tolerance=GOAL_TOLERANCE * corridor.extent,
            nearest=isinstance(goal_approach, str),  # "auto"; a length asks for its ramp
        )
        joined = join(problem)
        if joined is None and return_slope is not None and return_slope > max_slope:
            # The way back does not fit the action bound on the route's sides (a late
            # swerver passes a box 17 points before the goal, 14 cm aside): a steeper
            # return, as the person's, rather than another way round every obstacle.
            steeper = copy.copy(problem)
            steeper.max_step = problem.max_step * return_slope / max_slope
            joined = join(steeper)
        if joined is not None:
            d, more, joined_ok = joined
            n_iter, ok = n_iter + more, ok and joined_ok
        else:
            # No goal-reaching plan keeps the route (e.g. a hard radius beside the
            # goal blocks the way back): the best plan that reaches the goal.
            problem.weight = goal_w.copy()
            d, more, ok = route(problem, d0, horizon, True)
            n_iter += more
    problem.weight = goal_w  # the plan's cost includes the goal term, if any
    offsets = np.vstack([d0[None], d])
    plan = Plan(corridor.to_points(offsets), offsets, problem.cost(d), horizon, n_iter, ok)
    return verified_plan(plan, corridor, scene, clearance, reach_goal, times, margin)


def _default_points(nominal: Any) -> int:
    """:data:`PLAN_POINTS`, warned where the nominal has more than twice as many.

    A nominal planned at far fewer points than it has is otherwise silent: a
    250-point nominal gave a 100-point plan, and a comparison meant at 250
    points was made at 100. Up to twice as many (a smooth curve passed
    densely) is resampled unsaid.
    """
    try:
        count = np.shape(nominal)[0]
    except (ValueError, IndexError):  # ragged or scalar: Corridor.from_path says what is wrong
        return PLAN_POINTS
    if count > 2 * PLAN_POINTS:
        warnings.warn(
            f"nominal: its {count} points are resampled to a plan of {PLAN_POINTS} "
            f"(n_points' default); pass n_points={count} to plan at its own points, or "
            f"n_points={PLAN_POINTS} to keep this",
            UserWarning,
            stacklevel=4,  # plan_path's caller
        )
    return PLAN_POINTS


def _route(
    problem: Problem,
    d0: np.ndarray,
    horizon: int | None,
    reach_goal: bool,
    init: np.ndarray | None,
    lookahead: bool,
    progress: Progress,
    back: float = np.inf,
) -> tuple[np.ndarray, int, bool]:
    """The plan of ``problem`` (its weights as they are): full horizon or receding horizon.

    ``back``: the receding horizon's largest executed step toward the nominal (units).
    """
    if horizon is not None:
        if not lookahead:  # the thesis's window spans its share of the path (horizon_points)
            horizon = horizon_points(horizon, problem.n + 1)
        return _receding_horizon(problem, d0, horizon, reach_goal, lookahead, progress, back)
    if init is not None:
        starts = [init]
    else:
        with progress.stage(f"plan: global search over {problem.n + 1} points"):
            starts = _full_starts(problem, d0, reach_goal)
    label = f"plan: full horizon, polishing {len(starts)} starts"
    with progress.stage(label, total=len(starts)) as stage:
        return _best_of(problem, d0, starts, stage.advance)


def _side_anchors(problem: Problem, d: np.ndarray) -> list[tuple[int, np.ndarray]]:
    """Where plan ``d`` passes each obstacle that shapes it: nearest point and lateral offset.

    The obstacles whose term is above 1e-9 somewhere on ``d``, and the balls
    with a hard radius (a round obstacle's ball and anchor coincide: once).
    """
    near = problem.obstacles[..., problem.bumps(d)[0].max(axis=0) > 1e-9, :]
    hard = problem.hard_centres[..., problem.hard, :]
    same = (hard[..., :, None, :] == near[..., None, :, :]).all(axis=-1)
    if same.ndim == 3:  # moving: a centre per point, the same at every point
        same = same.all(axis=0)
    hard = hard[..., ~same.any(axis=1), :]
    return _nearest_laterals(problem, np.concatenate([near, hard], axis=-2))


def _sides(d: np.ndarray, anchors: list[tuple[int, np.ndarray]], start: int = 0) -> list:
    """The side ``d[k − start] − lateral`` of each anchor at or after ``start``."""
    return [d[k - start] - lateral for k, lateral in anchors if k >= start]


def _connect_to_goal(
    problem: Problem,
    d0: np.ndarray,
    route: np.ndarray,
    goal_w: np.ndarray,
    tolerance: float,
    nearest: bool = False,
) -> tuple[np.ndarray, int, bool] | None:
    """Join the route (planned without goal term) to the goal without changing its way round.

    With ``nearest`` (``goal_approach="auto"``) the join is first the
    goal-reaching path nearest the route (:func:`_nearest_join`): the route
    itself up to where the action bound forces the way back.

    The goal term is a terminal ramp of the nominal weight (``goal_w``) that
    acts only on the tail of the plan after ``s``: first after the last
    obstacle that shapes the route (so nothing before it moves), then, where
    the way back does not fit there (the action bound), from the start of the
    ramp, then over the whole path. Within the tail the plan must pass every
    obstacle on the route's side: the tail is polished from the route itself
    and from the best grid path that ends on the nominal with the other side
    of each obstacle forbidden, and a result on another side is rejected
    (where every polished tail is, the grid path itself is taken). An
    obstacle that no way back to the goal can pass on the route's side (too
    far aside for the steps left, or beyond the goal) is passed as the goal
    allows. Returns offsets, Newton iterations and convergence; None when no
    tail keeps the route (the caller then plans for the goal from the start).
    """
    n = problem.n
    if float(np.linalg.norm(route[-1])) <= 1e-6 * tolerance:  # 1e-9 of the extent
        return route, 0, True
    weight = problem.weight  # Q everywhere (the route's problem)
    ramp = int(np.count_nonzero(goal_w > weight * (1.0 + 1e-12)))
    anchors = _side_anchors(problem, route)
    last = max((k for k, _ in anchors if k < n - 1), default=-1)
    wanted = _sides(route, anchors)
    if nearest:
        joined = _nearest_join(problem, route, anchors, wanted)
        if joined is not None:
            return joined, 0, True
    tried, fallback = set(), None
    for s in (max(n - ramp, last + 1), n - ramp, 0):
        s = max(s, 0)
        if s >= n or s in tried:
            continue
        tried.add(s)
        anchor = d0 if s == 0 else route[s - 1]
        if float(np.abs(anchor).max()) > (n - s) * problem.max_step * (1.0 + 1e-9):
            continue  # the way back is longer than the tail
        tail = problem.window(s, n)
        length = min(n - s, ramp)
        tail.weight = weight[s:].copy()
        tail.weight[n - s - length :] = (
            goal_w[n - length :]
            if length == ramp
            else _ramp(weight[n - length :], goal_w[-1] / weight[-1] - 1.0)
        )
        # An obstacle passed where no way back to the goal fits (nearest to the goal
        # itself, or too far aside for the steps left) is passed as the goal allows.
        sides = [
            (k - s, lat, side)
            for (k, lat), side in zip(anchors, wanted, strict=True)
            if s <= k < n - 1
            and (n - 1 - k) * problem.max_step * float(np.abs(side).sum()) > float(lat @ side)
        ]
        starts = [route[s:]]
        grid = _grid_on_sides(tail, anchor, sides)
        if grid is not None:
            starts.append(grid)
        best, total = None, 0
        # In 3-D each polish is a whole tail's Newton solve (tens of ms): side by side.
        polished = (
            map_on_threads(partial(tail.solve, anchor), starts)
            if problem.m == 2
            else [tail.solve(anchor, guess) for guess in starts]
        )
        for d, cost, n_iter, ok in polished:
            total += n_iter
            if not np.isfinite(cost) or float(np.linalg.norm(d[-1])) > tolerance:
                continue
            if any(float((d[k] - lat) @ side) <= 0.0 for k, lat, side in sides):
                continue  # another way round an obstacle
            if best is None or cost < best[1]:
                best = (d, cost, ok)
        if best is not None:
            return np.vstack([route[:s], best[0]]), total, best[2]
        if grid is not None and fallback is None and np.isfinite(tail.total_cost(grid)):
            # Polishing crossed an obstacle (the ramp outweighs a soft response):
            # the grid path itself keeps the route (not an optimum, so not converged).
            fallback = (np.vstack([route[:s], grid]), total, False)
    return fallback


def _nearest_join(
    problem: Problem,
    route: np.ndarray,
    anchors: list[tuple[int, np.ndarray]],
    wanted: list,
) -> np.ndarray | None:
    """The goal-reaching offsets nearest the route (least squares), or None where unsafe.

    Reaching the goal at point ``K − 1`` within the action bound needs
    ``|d_k| ≤ (K − 1 − k) s`` per component; clipping the route to that
    envelope is the projection onto it, and it stays within the action bound
    (the clip of an ``s``-Lipschitz sequence by an ``s``-Lipschitz envelope).
    So the plan is the route until the way back must start, then returns at
    the action bound: where the person's route ends beside the goal (an
    obstacle near it), the plan leaves it as late as the steps allow (on the
    fidelity benchmark the thesis person's obstacles near the goal went from
    a median Pr of 69 % with a 10 % ramp to 74-79 %, against 76 % for that
    person's own path clipped so). None when the clipped tail
    enters a hard radius or passes an obstacle on another side than the route.
    """
    n = problem.n
    envelope = (n - 1 - np.arange(n))[:, None] * problem.max_step
    d = np.clip(route, -envelope, envelope)
    if not np.isfinite(problem.total_cost(d)):
        return None
    for (k, lateral), side in zip(anchors, wanted, strict=True):
        if k < n - 1 and float((d[k] - lateral) @ side) <= 0.0:
            return None  # another way round an obstacle
    return d


def _ramp(weight: np.ndarray, gain: float) -> np.ndarray:
    """The goal ramp of :func:`goal_weights` over these offsets: ``Q (1 + gain r²(3 − 2r))``."""
    r = np.arange(1, weight.size + 1) / weight.size
    return weight * (1.0 + gain * r * r * (3.0 - 2.0 * r))


def _grid_on_sides(
    problem: Problem, anchor: np.ndarray, sides: list[tuple[int, np.ndarray, np.ndarray]]
) -> np.ndarray | None:
    """The best grid path ending on the nominal, passing each ``(k, lateral, side)`` on ``side``.

    Where every such path on the grid is blocked and the grid cannot cover the
    scene (:func:`_coarse_stride`), the path over every stride-th point (each
    side kept at the coarse point nearest its own), interpolated.
    """
    levels, cells = _lateral_levels(problem, anchor)
    states = (
        levels[:, None]
        if problem.m == 1
        else np.stack(np.meshgrid(levels, levels, indexing="ij"), axis=-1).reshape(-1, 2)
    )
    extra = np.zeros((problem.n, states.shape[0]))
    for k, lateral, side in sides:
        extra[k, (states - lateral) @ side <= 0.0] = np.inf
    # The states' costs through the memo (_node_costs): a scene's plans search it with
    # other sides and floors, its obstacles' terms the same (lateral_dp's own numbers).
    node = _node_costs(problem, levels)
    found = _global_start(problem, anchor, True, (levels, cells), extra, node=node)
    stride = 1 if found is not None else _coarse_stride(problem, anchor)
    if stride > 1:
        coarse = _subsampled(problem, stride)
        last = coarse.n - 1
        moved = [(min(max((k + 1) // stride - 1, 0), last), lat, side) for k, lat, side in sides]
        wide = _grid_on_sides(coarse, anchor, moved)
        found = None if wide is None else _interpolated(wide, stride, problem.n, anchor)
    return found


def _vector(value: Any, name: str, size: int) -> np.ndarray:
    if value is None:
        return np.zeros(size)
    out = np.asarray(value, dtype=np.float64).reshape(-1)
    if out.size != size:
        raise ValueError(f"{name}: expected {size} value(s), got {out.size}")
    if not np.all(np.isfinite(out)):
        raise ValueError(f"{name}: must be finite, got {value!r}")
    return out


def _full_starts(problem: Problem, d0: np.ndarray, reach_goal: bool) -> list[np.ndarray]:
    """The global grid path, in 2-D its one-obstacle flips and a finer grid's, the nominal.

    Where the grid cannot cover the scene (:func:`_coarse_stride`) and its best
    path is blocked or runs along the grid's edge (the cover binds), the
    same over every stride-th point (:func:`_subsampled`), interpolated, too.
    """
    nominal = np.zeros((problem.n, problem.m))
    if not problem.has_obstacles:
        return [nominal]
    search = _GridSearch(problem, d0)
    starts = _grid_starts(search, reach_goal)
    edge = search.grids["coarse"][0][-1] * (1.0 - 1e-12)
    if starts is None or float(np.abs(starts[0]).max()) >= edge:
        stride = _coarse_stride(problem, d0, fine=problem.m == 1)
        if stride > 1:
            coarse = _grid_starts(_GridSearch(_subsampled(problem, stride), d0), reach_goal)
            if coarse is not None:
                wide = [_interpolated(start, stride, problem.n, d0) for start in coarse]
                starts = wide if starts is None else [*starts, *wide]
    if starts is None:
        raise UnsafePlanError(_blocked_message(problem, reach_goal))
    return [*starts, nominal]


def _grid_starts(search: _GridSearch, reach_goal: bool) -> list[np.ndarray] | None:
    """:func:`_full_starts`' grid paths from one search; None where every grid path is blocked."""
    grid = search.best(reach_goal)
    if grid is None:
        return None
    starts = [grid]
    if search.m == 1:  # cheap in 2-D; in 3-D each costs a dense solve per Newton step
        starts += search.flipped(reach_goal, grid)
        if search.grids["fine"] is not search.grids["coarse"]:
            fine = search.best(reach_goal, "fine")
            starts += [] if fine is None else [fine]
    return starts


def _blocked_message(problem: Problem, reach_goal: bool) -> str:
    return (
        "no collision-free plan: every path within the action bound "
        f"(max_slope {problem.max_step / problem.step:g}) enters an obstacle's "
        "radius plus clearance" + (" or cannot return to the goal" if reach_goal else "")
    )


def _best_of(
    problem: Problem,
    d0: np.ndarray,
    starts: list[np.ndarray],
    done: Callable[[], None] | None = None,
) -> tuple[np.ndarray, int, bool]:
    """The lowest-cost optimum polished from ``starts`` (skipping those inside a hard radius).

    ``done`` is called after each start is polished.
    """
    best, total_iter = None, 0
    for guess in starts:
        d, cost, n_iter, ok = problem.solve(d0, guess)
        total_iter += n_iter
        if done is not None:
            done()
        if np.isfinite(cost) and (best is None or cost < best[1] - 1e-12 * abs(best[1])):
            best = (d, cost, ok)
    if best is None:
        raise UnsafePlanError("no collision-free plan: every start enters an obstacle")
    return best[0], total_iter, best[2]


def _receding_horizon(
    problem: Problem,
    d0: np.ndarray,
    horizon: int,
    reach_goal: bool,
    lookahead: bool = True,
    progress: ProgressLike = None,
    back: float = np.inf,
) -> tuple[np.ndarray, int, bool]:
    """MPC: each window's best optimum, judged with the grid's cost-to-go after the window.

    A window alone is myopic: in front of a concave pocket the best ``H``
    points may head straight in. The grid's backward dynamic programme over
    the whole path (:func:`lfdkit.emulate._planner_kernels.grid_cost_to_go`) gives, for any
    offset at the window's end, the least cost of the rest. Near an obstacle
    the warm start and a grid path are polished; with ``lookahead`` the grid
    path is the global route from the anchor and the candidates (also that
    route itself) are ranked by window cost plus cost-to-go, without it the
    grid path is the window's own optimum and the least window cost wins
    (:func:`_ranked`). A candidate leading into a dead end is never executed.
    ``progress`` counts the steps. In 2-D with numba's kernels the loop runs
    compiled, bit for bit the same (:func:`_compiled_loop`); the Python loop
    is its NumPy form and the loop of 3-D plans. ``back`` (units, below
    ``max_step``): each executed step toward the nominal is at most that
    (:func:`lfdkit.emulate._planner_kernels.return_clamped`; the windows
    still plan with the symmetric bound, and the next window starts where the
    bounded step ended).
    """
    tracker = as_progress(progress)
    n, m = problem.n, problem.m
    offsets = np.zeros((n + 1, m))
    offsets[0] = d0
    guess = np.zeros((min(horizon, n), m))
    # The window grids' and the obstacle test's per-point numbers, once per plan.
    reaches = _WindowReaches(problem) if not lookahead and _WindowReaches.usable(problem) else None
    near = _ObstacleNear(problem) if problem.has_obstacles else None
    # 2-D with obstacles: the loop below in one compiled call (_compiled_loop)
    compiled = near is not None and m == 1 and (lookahead or reaches is not None) and use_compiled()
    table = levels = node = route = whole = None
    if problem.has_obstacles:
        with tracker.stage("plan: the grid's cost-to-go (global route)"):
            levels, cells = _lateral_levels(problem, d0)
            table = np.empty((n, levels.size**m))
            # grid_cost_to_go's two steps: the states' costs are shared (and used again compiled)
            states = _node_costs(problem, levels)
            _grid_kernel("grid_backward")(
                states, levels.size, cells, reach_goal, np.zeros((0, 0)), table
            )
            node = states if compiled else None
            whole = (levels, states)  # the 3-D windows take their states from it
            route = _LookAhead(table, levels, cells, problem.max_step, m)
            coarse = _coarse_look_ahead(problem, d0, reach_goal, route)
            if coarse is not None:  # the grid cannot cover the scene: every stride-th point
                route, compiled = coarse, False
        if not np.isfinite(route.walk(0, 1, d0)[1]):
            raise UnsafePlanError(_blocked_message(problem, reach_goal))
    ahead = _look_ahead_reach(horizon, n + 1, 1 if route is None else route.stride, lookahead)
    if compiled:
        with tracker.stage(f"plan: MPC H={horizon} over {n + 1} points", total=n) as stage:
            out = _compiled_loop(
                problem,
                d0,
                horizon,
                ahead,
                reach_goal,
                lookahead,
                (table, node, levels, cells),
                near,
                reaches,
                back,
            )
            stage.advance(n)
        return out
    total_iter, all_ok, widened, escapes = 0, True, False, []
    nodes = _WindowNodes(problem, whole) if m == 2 and use_compiled() else None

    def step(k: int, stop: int, window: Problem, guess: np.ndarray, anchor: np.ndarray, look):
        """The window's executed candidate: offsets, window cost, Newton iterations, ok.

        ``look``: rank as with ``lookahead`` (the route's path a candidate too).
        """
        # The route is consulted where an obstacle is within the look-ahead's reach
        # (_look_ahead_reach).
        if route is None or not near(k, min(k + ahead, n), anchor):
            return best_window(window, anchor, guess, sides=False)
        grid, total = route.walk(k, stop, anchor)
        blocked = not np.isfinite(total)
        if not look and not blocked:  # the window's own best grid path
            levels = (
                _lateral_levels(window, anchor)
                if reaches is None
                else _lateral_levels(window, anchor, widest=partial(reaches.widest, k, stop))
            )
            node = None if nodes is None else nodes.costs(k, stop, levels[0])
            own = _global_start(window, anchor, reach_goal and stop == n, levels, node=node)
            grid = grid if own is None else own
        polished, n_iter = [], 0
        for start in [guess] if blocked else [guess, grid]:
            d, cost, more, ok = window.solve(anchor, start)
            n_iter += more
            polished.append((d, ok))
        d, cost, ok = _ranked(window, polished, None if blocked else grid, route, stop, look)
        return d, cost, n_iter, ok

    with tracker.stage(f"plan: MPC H={horizon} over {n + 1} points", total=n) as stage:
        for k in range(n):
            stop = min(k + horizon, n)
            window = problem.window(k, stop)
            guess = guess[: stop - k]
            if guess.shape[0] < stop - k:
                guess = np.vstack([guess, np.repeat(guess[-1:], stop - k - guess.shape[0], axis=0)])
            anchor = offsets[k]
            d, cost, n_iter, ok = step(k, stop, window, guess, anchor, lookahead)
            # 3-D only: in 2-D the grids span 400 cells a side, and this loop must plan
            # as the compiled one (_compiled_loop), bit for bit.
            escape = not np.isfinite(cost) and not lookahead and m > 1
            if escape and not widened:
                # The thesis's window may swerve beyond the route's grid (at most 30
                # action bounds a side in 3-D), where its dead-end check judges from
                # the grid's edge, inside an obstacle's reach: the check again on a
                # route whose grid spans the anchor and the scene (_wider_look_ahead).
                wider = _wider_look_ahead(problem, anchor, reach_goal, route)
                if wider is not None:
                    route, widened = wider, True
                    ahead = _look_ahead_reach(horizon, n + 1, route.stride, lookahead)
                    total_iter += n_iter
                    d, cost, n_iter, ok = step(k, stop, window, guess, anchor, False)
            if escape and not np.isfinite(cost):
                # Every window optimum leads into a dead end: the escape is the
                # look-ahead's step (lookahead=True's ranking, the route's path
                # among the candidates), said once the plan is done.
                total_iter += n_iter
                d, cost, n_iter, ok = step(k, stop, window, guess, anchor, True)
                if np.isfinite(cost):
                    escapes.append(k + 1)
            if not np.isfinite(cost):
                raise UnsafePlanError(
                    f"no collision-free plan: at point {k + 1} of {n + 1} every move within the "
                    "action bound enters an obstacle's radius plus clearance"
                )
            total_iter += n_iter
            all_ok &= ok
            offsets[k + 1] = d[0]
            if back < problem.max_step:
                _grid_kernel("return_clamped")(anchor, offsets[k + 1], back)
            guess = np.vstack([d[1:], d[-1:]]) if d.shape[0] > 1 else d
            stage.advance()
    if escapes:
        warnings.warn(
            f"the thesis's receding horizon (lookahead=False, H={horizon} points) walked into "
            f"a dead end at {len(escapes)} of {n + 1} points (first {escapes[0]}): there it "
            "took the look-ahead route's step (lookahead=True's) instead of refusing",
            UserWarning,
            stacklevel=2,
        )
    return offsets[1:], total_iter, all_ok


def _strided_look_ahead(
    problem: Problem, stride: int, anchor: np.ndarray, reach_goal: bool
) -> _LookAhead:
    """The grid route of ``problem`` over every ``stride``-th point, laid out from ``anchor``.

    The :func:`_subsampled` problem's cost-to-go table on
    :func:`_lateral_levels`' grid (the route :func:`_coarse_look_ahead` and
    :func:`_wider_look_ahead` follow).
    """
    sub = _subsampled(problem, stride)
    levels, cells = _lateral_levels(sub, anchor)
    table = np.empty((sub.n, levels.size**problem.m))
    _grid_kernel("grid_cost_to_go")(
        *sub.kernel_arguments(), levels, cells, reach_goal, np.zeros((0, 0)), table
    )
    return _LookAhead(table, levels, cells, problem.max_step, problem.m, stride)


def _wider_look_ahead(
    problem: Problem, anchor: np.ndarray, reach_goal: bool, route: _LookAhead | None
) -> _LookAhead | None:
    """A route whose grid spans ``anchor`` and every obstacle's reach, where ``route``'s does not.

    The thesis's receding horizon (``lookahead=False``) follows its windows,
    not the route, and may swerve beyond the route's grid (3-D: at most 30
    action bounds a side, 20 cm at 100 points on a 0.68 m path); there its
    dead-end check (:meth:`_LookAhead.follow`) judged from the grid's edge,
    itself within a box's reach, and refused a plan that passes. This route
    is :func:`_coarse_look_ahead`'s over every ``stride``-th point, its grid
    laid out from ``anchor`` (:func:`_lateral_levels`). None where there is no
    route, ``route``'s grid already covers that span, or no stride does.
    """
    if route is None:
        return None
    stride = _coarse_stride(problem, anchor)
    if stride <= route.stride:
        return None
    return _strided_look_ahead(problem, stride, anchor, reach_goal)


def _look_ahead_reach(horizon: int, n_points: int, stride: int, lookahead: bool) -> int:
    """Points ahead of the receding horizon's step within which an obstacle consults the route.

    The horizon, over every ``stride``-th point where the route is
    (:func:`_coarse_look_ahead`); with ``lookahead``, at least the fraction of
    the path the horizon spans at :data:`~lfdkit.emulate.problem.PLAN_POINTS`
    points (:func:`~lfdkit.emulate.problem.horizon_points`). A plan at 500
    points then turns where one at 100 does: with the horizon's 8 points
    alone (1.6 % of the path) the route came too late to swerve round a
    0.2 m ball on a 1 m path at a 45° slope and the plan was refused. At 100
    points or fewer it is the horizon (the plan bit for bit as before);
    without ``lookahead`` (the thesis's MPC, which the IOC fits) ``horizon``
    is already the window's points (:func:`_route`).
    """
    reach = horizon * stride
    if lookahead:
        reach = max(reach, horizon_points(horizon, n_points))
    return reach


def _compiled_loop(
    problem: Problem,
    d0: np.ndarray,
    horizon: int,
    ahead: int,
    reach_goal: bool,
    lookahead: bool,
    grid: tuple[np.ndarray, np.ndarray, np.ndarray, int],
    near: _ObstacleNear,
    reaches: _WindowReaches | None,
    back: float = np.inf,
) -> tuple[np.ndarray, int, bool]:
    """:func:`_receding_horizon`'s loop in one compiled call (2-D, with obstacles).

    The same plan bit for bit as the Python loop, which stays the NumPy form
    (and the one for 3-D and for a moving problem's own window grids): the
    loop's glue around small kernel calls was four fifths of an MPC plan
    (issue 26). ``grid``: the whole path's cost-to-go table, its states'
    costs, levels and cells per step (a window's own grid on the same
    spacing takes its states' costs from there: the same numbers); ``ahead``
    the look-ahead's reach in points (:func:`_look_ahead_reach`).
    """
    table, node, levels, cells = grid
    empty = np.zeros((0, 0))
    per_point = (
        (empty, empty, empty, empty)
        if reaches is None
        else (reaches.distance2, reaches.reach, reaches.norms, reaches.largest)
    )
    offsets = np.zeros((problem.n + 1, problem.m))
    n_iter, ok, failed = _grid_kernel("receding_horizon_2d")(
        *problem.kernel_arguments(),
        problem.max_step,
        np.ascontiguousarray(d0, dtype=np.float64),
        int(horizon),
        int(ahead),
        bool(reach_goal),
        bool(lookahead),
        table,
        node,
        levels,
        int(cells),
        np.ascontiguousarray(near.b_norm),
        np.ascontiguousarray(near.radius),
        np.ascontiguousarray(near.outer[0]),
        *(np.ascontiguousarray(x, dtype=np.float64) for x in per_point),
        1e-10,
        100,
        offsets,
        float(back),
    )
    if failed >= 0:
        raise UnsafePlanError(
            f"no collision-free plan: at point {failed + 1} of {problem.n + 1} every move "
            "within the action bound enters an obstacle's radius plus clearance"
        )
    return offsets[1:], int(n_iter), bool(ok)


def _ranked(
    window: Problem,
    polished: list[tuple[np.ndarray, bool]],
    grid: np.ndarray | None,
    route: _LookAhead,
    stop: int,
    lookahead: bool,
) -> tuple[np.ndarray, float, bool]:
    """The window's candidate to execute.

    Candidates from whose last offset the rest of the path is blocked are
    skipped. With ``lookahead``, the least window cost plus cost-to-go wins,
    the grid path itself among the candidates (it is the only one that turns
    early enough to pass a concave pocket the window cannot see round);
    without, the window optimum of least window cost (the thesis's MPC).
    Returns offsets, window cost (``+inf`` when every candidate is blocked)
    and whether the candidate is a converged optimum.
    """
    candidates = list(polished) + ([(grid, True)] if lookahead and grid is not None else [])
    best, best_score = None, np.inf
    for d, ok in candidates:
        cost = window.total_cost(d)
        follow = route.follow(stop, d[-1])
        if not np.isfinite(follow):
            continue
        score = cost + follow if lookahead else cost
        if best is None or score < best_score:
            best, best_score = (d, cost, ok), score
    if best is None:  # blocked everywhere: the caller reports it
        best = (polished[0][0], np.inf, polished[0][1])
    return best


class _LookAhead:
    """The whole path's grid route for the receding horizon: a cost-to-go table and its walk.

    ``table`` (rows, G^m) is :func:`._planner_kernels.grid_cost_to_go`'s on
    ``levels`` (``cells`` per step), over every point (``stride`` 1) or over
    every ``stride``-th one, points ``stride − 1, 2 stride − 1, …`` of a
    :func:`_subsampled` problem (:func:`_coarse_look_ahead`). ``max_step`` is
    the plan's own action bound (units), ``m`` its offsets' dimension.
    """

    def __init__(
        self,
        table: np.ndarray,
        levels: np.ndarray,
        cells: int,
        max_step: float,
        m: int,
        stride: int = 1,
    ) -> None:
        self.table, self.levels, self.cells = table, levels, cells
        self.max_step, self.m, self.stride = max_step, m, stride

    def _row(self, point: int) -> tuple[int, int]:
        """The first row at or after ``point`` with a grid state in reach of point ``point − 1``.

        Returns the row (past the table's end after its last) and the steps
        from ``point − 1`` to it: enough for half a grid spacing, so that some
        state is within the action bound of any offset.
        """
        row = point // self.stride
        steps = self.stride * (row + 1) - point
        spacing = float(self.levels[1] - self.levels[0]) if self.levels.size > 1 else 0.0
        least = int(np.ceil(0.5 * spacing / self.max_step - 1e-9))
        if steps < least:
            more = -(-(least - steps) // self.stride)
            row, steps = row + more, steps + more * self.stride
        return row, steps

    def follow(self, stop: int, end: np.ndarray) -> float:
        """Least route cost of points ``stop …`` from offset ``end`` at point ``stop − 1``.

        Over every stride-th point, scaled by ``stride`` (the points it skips
        cost about as much), reached in as many steps as lie between.
        """
        if self.stride == 1:
            return _cost_to_go(self.table, self.levels, stop, end, self.max_step)
        row, steps = self._row(stop)
        if row >= self.table.shape[0]:
            return 0.0
        return self.stride * _cost_to_go(self.table, self.levels, row, end, steps * self.max_step)

    def walk(self, start: int, stop: int, anchor: np.ndarray) -> tuple[np.ndarray, float]:
        """The route (stop − start, m) over points ``start … stop − 1`` from ``anchor`` before them.

        Over every stride-th point, joined by straight lines from ``anchor``
        (within the action bound: a route step of ``s`` bounds over ``s``
        points). Returns the path and the route's cost from there (``+inf``:
        blocked; the path is then not to be used).
        """
        m = self.m
        if self.stride == 1:
            out = np.zeros((stop - start, m))
            total = _grid_kernel("grid_walk")(
                self.table[start:stop], self.levels, self.cells, self.max_step, anchor, out
            )
            return out, total
        first, steps = self._row(start)
        rows = self.table.shape[0]
        if first >= rows:  # after the route's last point: nothing left to route round
            return np.repeat(anchor[None], stop - start, axis=0), 0.0
        last = min(max(first, (stop - 1) // self.stride), rows - 1)
        coarse = np.zeros((last - first + 1, m))
        total = _grid_kernel("grid_walk")(
            self.table[first : last + 1],
            self.levels,
            self.cells,
            steps * self.max_step,
            anchor,
            coarse,
        )
        at = np.concatenate([[start - 1.0], self.stride * np.arange(first + 1, last + 2) - 1.0])
        # The route may end past ``stop``: the path is the line towards it, within the bound.
        values = np.vstack([anchor[None], coarse])
        points = np.arange(start, stop, dtype=np.float64)
        out = np.stack([np.interp(points, at, values[:, i]) for i in range(m)], axis=1)
        return out, total


def _coarse_look_ahead(
    problem: Problem, d0: np.ndarray, reach_goal: bool, route: _LookAhead
) -> _LookAhead | None:
    """The route over every stride-th point where the grid's own does not cover the scene.

    The receding horizon's look-ahead is the whole path's grid route
    (:func:`_receding_horizon`); its grid has at most a budget of cells a side,
    each at least one action bound wide (:func:`_coarse_stride`), so on a fine
    path (3-D at 250 points: ±8 cm) a way round a box is off the grid and the
    plan was refused, or cornered where the route runs along the grid's edge.
    There the route is that of the :func:`_subsampled` problem (an action bound
    ``stride`` times as wide): the look-ahead then covers the same lateral
    extent, in the path's length, at 100, 250 or 500 points. None where the
    grid covers the scene, or its route from ``d0`` keeps off the grid's edge
    (the look-ahead as it was, bit for bit).
    """
    stride = _coarse_stride(problem, d0)
    if stride == 1:
        return None
    path, total = route.walk(0, problem.n, d0)
    edge = route.levels[-1] * (1.0 - 1e-12)
    if np.isfinite(total) and float(np.abs(path).max()) < edge:
        return None
    return _strided_look_ahead(problem, stride, d0, reach_goal)


def _cost_to_go(
    table: np.ndarray, levels: np.ndarray, stop: int, end: np.ndarray, max_step: float
) -> float:
    """Least grid cost of points ``stop …`` reached in one step from offset ``end``.

    An offset beyond the grid (which spans every obstacle's reach, so nothing
    is in the way out there) is judged from the grid's edge: a plan that drifts
    wide, e.g. with a weak nominal weight, is not taken for blocked.
    """
    if stop >= table.shape[0]:
        return 0.0
    # np.clip's value on Python floats (a tenth of the MPC step's NumPy calls was np.clip).
    low, high = float(levels[0]), float(levels[-1])
    end = [min(max(float(value), low), high) for value in end]
    near = np.abs(levels - end[0]) <= max_step * (1.0 + 1e-12)
    row = table[stop]
    if len(end) == 2:
        near2 = np.abs(levels - end[1]) <= max_step * (1.0 + 1e-12)
        row = row.reshape(levels.size, levels.size)[near][:, near2]
        return float(row.min()) if row.size else np.inf
    return float(row[near].min()) if near.any() else np.inf


def best_window(
    window: Problem, anchor: np.ndarray, guess: np.ndarray, *, sides: bool = True
) -> tuple[np.ndarray, float, int, bool]:
    """Solve one MPC window from the warm start and, near an obstacle, its global grid path.

    The thesis's window solve (what :func:`plan_path` does away from
    obstacles, and what the emulation benchmark times window by window).

    Parameters
    ----------
    window : Problem
        The window's offsets (:meth:`Problem.window`).
    anchor : ndarray, shape (m,)
        The executed offset before the window (units).
    guess : ndarray, shape (h, m)
        Warm start: the previous window shifted by one point.
    sides : bool
        Near an obstacle, also polish the window's best path on the lateral
        grid (another way round it); False: the warm start alone.

    Returns
    -------
    d : ndarray, shape (h, m)
        The lowest-cost optimum found.
    cost : float
        Its cost (``+inf`` if every candidate enters a hard radius).
    n_iter : int
        Newton iterations, summed over the candidates.
    converged : bool
        Whether that optimum converged.
    """
    candidates = [guess]
    if sides and _obstacle_near(window, anchor):
        grid = _global_start(window, anchor, False)
        if grid is not None:
            candidates.append(grid)
    best, total = None, 0
    for candidate in candidates:
        d, cost, n_iter, ok = window.solve(anchor, candidate)
        total += n_iter
        if best is None or cost < best[1]:
            best = (d, cost, ok)
    return best[0], best[1], total, best[2]


def _obstacle_near(window: Problem, anchor: np.ndarray) -> bool:
    """Whether an obstacle's response or hard radius reaches the window's reachable offsets.

    Offsets within reach satisfy ``|d| ≤ ρ = |d_anchor| + n · max_step``; there the
    exponent ``c + 2bᵀd + dᵀAd`` is at least ``c − 2|b|ρ`` (``A`` is positive
    semi-definite), so an obstacle whose bound stays above 28 contributes less
    than 1e-12 anywhere the window can go.
    """
    if not window.has_obstacles:
        return False
    reach = float(np.linalg.norm(anchor)) + window.n * window.max_step * np.sqrt(window.m)
    lowest = window.c - 2.0 * np.linalg.norm(window.b, axis=2) * reach
    if bool(np.any(lowest < 28.0)):
        return True
    # rr may be below 0 for a moving obstacle's widened radius (problem.Problem): inside.
    return bool(np.any(np.sqrt(np.maximum(window.rr, 0.0)) - reach < np.sqrt(window.outer2)[None]))


class _ObstacleNear:
    """:func:`_obstacle_near` of ``problem.window(start, stop)``; per-point norms computed once."""

    def __init__(self, problem: Problem) -> None:
        self.problem = problem
        self.b_norm = np.linalg.norm(problem.b, axis=2)
        self.radius = np.sqrt(np.maximum(problem.rr, 0.0))
        self.outer = np.sqrt(problem.outer2)[None]
        self.max_step, self.root_m = problem.max_step, np.sqrt(problem.m)

    def __call__(self, start: int, stop: int, anchor: np.ndarray) -> bool:
        # The same operations, in the same order, as _obstacle_near's.
        reach = float(np.linalg.norm(anchor)) + (stop - start) * self.max_step * self.root_m
        lowest = self.problem.c[start:stop] - 2.0 * self.b_norm[start:stop] * reach
        if bool(np.any(lowest < 28.0)):
            return True
        return bool(np.any(self.radius[start:stop] - reach < self.outer))


def _check_ends(
    corridor: Corridor,
    d0: np.ndarray,
    problem: Problem,
    scene: Scene,
    clearance: np.ndarray,
    reach_goal: bool,
    which: tuple[str, ...] = ("start", "goal"),
) -> None:
    """Refuse a start (or, when the plan must reach it, a goal) inside an obstacle.

    Inside means within the radius plus clearance (or inside a shape with
    volume, :attr:`Obstacle.has_extent`), or, for a start, within
    one width of the response of an obstacle with neither (a goal may lie in
    a point obstacle's response: the plan passes through it to the goal).
    """
    if not problem.has_obstacles:
        return
    hard = scene.has_extent | (clearance > 0)  # a barrier: volume or a clearance
    anchor_owner = scene.anchors()[1]
    ends = [("start", corridor.points[0] + d0 @ corridor.normals[0])] if "start" in which else []
    if reach_goal and "goal" in which:
        ends.append(("goal", corridor.points[-1]))
    for name, point in ends:
        rel = point[None] - problem.obstacles
        depth = np.einsum("li,lij,lj->l", rel, problem.precision, rel)
        within_response = np.zeros(len(scene), bool)
        within_response[anchor_owner[depth < 1.0]] = True
        surface = scene.distances(point[None])
        # A start within a point obstacle's response is refused; the goal only
        # within a radius plus clearance (the way to it may pass through a response).
        response = within_response if name == "start" else np.zeros_like(within_response)
        inside = np.flatnonzero(np.where(hard, surface < clearance, response))
        if inside.size:
            o = int(inside[0])
            obstacle = scene.obstacles[o]
            if scene.radii[o] + clearance[o] > 0:
                what = f"its radius {scene.radii[o]:g} plus clearance {clearance[o]:g}"
            elif hard[o]:
                what = f"its {obstacle.shape} shape"
            else:
                what = "one width of its response"
            raise ValueError(
                f"{name}: lies inside obstacle {o} ({obstacle.label!r} at "
                f"{_coordinates(obstacle.position)}; within {what}); move the {name} or the "
                "obstacle"
            )


def clearance_per_obstacle(value: Any, scene: Scene) -> np.ndarray:
    """The clearance of each obstacle (n_obstacles,): one number for all, or one each."""
    if np.ndim(value) == 0:
        return np.full(len(scene), check_positive(value, "clearance", allow_zero=True))
    out = np.asarray(value, dtype=np.float64).reshape(-1)
    if out.size != len(scene):
        raise ValueError(
            f"clearance: expected one number or one per obstacle ({len(scene)}), got {out.size}"
        )
    if not np.all(np.isfinite(out)) or np.any(out < 0.0):
        raise ValueError(f"clearance: expected finite values >= 0, got {value!r}")
    return out


def _coordinates(point: np.ndarray) -> str:
    return "(" + ", ".join(f"{v:.6g}" for v in point) + ")"


def _clearance(path: np.ndarray, scene: Scene, clearance: float | np.ndarray) -> np.ndarray:
    """:func:`lfdkit.emulate.metrics.clearance` of a path and clearance already checked."""
    if not len(scene):
        return np.zeros(0)
    return scene.distances(path) - clearance


def timed_gaps(
    obstacle: Any,
    points: np.ndarray,
    times: np.ndarray,
    margin: float = 0.0,
    prediction: tuple[np.ndarray, np.ndarray] | None = None,
) -> np.ndarray:
    """Surface distance of each segment of a timed path to a moving obstacle (units).

    Between two points the tool and the obstacle's predicted mean are taken
    to move linearly, so segment ``k → k+1`` is measured in the obstacle's
    frame: the tool's position *relative* to the mean moves on a straight
    segment, whose distance to the obstacle is exact for that motion (not
    the obstacle frozen at a midpoint). ``margin`` times the smaller of the
    two predictions' standard deviations is subtracted.

    Parameters
    ----------
    obstacle : lfdkit.model.scene.Obstacle
    points : ndarray, shape (K, q)
    times : ndarray, shape (K,)
        Seconds at each point (K ≥ 2).
    margin : float
    prediction : (ndarray (K, q), ndarray (K, q, q)), optional
        ``obstacle.predict(times)``, when the caller has it already.

    Returns
    -------
    ndarray, shape (K − 1,)
        Negative where the segment comes within the radius plus margin.
    """
    means, covs = obstacle.predict(times) if prediction is None else prediction
    sigma = margin * predicted_sigma(covs) if margin else np.zeros(len(times))
    rel = points - means  # the tool in the obstacle's frame (its reference at the origin)
    if type(obstacle).distance is _ROUND_DISTANCE:
        a, d = rel[:-1], rel[1:] - rel[:-1]
        dd = np.einsum("kq,kq->k", d, d)
        s = np.clip(-np.einsum("kq,kq->k", a, d) / np.where(dd > 0.0, dd, 1.0), 0.0, 1.0)
        closest = a + s[:, None] * d
        gaps = np.sqrt(np.einsum("kq,kq->k", closest, closest)) - obstacle.radius
    else:  # any shape: its own distance to each relative segment
        framed = rel + obstacle.position
        gaps = np.array([obstacle.distance(framed[k : k + 2]) for k in range(len(points) - 1)])
    return gaps - np.minimum(sigma[1:], sigma[:-1])


def moving_clearance(
    points: np.ndarray,
    times: np.ndarray,
    scene: Scene,
    clearance: float | np.ndarray,
    margin: float,
) -> np.ndarray:
    """Distance of a timed path to each (moving) obstacle's surface, minus the margins.

    Each segment ``k → k+1`` is measured with the tool and the obstacle's
    predicted mean both moving linearly over it (:func:`timed_gaps`), minus
    ``clearance`` and ``margin`` times the smaller standard deviation of the
    two predictions. (The planner's hard radius at a point, widened by half
    the obstacle's move to its neighbours and half a segment, keeps this
    positive whenever radius plus clearance is at least half a segment.)

    Parameters
    ----------
    points : ndarray, shape (K, q)
    times : ndarray, shape (K,)
        Seconds at each point.
    scene : Scene
    clearance : float or ndarray, shape (n_obstacles,)
    margin : float

    Returns
    -------
    ndarray, shape (n_obstacles,)
        Negative where the path comes within the obstacle's radius plus margins.
    """
    out = np.empty(len(scene))
    for o, obstacle in enumerate(scene.obstacles):
        out[o] = timed_gaps(obstacle, points, times, margin).min() - (
            clearance[o] if np.ndim(clearance) else clearance
        )
    return out


def verified_plan(
    plan: Plan,
    corridor: Corridor,
    scene: Scene,
    clearance: np.ndarray,
    reach_goal: bool,
    times: np.ndarray | None = None,
    margin: float = UNCERTAINTY_MARGIN,
) -> Plan:
    """Check the finished plan against every obstacle and the goal; raise if it fails.

    With ``times`` (a scene with moving obstacles) against where each
    obstacle is predicted when the tool is there (:func:`moving_clearance`).
    """
    if times is None:
        plan.clearance = _clearance(plan.points, scene, clearance)  # checked by plan_path
    else:
        plan.clearance = moving_clearance(plan.points, times, scene, clearance, margin)
    plan.goal_error = float(np.linalg.norm(plan.points[-1] - corridor.points[-1]))
    tolerance = 1e-9 * max(corridor.extent, corridor.length)
    hit = np.flatnonzero((plan.clearance < -tolerance) & (scene.has_extent | (clearance > 0)))
    if hit.size:
        o = int(hit[np.argmin(plan.clearance[hit])])
        obstacle = scene.obstacles[o]
        raise UnsafePlanError(
            f"no collision-free plan: the best plan passes {-plan.clearance[o]:.3g} inside "
            f"obstacle {o} ({obstacle.label!r} at {_coordinates(obstacle.position)}, radius "
            f"{obstacle.radius:g} plus clearance {clearance[o]:g})"
        )
    if reach_goal and plan.goal_error > GOAL_TOLERANCE * corridor.extent:
        raise UnsafePlanError(
            f"the plan ends {plan.goal_error:.3g} from the goal (more than {GOAL_TOLERANCE:g} of "
            f"the path's extent {corridor.extent:.3g}); a longer goal_approach may help"
        )
    return plan
