"""The straightforward SciPy IOC the emulation benchmark times lfdkit against (section 4 (c)).

Each inner plan by ``scipy.optimize.minimize(method="L-BFGS-B")`` over the
bounded actions, with the cost and gradient of
:meth:`lfdkit.emulate.problem.Problem.derivatives` (the NumPy form of the
planner's cost); the outer loop L-BFGS-B on the same scaled loss with SciPy's
finite-difference gradient. Also used by ``benchmarks/emulate_robustness.py``.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.optimize import minimize

from lfdkit.emulate import Corridor, Reward
from lfdkit.emulate.problem import Problem

from .common import reward_record
from .spec import SCIPY_FD_STEP


class _OutOfTime(Exception):
    pass


def demo_targets(corridor: Corridor, demos) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """(start offset, lateral offsets, found) of each demonstration, as IOC prepares them."""
    out = []
    for demo in demos:
        offsets, found = corridor.offsets_of(demo)
        start = offsets[0] if found[0] else offsets[np.argmax(found)]
        out.append((start, offsets, found))
    return out


def scipy_plan(problem, d0: np.ndarray, init: np.ndarray, **options) -> np.ndarray:
    """Offsets minimising the planner's cost by L-BFGS-B over the bounded actions."""
    n, m = problem.n, problem.m
    bound = problem.max_step

    def fun(actions):
        d = d0 + np.cumsum(actions.reshape(n, m), axis=0)
        cost, gradient, _ = problem.derivatives(d)
        return cost, np.cumsum(gradient[::-1], axis=0)[::-1].ravel()

    a0 = np.clip(np.diff(np.vstack([d0[None], init]), axis=0), -bound, bound).ravel()
    result = minimize(
        fun,
        a0,
        jac=True,
        method="L-BFGS-B",
        bounds=[(-bound, bound)] * a0.size,
        options={"maxiter": 1000, "ftol": 1e-12, "gtol": 1e-9, **options},
    )
    return d0 + np.cumsum(result.x.reshape(n, m), axis=0)


def scipy_mpc(problem, d0: np.ndarray, guide: np.ndarray, horizon: int) -> np.ndarray:
    """Receding horizon: each window by :func:`scipy_plan`, warm-started from the last one."""
    n, m = problem.n, problem.m
    offsets = np.zeros((n, m))
    anchor = d0
    guess = guide[: min(horizon, n)].copy()
    for k in range(n):
        stop = min(k + horizon, n)
        guess = guess[: stop - k]
        if guess.shape[0] < stop - k:
            guess = np.vstack([guess, np.repeat(guess[-1:], stop - k - guess.shape[0], axis=0)])
        w = scipy_plan(problem.window(k, stop), anchor, guess)
        offsets[k] = w[0]
        anchor = w[0]
        guess = np.vstack([w[1:], w[-1:]]) if w.shape[0] > 1 else w
    return offsets


def scipy_ioc(demos, scenes, nominal, classes, theta0, horizon, limit_s: float) -> dict:
    """The straightforward SciPy IOC of section 4 (c); stops after ``limit_s`` seconds."""
    corridor = Corridor.from_path(nominal, 100)
    items = demo_targets(corridor, demos)
    q = corridor.n_dims
    count = sum(int(f[1:].sum()) for _, _, f in items)
    scale = float(np.mean([np.mean(off[f] ** 2) for _, off, f in items]))
    best = {"loss": np.inf, "theta": np.array(theta0, float)}
    evaluations, iterations = [0], [0]
    start = time.perf_counter()

    def loss(theta: np.ndarray) -> float:
        if time.perf_counter() - start > limit_s:
            raise _OutOfTime
        reward = Reward.from_theta(theta, classes, q)
        total = 0.0
        for (d0, offsets, found), scene in zip(items, scenes, strict=True):
            problem = Problem.from_scene(reward, corridor, scene)
            guide = np.where(found[1:, None], offsets[1:], 0.0)
            if horizon is None:
                d = scipy_plan(problem, d0, guide)
            else:
                d = scipy_mpc(problem, d0, guide, horizon)
            total += float(np.sum(np.where(found[1:, None], d - offsets[1:], 0.0) ** 2)) / count
        evaluations[0] += 1
        if total < best["loss"]:
            best.update(loss=total, theta=np.array(theta))
        return total / scale

    def callback(*_):
        iterations[0] += 1

    finished, message = True, ""
    try:
        result = minimize(
            loss,
            np.array(theta0, float),
            method="L-BFGS-B",
            bounds=[(-20.0, 25.0)] * len(theta0),
            callback=callback,
            options={"maxiter": 200, "ftol": 1e-10, "gtol": 1e-12, "eps": SCIPY_FD_STEP},
        )
        message = str(result.message)
        theta = result.x
    except _OutOfTime:
        finished, message = False, f"did not finish in {limit_s:.0f} s"
        theta = best["theta"]
    seconds = time.perf_counter() - start
    return {
        "planner": "full horizon" if horizon is None else f"MPC H={horizon}",
        "finished": finished,
        "seconds": seconds,
        "message": message,
        "outer_iterations": iterations[0],
        "loss_evaluations": evaluations[0],
        "loss": float(best["loss"]),
        "theta": np.asarray(theta).tolist(),
        "reward": reward_record(Reward.from_theta(theta, classes, q)),
    }


def default_start(nominal: np.ndarray, classes, q: int) -> Reward:
    """lfdkit's former default start: ``Q = 10 / extent²``, every width 5 % of the extent."""
    points = Corridor.from_path(nominal, 100).points
    extent = float(np.ptp(points, axis=0).max())
    width = 0.05 * extent
    return Reward(10.0 / extent**2, {c: np.full(q, 1.0 / width**2) for c in classes})
