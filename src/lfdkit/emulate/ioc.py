"""Inverse optimal control: the reward whose optimal paths match the demonstrations (eq. 5.5).

``θ = [log Q, log diag P_c for each class]`` minimises the mean squared
distance between each demonstration and the path planned in its scene::

    L(θ) = Σ_d Σ_k |x̄_k(θ, scene_d) − ζ_{d,k}|² / (number of matched points)

Distances are taken along the nominal's normals (the planner's own
coordinates, :class:`lfdkit.emulate.Corridor`): ``ζ_{d,k}`` is where
demonstration ``d`` crosses the normal of nominal point ``k``, so ``|x̄_k −
ζ_{d,k}|`` is the difference of two lateral offsets. Points where the
demonstration does not cross a normal are left out.

Gradients are exact, by implicit differentiation of the planner's optimality
conditions. At a plan ``d*`` the free action groups (:mod:`.planner`) satisfy
``G(d*, θ) = 0``; so ``dδ/dθ = −H⁻¹ ∂G/∂θ`` with ``H`` the (block-)diagonal
reduced Hessian, and the loss gradient is one adjoint solve per demonstration,
``−λᵀ ∂G/∂θ`` with ``H λ = ∂L/∂δ``. Held actions (at their bound) do not move
to first order. The outer loop is L-BFGS on ``θ``; each inner plan is
warm-started on the demonstration it is compared with, so it lands in the same
local optimum (the same side of each obstacle) as the demonstrator.

The fit is staged: the full-horizon planner first (cheap, smooth), then,
optionally, refinement with the receding-horizon planner (MPC) that is used
at run time, its gradient by forward sensitivities through every MPC step.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.optimize import minimize

from lfdkit._validation import check_positive
from lfdkit.emulate.planner import (
    MAX_HORIZON,
    MIN_HORIZON,
    Corridor,
    _build,
    _groups,
    _Problem,
    _side_starts,
    _solve,
    plan_path,
)
from lfdkit.emulate.reward import Reward
from lfdkit.emulate.scene import Scene

__all__ = ["IOC", "DemoInScene"]


@dataclass(frozen=True, eq=False)
class DemoInScene:
    """One demonstration in the planner's coordinates."""

    corridor: Corridor
    scene: Scene
    start: np.ndarray  # (m,) lateral offset of the demonstration's start
    target: np.ndarray  # (K, m) lateral offsets of the demonstration
    found: np.ndarray  # (K,) where it crosses the normals


def _theta_derivative(
    problem: _Problem, d: np.ndarray, class_of: np.ndarray, n_classes: int
) -> np.ndarray:
    """``∂G/∂θ``: derivative of the offset gradient w.r.t. θ, shape (n, m, n_theta).

    θ = [log Q, log p_{c,i}]; precisions diagonal. For obstacle ``o`` of class
    ``c`` with ``u = x − O`` and ``e = exp(−uᵀPu)`` the gradient term is
    ``−2e N P u``, whose derivative in ``log p_i`` is ``2 e p_i u_i (u_i N P u − N_{·i})``.
    """
    n, m = d.shape
    q = problem.base.shape[1]
    out = np.zeros((n, m, 1 + n_classes * q))
    out[:, :, 0] = 2.0 * problem.weight[:, None] * d
    if not problem.has_obstacles:
        return out
    points = problem.base + np.einsum("km,kmq->kq", d, problem.normals)
    rel = points[:, None, :] - problem.obstacles[None]  # (n, L, q)
    diag = np.einsum("lii->li", problem.precision)  # (L, q)
    pu = rel * diag[None]  # P u for diagonal P
    bump = np.exp(-np.einsum("kli,kli->kl", rel, pu))
    npu = np.einsum("kmq,klq->klm", problem.normals, pu)
    # (n, L, m, q): 2 e p_i u_i (u_i N P u − N[:, i])
    term = (
        2.0
        * (bump[:, :, None] * diag[None] * rel)[:, :, None, :]
        * (rel[:, :, None, :] * npu[:, :, :, None] - problem.normals[:, None, :, :])
    )
    for o in range(problem.obstacles.shape[0]):
        c = int(class_of[o])
        out[:, :, 1 + c * q : 1 + (c + 1) * q] += term[:, o]
    return out


def _held(problem: _Problem, d0: np.ndarray, d: np.ndarray, gradient: np.ndarray) -> np.ndarray:
    actions = np.diff(np.vstack([d0[None], d]), axis=0)
    action_gradient = np.cumsum(gradient[::-1], axis=0)[::-1]
    bound = problem.max_step
    return ((actions >= bound * (1 - 1e-9)) & (action_gradient < 0)) | (
        (actions <= -bound * (1 - 1e-9)) & (action_gradient > 0)
    )


def _reduced_hessian(index: np.ndarray, n_vars: int, hessian: np.ndarray) -> np.ndarray:
    m = index.shape[1]
    h = np.zeros((n_vars, n_vars))
    for i in range(m):
        for j in range(m):
            keep = (index[:, i] >= 0) & (index[:, j] >= 0)
            np.add.at(h, (index[keep, i], index[keep, j]), hessian[keep, i, j])
    return h


def _closest_window(
    window: _Problem, anchor: np.ndarray, guess: np.ndarray, guide: np.ndarray, matched: bool
) -> np.ndarray:
    """The window optimum (of several starts) whose first offset is nearest the demonstration's."""
    candidates = [guess, guide.copy()]
    if window.has_obstacles and window.bumps(guess)[0].max() > 1e-6:
        candidates += _side_starts(window, anchor)[1:]
    best, best_key = None, None
    for candidate in candidates:
        d, cost, _, _ = _solve(window, anchor, candidate, tol=1e-11, max_iter=200)
        key = (float(np.sum((d[0] - guide[0]) ** 2)) if matched else 0.0, cost)
        if best_key is None or key < best_key:
            best, best_key = d, key
    return best


def _mpc_with_sensitivity(
    problem: _Problem, item: DemoInScene, horizon: int, class_of: np.ndarray, n_classes: int
) -> tuple[np.ndarray, np.ndarray]:
    """Receding-horizon plan and its derivative w.r.t. θ by forward sensitivities.

    Each window is solved from the previous window shifted (as at run time),
    from the demonstration's offsets over the window and from both sides of a
    near obstacle; of these local optima the one whose executed offset is
    closest to the demonstration's is kept. The demonstrator's choice of side
    is data, and what is explained is how far and how smoothly it swerves;
    within one choice the plan is smooth in θ. At a window's
    optimum the free groups satisfy ``G(w, d_k, θ) = 0``; the window moves with
    ``θ`` directly and through the executed offset ``d_k`` it is anchored to:
    ``dδ = −H⁻¹ (∂G/∂θ + ∂G/∂d_k · S_k)``, and ``S_{k+1}`` is the first
    offset's row of it (or ``S_k`` where the first action is held).

    Returns offsets (n, m) and sensitivities (n, m, n_theta).
    """
    n, m = problem.n, problem.m
    n_theta = 1 + n_classes * problem.base.shape[1]
    guide = np.where(item.found[1:, None], item.target[1:], 0.0)
    offsets = np.zeros((n, m))
    sensitivity = np.zeros((n, m, n_theta))
    anchor, anchor_sens = item.start.astype(float), np.zeros((m, n_theta))
    guess = guide[: min(horizon, n)].copy()
    for k in range(n):
        stop = min(k + horizon, n)
        window = problem.window(k, stop)
        guess = guess[: stop - k]
        w = _closest_window(window, anchor, guess, guide[k:stop], item.found[k + 1])
        guess = np.vstack([w[1:], w[-1:]]) if w.shape[0] > 1 else w
        _, gradient, hessian = window.derivatives(w)
        held = _held(window, anchor, w, gradient)
        index, n_vars = _groups(~held)
        first = np.empty((m, n_theta))
        if n_vars:
            moving = index >= 0
            rhs = np.zeros((n_vars, n_theta))
            np.add.at(rhs, index[moving], _theta_derivative(window, w, class_of, n_classes)[moving])
            coupling = np.zeros((n_vars, m))  # ∂G/∂d_k: anchored components move with d_k
            for i in range(m):
                for j in range(m):
                    pair = moving[:, i] & ~moving[:, j]
                    np.add.at(coupling[:, j], index[pair, i], hessian[pair, i, j])
            h = _reduced_hessian(index, n_vars, hessian)
            moves = -np.linalg.solve(h, rhs + coupling @ anchor_sens)
            for i in range(m):
                first[i] = moves[index[0, i]] if index[0, i] >= 0 else anchor_sens[i]
        else:
            first[:] = anchor_sens
        offsets[k], sensitivity[k] = w[0], first
        anchor, anchor_sens = w[0], first
    return offsets, sensitivity


class IOC:
    """Fit a :class:`Reward` to demonstrations in their scenes (thesis eq. 5.5).

    Parameters
    ----------
    classes : sequence of str, optional
        Obstacle classes to learn (default: every class in the scenes).
    n_points : int
        Points ``K`` of each plan along the nominal.
    horizon : int, optional
        If given (4–12), refine the full-horizon fit with the MPC planner of
        this horizon (the staged fit).
    max_slope : float
        The planner's action bound (sideways step per nominal step).
    init : Reward, optional
        Starting reward (default: the best of a coarse grid of stiffnesses and
        obstacle widths, see :meth:`_initial_theta`).
    max_iter : int
        L-BFGS iterations per stage.
    tol : float
        Relative tolerance on the loss for L-BFGS.
    gradient : {"implicit", "finite_difference"}
        Exact implicit gradients (default), or central finite differences of the
        loss (two extra plans per parameter and demonstration; for comparison).

    Attributes
    ----------
    reward_ : Reward
    theta_ : ndarray
        ``[log Q, log diag P_c …]``.
    classes_ : tuple of str
    loss_ : float
        Final mean squared distance (units²) on the training demonstrations.
    loss_history_ : list of float
    stages_ : list of dict
        Per stage: planner, iterations, loss, seconds.
    """

    def __init__(
        self,
        classes: Sequence[str] | None = None,
        *,
        n_points: int = 100,
        horizon: int | None = None,
        max_slope: float = 1.0,
        init: Reward | None = None,
        max_iter: int = 200,
        tol: float = 1e-10,
        gradient: str = "implicit",
    ) -> None:
        self.classes = classes
        self.n_points = n_points
        self.horizon = horizon
        self.max_slope = max_slope
        self.init = init
        self.max_iter = max_iter
        self.tol = tol
        self.gradient = gradient

    # ---------------------------------------------------------------- data
    def _prepare(self, demos: Any, scenes: Any, nominal: Any) -> list[DemoInScene]:
        demos = list(demos)
        scenes = list(scenes)
        if len(demos) != len(scenes):
            raise ValueError(
                f"scenes: {len(scenes)} scenes for {len(demos)} demonstrations; "
                "give one scene per demonstration"
            )
        if not demos:
            raise ValueError("demos: needs at least one demonstration")
        nominals = nominal if isinstance(nominal, (list, tuple)) else [nominal] * len(demos)
        if len(nominals) != len(demos):
            raise ValueError(f"nominal: {len(nominals)} nominal paths for {len(demos)} demos")
        corridors: dict[int, Corridor] = {}
        prepared = []
        for j, (demo, scene, path) in enumerate(zip(demos, scenes, nominals, strict=True)):
            if not isinstance(scene, Scene):
                raise TypeError(f"scenes[{j}]: expected a Scene, got {type(scene).__name__}")
            corridor = corridors.get(id(path))
            if corridor is None:
                corridor = Corridor.from_path(path, self.n_points)
                corridors[id(path)] = corridor
            try:
                target, found = corridor.offsets_of(demo)
            except ValueError as exc:
                raise ValueError(f"demos[{j}]: {exc}") from None
            if found.sum() < 0.5 * corridor.n_points:
                raise ValueError(
                    f"demos[{j}]: crosses only {int(found.sum())} of {corridor.n_points} normals "
                    "of the nominal path; does it follow the same course?"
                )
            start = target[0] if found[0] else target[np.argmax(found)]
            prepared.append(DemoInScene(corridor, scene, start, target, found))
        return prepared

    # ------------------------------------------------------------- objective
    def _objective(
        self, theta: np.ndarray, data: list[DemoInScene], warm: list[np.ndarray]
    ) -> tuple[float, np.ndarray]:
        reward = Reward.from_theta(theta, self.classes_, self._q)
        total, gradient = 0.0, np.zeros_like(theta)
        count = sum(int(item.found[1:].sum()) for item in data)
        for j, item in enumerate(data):
            problem = self._problem(reward, item)
            d, _, _, _ = _solve(problem, item.start, warm[j], tol=1e-11, max_iter=200)
            warm[j] = d
            residual = np.where(item.found[1:, None], d - item.target[1:], 0.0)
            total += float(np.sum(residual**2)) / count
            gradient += self._implicit_gradient(problem, item, d, 2.0 * residual / count)
        return total, gradient

    def _problem(self, reward: Reward, item: DemoInScene) -> _Problem:
        return _build(reward, item.corridor, item.scene, self.max_slope)

    def _implicit_gradient(
        self, problem: _Problem, item: DemoInScene, d: np.ndarray, d_loss: np.ndarray
    ) -> np.ndarray:
        _, gradient, hessian = problem.derivatives(d)
        held = _held(problem, item.start, d, gradient)
        index, n_vars = _groups(~held)
        if n_vars == 0:
            return np.zeros(1 + len(self.classes_) * self._q)
        moving = index >= 0
        rhs = np.bincount(index[moving], weights=d_loss[moving], minlength=n_vars)
        h = _reduced_hessian(index, n_vars, hessian)
        try:
            adjoint = np.linalg.solve(h, rhs)
        except np.linalg.LinAlgError:
            adjoint = np.linalg.lstsq(h, rhs, rcond=None)[0]
        class_of = np.array([self.classes_.index(label) for label in item.scene.labels], int)
        d_grad = _theta_derivative(problem, d, class_of, len(self.classes_))
        spread = np.where(moving[:, :, None], adjoint[np.maximum(index, 0)][:, :, None], 0.0)
        return -np.einsum("kmp,kmp->p", spread, d_grad)

    # ------------------------------------------------------------------ fit
    def fit(self, demos: Any, scenes: Any, nominal: Any) -> IOC:
        """Learn the reward.

        Parameters
        ----------
        demos : sequence of array_like, each (n_j, q)
            Demonstrations, each recorded in its scene.
        scenes : sequence of Scene
            One scene per demonstration.
        nominal : array_like (n, q), or a sequence of them (one per demonstration)
            The nominal path the demonstrations deviate from (e.g. their
            Mean-Path, or a DMP rollout to their goal).

        Returns
        -------
        IOC
            ``self``.
        """
        check_positive(self.n_points, "n_points", integer=True)
        check_positive(self.max_iter, "max_iter", integer=True)
        if self.gradient not in ("implicit", "finite_difference"):
            raise ValueError(
                f"gradient: expected 'implicit' or 'finite_difference', got {self.gradient!r}"
            )
        if self.horizon is not None and not MIN_HORIZON <= int(self.horizon) <= MAX_HORIZON:
            raise ValueError(
                f"horizon: expected {MIN_HORIZON} <= H <= {MAX_HORIZON}, got {self.horizon}"
            )
        data = self._prepare(demos, scenes, nominal)
        seen = tuple(dict.fromkeys(label for item in data for label in item.scene.labels))
        self.classes_ = tuple(self.classes) if self.classes is not None else seen
        missing = [label for label in seen if label not in self.classes_]
        if missing:
            raise ValueError(f"classes: the scenes contain {missing[0]!r}, which is not listed")
        self._q = data[0].corridor.n_dims
        warm = [np.where(item.found[1:, None], item.target[1:], 0.0) for item in data]
        started = time.perf_counter()
        theta0 = self._initial_theta(data, warm)
        history: list[float] = []
        self.stages_ = [
            {
                "planner": "initial grid",
                "iterations": 0,
                "loss": float("nan"),
                "seconds": time.perf_counter() - started,
                "message": "best of the starting grid" if self.init is None else "init given",
            }
        ]

        # L-BFGS-B's stopping test is relative to max(|f|, 1): scale the loss to
        # about 1, the mean squared offset of the demonstrations from the nominal
        # (replaying the nominal scores 1).
        self._scale = float(
            np.mean([np.mean(item.target[item.found] ** 2) for item in data]) or 1.0
        )

        def fun(theta: np.ndarray) -> tuple[float, np.ndarray]:
            value, grad = self._objective(theta, data, warm)
            if self.gradient == "finite_difference":
                grad = self._finite_difference(
                    lambda t: self._objective(t, data, [w.copy() for w in warm])[0], theta
                )
            history.append(value)
            return value / self._scale, grad / self._scale

        started = time.perf_counter()
        result = minimize(
            fun,
            theta0,
            jac=True,
            method="L-BFGS-B",
            bounds=[(-20.0, 25.0)] * theta0.size,
            options={"maxiter": self.max_iter, "ftol": self.tol, "gtol": 1e-8},
        )
        self.stages_.append(
            {
                "planner": "full horizon",
                "iterations": int(result.nit),
                "loss": float(result.fun) * self._scale,
                "seconds": time.perf_counter() - started,
                "message": str(result.message),
            }
        )
        theta = result.x
        if self.horizon is not None:
            theta = self._refine_mpc(theta, data, history)
        self.theta_ = theta
        self.reward_ = Reward.from_theta(theta, self.classes_, self._q)
        self.loss_history_ = history
        self.loss_ = float(self.stages_[-1]["loss"])  # the last fitting stage
        self.converged_ = bool(result.success)
        return self

    @staticmethod
    def _finite_difference(loss: Any, theta: np.ndarray, eps: float = 1e-4) -> np.ndarray:
        out = np.empty_like(theta)
        for i in range(theta.size):
            step = np.zeros_like(theta)
            step[i] = eps
            out[i] = (loss(theta + step) - loss(theta - step)) / (2.0 * eps)
        return out

    def _initial_theta(self, data: list[DemoInScene], warm: list[np.ndarray]) -> np.ndarray:
        """``init``'s θ, or the best of a coarse grid of stiffnesses and widths.

        The loss has local minima in θ (a stiff path with narrow obstacles and a
        soft one with wide obstacles can both bend around a demonstration), so
        without ``init`` the loss is evaluated (plans only, no optimisation) for
        ``Q = 10 f_Q / extent²`` and widths ``0.05 f_w extent``, ``f_Q`` in 0.1 … 10,
        ``f_w`` in 0.4 … 2.5, and the fit starts from the best.
        """
        if self.init is not None:
            missing = [c for c in self.classes_ if c not in self.init.precisions]
            if missing:
                raise ValueError(f"init: has no precision for class {missing[0]!r}")
            sub = Reward(
                self.init.nominal_weight, {c: self.init.precisions[c] for c in self.classes_}
            )
            return sub.theta
        extent = max(float(np.ptp(item.corridor.points, axis=0).max()) for item in data)
        best, best_loss = None, np.inf
        for stiffness in (0.1, 0.3, 1.0, 3.0, 10.0):
            for spread in (0.4, 0.63, 1.0, 1.6, 2.5):
                width = 0.05 * spread * extent
                theta = np.array(
                    [np.log(10.0 * stiffness / extent**2)]
                    + [np.log(1.0 / width**2)] * (self._q * len(self.classes_))
                )
                loss = self._loss_only(theta, data, warm)
                if loss < best_loss:
                    best, best_loss = theta, loss
        return best

    def _loss_only(
        self, theta: np.ndarray, data: list[DemoInScene], warm: list[np.ndarray]
    ) -> float:
        reward = Reward.from_theta(theta, self.classes_, self._q)
        count = sum(int(item.found[1:].sum()) for item in data)
        total = 0.0
        for j, item in enumerate(data):
            d, _, _, _ = _solve(self._problem(reward, item), item.start, warm[j].copy())
            residual = np.where(item.found[1:, None], d - item.target[1:], 0.0)
            total += float(np.sum(residual**2)) / count
        return total

    def _refine_mpc(
        self, theta: np.ndarray, data: list[DemoInScene], history: list[float]
    ) -> np.ndarray:
        started = time.perf_counter()

        def fun(value: np.ndarray) -> tuple[float, np.ndarray]:
            loss, grad = self._objective_mpc(value, data)
            if self.gradient == "finite_difference":
                grad = self._finite_difference(lambda t: self._objective_mpc(t, data)[0], value)
            history.append(loss)
            return loss / self._scale, grad / self._scale

        result = minimize(
            fun,
            theta,
            jac=True,
            method="L-BFGS-B",
            bounds=[(-20.0, 25.0)] * theta.size,
            options={"maxiter": self.max_iter, "ftol": self.tol, "gtol": 1e-8},
        )
        self.stages_.append(
            {
                "planner": f"MPC H={int(self.horizon)}",
                "iterations": int(result.nit),
                "loss": float(result.fun) * self._scale,
                "seconds": time.perf_counter() - started,
                "message": str(result.message),
            }
        )
        return result.x

    def _objective_mpc(
        self, theta: np.ndarray, data: list[DemoInScene]
    ) -> tuple[float, np.ndarray]:
        reward = Reward.from_theta(theta, self.classes_, self._q)
        count = sum(int(item.found[1:].sum()) for item in data)
        total, gradient = 0.0, np.zeros_like(theta)
        for item in data:
            problem = self._problem(reward, item)
            class_of = np.array([self.classes_.index(label) for label in item.scene.labels], int)
            d, sensitivity = _mpc_with_sensitivity(
                problem, item, int(self.horizon), class_of, len(self.classes_)
            )
            residual = np.where(item.found[1:, None], d - item.target[1:], 0.0)
            total += float(np.sum(residual**2)) / count
            gradient += np.einsum("km,kmp->p", 2.0 * residual / count, sensitivity)
        return total, gradient

    # -------------------------------------------------------------- use
    def score(self, demos: Any, scenes: Any, nominal: Any, *, horizon: Any = "fitted") -> float:
        """Mean squared distance (units²) from held-out demonstrations to the plans in their scenes.

        Distances along the nominal's normals, as in training, but to the plans
        :meth:`plan` makes (multi-start, not started from the demonstration):
        a test score for a train/test split. ``horizon`` defaults to the fitted
        planner (full horizon, or the MPC of the staged fit).
        """
        if not hasattr(self, "reward_"):
            raise ValueError("score: fit the IOC first")
        data = self._prepare(demos, scenes, nominal)
        unknown = {label for item in data for label in item.scene.labels} - set(self.classes_)
        if unknown:
            raise ValueError(f"scenes: obstacle class {sorted(unknown)[0]!r} was never learned")
        horizon = self.horizon if horizon == "fitted" else horizon
        count = sum(int(item.found[1:].sum()) for item in data)
        total = 0.0
        for item in data:
            plan = plan_path(
                self.reward_,
                item.corridor,
                item.scene,
                horizon=horizon,
                start_offset=item.start,
                max_slope=self.max_slope,
                goal_approach=None,  # the model that was fitted
                lookahead=False,
            )
            residual = np.where(item.found[1:, None], plan.offsets[1:] - item.target[1:], 0.0)
            total += float(np.sum(residual**2)) / count
        return total

    def plan(self, nominal: Any, scene: Scene, **kwargs: Any):
        """Plan with the learned reward (:func:`lfdkit.emulate.plan_path`)."""
        kwargs.setdefault("horizon", self.horizon)
        kwargs.setdefault("n_points", self.n_points)
        kwargs.setdefault("max_slope", self.max_slope)
        kwargs.setdefault("goal_approach", None)  # the model that was fitted
        kwargs.setdefault("lookahead", False)
        return plan_path(self.reward_, nominal, scene, **kwargs)
