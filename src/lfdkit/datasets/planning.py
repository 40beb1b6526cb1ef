"""Random planning problems and an exhaustive reference cost: the planner's known answers.

The planner's tests and ``benchmarks/emulate_planner.py`` draw the same random
cases: a reward with random stiffness and widths, one of three nominal paths
(a line, an S as the thesis's artificial task, a quarter circle) and one to
eight obstacles scattered near it, in a concave pocket, or overlapping. The
reference (:func:`reference_cost`) is written independently of the planner's
code: a dynamic programme over every path on a lateral grid twice as fine
as the planner's (NumPy, SciPy's sliding minimum), polished by
SciPy's L-BFGS-B on the actions.
"""

from __future__ import annotations

import numpy as np

from lfdkit.emulate import Corridor, Reward
from lfdkit.emulate.problem import Problem
from lfdkit.model.scene import Obstacle, Scene

__all__ = ["N_POINTS", "nominal_path", "random_case", "random_case_with_radii", "reference_cost"]

#: Points of the corridor every case is planned on.
N_POINTS = 50


def nominal_path(kind: int) -> np.ndarray:
    """Nominal path ``kind`` (0 a line, 1 an S, 2 a quarter circle), 400 points, metres."""
    u = np.linspace(0.0, 1.0, 400)
    if kind == 0:
        return np.column_stack([u, np.zeros_like(u)])
    if kind == 1:  # an S, as the thesis's artificial task
        return np.column_stack([u, 0.05 * np.sin(2 * np.pi * u)])
    angle = 0.5 * np.pi * u  # a quarter circle of radius 0.7
    return np.column_stack([0.7 * np.sin(angle), 0.7 * (1.0 - np.cos(angle))])


def random_case(seed: int) -> tuple[Reward, np.ndarray, Scene]:
    """A reward with random stiffness and widths, and 1–8 obstacles near the path."""
    rng = np.random.default_rng(seed)
    along, across = rng.uniform(100.0, 1500.0), rng.uniform(300.0, 4000.0)
    reward = Reward(rng.uniform(2.0, 40.0), {"obstacle": [along, across]})
    path = nominal_path(seed % 3)
    corridor = Corridor.from_path(path, N_POINTS)
    width = 1.0 / np.sqrt(across)
    kind = rng.integers(3)
    centres = []
    if kind == 0:  # scattered, possibly overlapping
        for _ in range(rng.integers(1, 9)):
            k = rng.integers(8, N_POINTS - 8)
            lateral = rng.uniform(-2.0, 2.0) * width
            centres.append(corridor.points[k] + lateral * corridor.normals[k, 0])
    elif kind == 1:  # a concave pocket opening towards the oncoming path
        k = rng.integers(15, N_POINTS - 15)
        radius = rng.uniform(1.5, 3.5) * width
        tangent, normal = corridor.tangents[k], corridor.normals[k, 0]
        for angle in np.linspace(-0.5 * np.pi, 0.5 * np.pi, 5):
            offset = radius * (np.cos(angle) * tangent + np.sin(angle) * normal)
            centres.append(corridor.points[k] + offset + rng.uniform(-0.5, 0.5) * width * normal)
    else:  # a pair overlapping on the path plus scattered ones
        k = rng.integers(10, N_POINTS - 10)
        for shift in (-0.3, 0.3):
            centres.append(corridor.points[k] + shift * width * corridor.normals[k, 0])
        for _ in range(rng.integers(0, 4)):
            j = rng.integers(8, N_POINTS - 8)
            centres.append(corridor.points[j] + rng.uniform(-2, 2) * width * corridor.normals[j, 0])
    scene = Scene(tuple(Obstacle("obstacle", c) for c in centres))
    return reward, path, scene


def random_case_with_radii(seed: int) -> tuple[Reward, np.ndarray, Scene, float]:
    """:func:`random_case` with radii of 0–1.5 response widths and a random tool clearance."""
    reward, path, scene = random_case(20_000 + seed)
    rng = np.random.default_rng(seed)
    width = 1.0 / np.sqrt(reward.precisions["obstacle"][1, 1])
    radii = rng.uniform(0.0, 1.5, len(scene)) * width
    scene = Scene(
        tuple(Obstacle("obstacle", o.position, radius=r) for o, r in zip(scene, radii, strict=True))
    )
    return reward, path, scene, float(rng.uniform(0.0, 0.5) * width)


def reference_cost(reward: Reward, path: np.ndarray, scene: Scene, goal_approach) -> float:
    """Exhaustive reference: fine grid dynamic programme over every path, then L-BFGS-B."""
    from scipy.ndimage import minimum_filter1d  # here: the datasets load without SciPy
    from scipy.optimize import minimize

    corridor = Corridor.from_path(path, N_POINTS)
    problem = Problem.from_scene(reward, corridor, scene, 1.0, goal_approach)
    step, n = problem.max_step, problem.n
    cells = 8
    levels = step / cells * np.arange(-cells * n, cells * n + 1)
    levels = levels[np.abs(levels) <= 0.6]
    b, a = problem.b[..., 0], problem.a[..., 0, 0]  # (n, L)
    g = levels[None, None, :]
    node = problem.weight[:, None] * levels[None] ** 2 + np.exp(
        -(problem.c[..., None] + 2.0 * b[..., None] * g + a[..., None] * g * g)
    ).sum(axis=1)
    value = np.where(np.abs(levels) <= step * (1 + 1e-12), node[0], np.inf)
    table = [value]
    for k in range(1, n):
        value = node[k] + minimum_filter1d(value, 2 * cells + 1, mode="constant", cval=np.inf)
        table.append(value)
    state = int(np.argmin(np.abs(levels))) if goal_approach is not None else int(np.argmin(value))
    d = np.empty(n)
    for k in range(n - 1, -1, -1):
        d[k] = levels[state]
        if k:
            lo, hi = max(0, state - cells), min(levels.size, state + cells + 1)
            state = lo + int(np.argmin(table[k - 1][lo:hi]))

    def cost(actions: np.ndarray) -> tuple[float, np.ndarray]:
        value, gradient, _ = problem.derivatives(np.cumsum(actions)[:, None])
        return value, np.cumsum(gradient[::-1, 0])[::-1]

    result = minimize(
        cost,
        np.diff(np.concatenate([[0.0], d])),
        jac=True,
        method="L-BFGS-B",
        bounds=[(-step, step)] * n,
        options={"ftol": 1e-15, "gtol": 1e-12, "maxiter": 2000},
    )
    return float(min(result.fun, problem.cost(d[:, None])))
