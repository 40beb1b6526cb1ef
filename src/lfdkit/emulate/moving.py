"""Closed-loop planning among moving obstacles: one MPC window per control step.

The thesis's MPC (§5.4) plans around static obstacles; moving ones, predicted
over the horizon, are its future work. :class:`RecedingPlanner` runs that
loop: at control step ``k`` the tool is at plan point ``k`` (time
``times[k]``); the window of points ``k+1 … k+H`` is planned with each
obstacle's reward terms and hard radius at its *predicted* position at the
time the tool reaches each point (:meth:`lfdkit.model.scene.Obstacle.predict`, e.g.
a :class:`lfdkit.model.motion.Tracked` Kalman tracker fed with the latest
observation), the hard radius widened by ``margin`` standard deviations of the
prediction (:data:`~lfdkit.emulate.problem.UNCERTAINTY_MARGIN`); the tool
moves to the window's first point, and the next step re-plans with the next
observation.

Timing assumption
-----------------
The tool reaches plan point ``k`` at ``times[k]``: the nominal's timing (a
skill's speed profile along the nominal, :meth:`lfdkit.skill.Skill.point_times`),
from the planner's own copy of ``times`` (a hold moves the rest of it later;
the caller's array is never written to).
A plan that swerves is a little longer than the nominal; run with the
nominal's times, the swerve is slightly faster, not later, so the predicted
positions are those of the right moments. Obstacles are assumed to follow the
tracker's motion model (constant velocity by default) over the horizon; the
uncertainty margin and the re-planning at every step absorb what it misses,
and with an acceleration bound in the tracker
(:class:`lfdkit.model.motion.ConstantVelocityKalman`'s ``max_acceleration``) the
margin also covers obstacles that speed up, brake or turn up to that bound.

Holding safely
--------------
When every move in the window is blocked, :meth:`RecedingPlanner.step`
raises and the caller holds the tool with :meth:`RecedingPlanner.hold`. A
hold is not "stop where you are": an obstacle coming at a standing tool
hits it all the same (the issue-27 battery: 4 of 5 collisions were of a held
brush). The hold ranks the reachable actions — stay, step aside along the
normal (up to one action bound ``max_step`` each way, on a grid of
:data:`HOLD_CHOICES` each side), or retreat one point along the path with
the same sideways choices — by the *predicted clearance over the horizon*:
the tool moving straight to the candidate in ``wait`` s and standing there
until :data:`HOLD_LOOKAHEAD` waits have passed (the loop observes and
re-plans at each; further ahead the worst-case allowance of a manoeuvring
obstacle, growing as ``τ²``, would call every spot unsafe and walk the tool
back along the whole path), measured against every obstacle
moving as predicted (:func:`lfdkit.emulate.planner.timed_gaps`: tool and
obstacle both moving, radius plus clearance plus ``margin`` σ). Staying
wins whenever it is clear over that span; otherwise the smallest move that
is, sideways before backwards (a retreat reverses the tool's direction,
which a tool whose heading follows the path turns round for); when none
is, the candidate of largest predicted clearance. If even that one is predicted inside an
obstacle's allowance before the loop can act twice more (``2 · wait``),
the hold raises :class:`~lfdkit.emulate.planner.UnsafePlanError` with the
predicted time of contact: the verdict comes *before* the contact.

What is guaranteed, given the tracker's allowance covers the truth (with
:class:`lfdkit.model.motion.ConstantVelocityKalman`'s ``max_acceleration`` ``A``:
any obstacle accelerating, braking or turning at most ``A``; observation
noise within ``margin`` σ): the executed steps stay out of radius plus
clearance, and a blocked tool either moves out of the predicted path of an
obstacle whose speed *relative to the tool's escape* is below
``max_step / wait`` (per axis: one action bound per hold; with the sweeping
task's 0.5 slope, 7.9 mm steps and ``wait`` 0.1 s, 3.9 cm/s sideways — so an
obstacle at 30 cm/s is escaped only when the window sees it coming early
enough, ``H`` points ahead), or the run stops with a verdict before the
predicted contact. Nothing is promised for an obstacle whose motion the
allowance does not cover (faster manoeuvres than ``A``, teleports), nor
once the run has stopped (a robot standing still can still be hit; the
verdict is the caller's cue to retract or halt the obstacle's source). The
allowance itself is a bound only up to the tracker's ``bound_horizon`` (the
sweeping loop: 0.3 s); further ahead it is the noise's σ plus the bound
there, measured, not guaranteed (``benchmarks/moving.py``: ≥ 99.9 % of
window points near the tool covered for obstacles accelerating, braking,
stopping and going or turning at up to 0.3 m/s²; over *all* window points,
98.2 % at least, the misses ~0.4 m from the point, beyond the bound's 0.3 s;
carried 0.5 s ahead the bound covers ≥ 99.7 % of all of them, but holds the
tool longer and gives up more often: ``--bound-horizons 0.3,0.5``).

Each window is solved as :func:`lfdkit.emulate.planner.best_window` solves the
thesis's MPC window (the warm start and, near an obstacle, the window's best
path on the lateral grid, polished by Newton); with a static scene this is the
thesis's MPC re-planned at every step. A known motion without observations
(:class:`lfdkit.model.motion.ConstantVelocity`) can also be planned open loop, over
the whole path at once: ``plan_path(..., times=...)``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from lfdkit.core.options import MAX_HORIZON
from lfdkit.core.validation import check_horizon, check_positive
from lfdkit.emulate.planner import UnsafePlanError, best_window, timed_gaps
from lfdkit.emulate.problem import (
    UNCERTAINTY_MARGIN,
    Corridor,
    Problem,
    check_times,
    goal_weights,
)
from lfdkit.emulate.reward import Reward
from lfdkit.model.scene import Scene

__all__ = ["HOLD_CHOICES", "HOLD_LOOKAHEAD", "RecedingPlanner"]

#: Sideways choices of a hold on each side (the action bound split into this many steps).
HOLD_CHOICES = 4
#: Holds look this many waits ahead (the next observations and the re-plans they allow).
HOLD_LOOKAHEAD = 3


class RecedingPlanner:
    """MPC re-planned at every control step with the obstacles' predicted positions.

    Parameters
    ----------
    reward : Reward
        The learned reward (its classes cover the scenes' obstacles).
    nominal : array_like, shape (n, q) or Corridor
        Nominal path (e.g. the DMP to the goal); resampled to ``n_points``.
    times : array_like, shape (n_points,)
        Seconds at which the tool reaches each plan point (non-decreasing).
    horizon : int
        Window length ``H`` (4 to 12).
    n_points : int
        Points ``K`` of the plan (control steps ``K − 1``).
    max_slope : float
        Largest sideways step per nominal step.
    goal_approach : float, "auto" or None
        As :func:`lfdkit.emulate.plan_path`: the plan returns to the goal.
    clearance : float
        Tool clearance (units) added to every obstacle's radius (hard).
    margin : float
        Standard deviations of the prediction added to a moving obstacle's radius.
    start_offset : array_like, shape (q − 1,), optional
        Lateral offset of the start from the nominal's.

    Attributes
    ----------
    corridor : Corridor
    times : ndarray, shape (K,)
    step_index : int
        The point the tool is at (0 at the start).
    offsets : ndarray, shape (K, q − 1)
        Executed offsets (rows after ``step_index`` are zero until executed).
    window : ndarray, shape (h + 1, q)
        The last planned window, from the point the tool was at.
    """

    def __init__(
        self,
        reward: Reward,
        nominal: Any,
        times: Any,
        *,
        horizon: int = MAX_HORIZON,
        n_points: int = 100,
        max_slope: float = 1.0,
        goal_approach: float | str | None = "auto",
        clearance: float = 0.0,
        margin: float = UNCERTAINTY_MARGIN,
        start_offset: Any = None,
    ) -> None:
        if not isinstance(reward, Reward):
            raise TypeError(f"reward: expected an lfdkit.emulate.Reward, got {type(reward)}")
        horizon = check_horizon(horizon)
        self.reward = reward
        self.corridor = (
            nominal if isinstance(nominal, Corridor) else Corridor.from_path(nominal, n_points)
        )
        self.times = check_times(times, self.corridor.n_points)
        self._pace = self.times - self.times[0]  # the nominal's timing, for after a hold
        self.horizon = horizon
        self.max_slope = check_positive(max_slope, "max_slope")
        self.clearance = check_positive(clearance, "clearance", allow_zero=True)
        self.margin = check_positive(margin, "margin", allow_zero=True)
        self.weights = goal_weights(self.corridor, reward.nominal_weight, goal_approach)
        m = self.corridor.n_dims - 1
        self.offsets = np.zeros((self.corridor.n_points, m))
        if start_offset is not None:
            self.offsets[0] = np.asarray(start_offset, dtype=np.float64).reshape(m)
        self.step_index = 0
        self._guess = np.zeros((0, m))
        self.window = self.corridor.points[:1].copy()

    @property
    def done(self) -> bool:
        """Whether the tool is at the last point."""
        return self.step_index >= self.corridor.n_points - 1

    @property
    def point(self) -> np.ndarray:
        """Where the tool is (q,)."""
        k = self.step_index
        return self.corridor.points[k] + self.offsets[k] @ self.corridor.normals[k]

    @property
    def points(self) -> np.ndarray:
        """The executed points so far, (step_index + 1, q)."""
        k = self.step_index + 1
        return self.corridor.to_points(self.offsets[:k]) if k else self.corridor.points[:0]

    def window_problem(self, scene: Scene) -> Problem:
        """The problem of the next window's offsets, the obstacles where predicted."""
        k, n = self.step_index, self.corridor.n_points - 1
        stop = min(k + self.horizon, n)
        c = self.corridor
        sub = Corridor(
            c.points[k : stop + 1], c.normals[k : stop + 1], c.tangents[k : stop + 1], c.step
        )
        problem = Problem.from_scene(
            self.reward,
            sub,
            scene,
            self.max_slope,
            None,
            self.clearance,
            self.times[k : stop + 1] if scene.moving else None,
            self.margin,
        )
        problem.weight = self.weights[k:stop].copy()
        return problem

    def step(self, scene: Scene) -> np.ndarray:
        """Plan the window with ``scene`` and move to the next point; returns it (q,).

        Raises
        ------
        UnsafePlanError
            When every move within the action bound enters an obstacle's
            radius plus clearance (and margin) in the window: the caller
            should stop the robot.
        ValueError
            After the last point, or for a scene the reward does not know.
        """
        if self.done:
            raise ValueError("step: the tool is at the goal; nothing left to plan")
        if not isinstance(scene, Scene):
            raise TypeError(f"scene: expected an lfdkit.emulate.Scene, got {type(scene).__name__}")
        window = self.window_problem(scene)
        h = window.n
        guess = self._guess[:h]
        if guess.shape[0] < h:
            fill = guess[-1:] if guess.shape[0] else self.offsets[self.step_index][None]
            guess = np.vstack([guess, np.repeat(fill, h - guess.shape[0], axis=0)])
        anchor = self.offsets[self.step_index]
        d, cost, _, _ = best_window(window, anchor, guess, sides=True)
        k = self.step_index
        if not np.isfinite(cost):
            raise UnsafePlanError(
                f"no collision-free move at point {k + 1} of {self.corridor.n_points} "
                f"(t = {self.times[k + 1]:.3g} s): every move within the action bound enters "
                "an obstacle's predicted radius plus clearance and uncertainty margin"
            )
        self.offsets[k + 1] = d[0]
        self._guess = np.vstack([d[1:], d[-1:]])
        sub = self.corridor
        self.window = np.vstack(
            [
                self.point,
                sub.points[k + 1 : k + 1 + h]
                + np.einsum("km,kmq->kq", d, sub.normals[k + 1 : k + 1 + h]),
            ]
        )
        self.step_index = k + 1
        return self.point

    def hold(self, scene: Scene, wait: float, position: Any = None) -> np.ndarray:
        """Hold the tool ``wait`` s where the predicted clearance is largest; returns where (q,).

        Candidates (module notes): stay, step aside up to ``max_step`` along
        the normal, or retreat one point along the path (same sideways
        choices); each scored by its least predicted clearance while the tool
        moves there in ``wait`` s and stands there until
        :data:`HOLD_LOOKAHEAD` waits have passed.
        The rest of the plan's times move later so that the tool is at its
        point at ``times[step_index] + wait`` (the planner's own copy; the
        caller's array is never written to).

        Parameters
        ----------
        scene : Scene
            The obstacles, as for :meth:`step`.
        wait : float
            Seconds until the next observation (> 0).
        position : array_like, shape (q,), optional
            Where the tool is, if not at :attr:`point` (stopped inside a long
            step): the candidates are then those of the point it was heading
            to and the one before, within reach of ``position``.

        Returns
        -------
        ndarray, shape (q,)
            Where the tool is after the hold.

        Raises
        ------
        UnsafePlanError
            When even the best candidate is predicted to come inside an
            obstacle's radius plus clearance (and margin) within ``2 · wait``
            s: the contact cannot be avoided within the action bound; the
            message gives the predicted time. The tool has not moved.
        """
        wait = check_positive(wait, "wait")
        if not isinstance(scene, Scene):
            raise TypeError(
                f"scene: expected an lfdkit.model.scene.Scene, got {type(scene).__name__}"
            )
        c, k = self.corridor, self.step_index
        here = self.point if position is None else np.asarray(position, dtype=np.float64)
        now = float(self.times[k])
        span = HOLD_LOOKAHEAD * wait
        m = c.n_dims - 1
        steps = self.max_slope * c.step * np.linspace(-1.0, 1.0, 2 * HOLD_CHOICES + 1)
        if m == 1:
            sideways = steps[:, None]
        else:
            sideways = np.stack(np.meshgrid(steps, steps, indexing="ij"), axis=-1).reshape(-1, 2)
        reach = float(np.hypot(c.step, self.max_slope * c.step * np.sqrt(m))) * (1.0 + 1e-9)
        candidates = []
        for index in (k, k - 1) if k > 0 else (k,):
            offsets = self.offsets[k] + sideways
            points = c.points[index] + offsets @ c.normals[index]
            for offset, point in zip(offsets, points, strict=True):
                if np.linalg.norm(point - here) <= reach:
                    candidates.append((index, offset, point))
        # the tool moves to the candidate in `wait`, then stands there until `span`
        grid = now + np.concatenate([np.linspace(0.0, wait, 5), np.linspace(wait, span, 9)[1:]])
        early = grid <= now + 2.0 * wait + 1e-12
        hard = [o for o in scene.obstacles if o.has_extent or self.clearance > 0.0]
        predictions = [o.predict(grid) for o in hard]  # the same for every candidate
        scores = []
        for _, _, point in candidates:
            path = np.vstack([np.linspace(here, point, 5), np.repeat(point[None], 8, axis=0)])
            gaps = np.full(len(grid) - 1, np.inf)
            for obstacle, prediction in zip(hard, predictions, strict=True):
                margin = self.margin if obstacle.moving else 0.0
                gap = timed_gaps(obstacle, path, grid, margin, prediction)
                gaps = np.minimum(gaps, gap - self.clearance)
            scores.append(gaps)
        overall = np.array([g.min() for g in scores])
        stay = next(
            (
                i
                for i, (index, offset, _) in enumerate(candidates)
                if index == k and np.array_equal(offset, self.offsets[k])
            ),
            None,
        )
        moves = np.array([np.linalg.norm(p - here) for _, _, p in candidates])
        aside = [i for i, c in enumerate(candidates) if c[0] == k and overall[i] >= 0.0]
        back = [i for i, c in enumerate(candidates) if c[0] < k and overall[i] >= 0.0]
        if stay is not None and overall[stay] >= 0.0:
            best = stay
        elif aside or back:  # the smallest safe move; sideways before backwards
            best = min(aside or back, key=lambda i: moves[i])
        else:  # the largest clearance; among equals, the smallest move
            best = int(np.lexsort((moves, -np.round(overall, 12)))[0])
        soon = scores[best][early[1:]].min()
        if soon < 0.0:
            when = grid[1:][int(np.argmax(scores[best] < 0.0))]
            raise UnsafePlanError(
                f"contact predicted at t = {when:.3g} s (now {now:.3g} s): no reachable hold "
                f"(stay, step aside or retreat within the action bound) keeps out of an "
                f"obstacle's predicted radius plus clearance and margin; stop the robot"
            )
        index, offset, point = candidates[best]
        self.step_index = index
        self.offsets[index] = offset
        # the rest runs at the nominal's pace from the hold's end (after a retreat too:
        # the step back to where the tool was is a step of the nominal's, not the hold)
        self.times[index:] = now + wait + self._pace[index:] - self._pace[index]
        self._guess = np.zeros((0, m))
        self.window = point[None].copy()
        return self.point
