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
skill's speed profile along the nominal, :meth:`lfdkit.skill.Skill.point_times`).
A plan that swerves is a little longer than the nominal; run with the
nominal's times, the swerve is slightly faster, not later, so the predicted
positions are those of the right moments. Obstacles are assumed to follow the
tracker's motion model (constant velocity by default) over the horizon; the
uncertainty margin and the re-planning at every step absorb what it misses.

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
from lfdkit.emulate.planner import UnsafePlanError, best_window
from lfdkit.emulate.problem import (
    UNCERTAINTY_MARGIN,
    Corridor,
    Problem,
    check_times,
    goal_weights,
)
from lfdkit.emulate.reward import Reward
from lfdkit.model.scene import Scene

__all__ = ["RecedingPlanner"]


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
