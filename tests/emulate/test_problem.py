"""Tests for lfdkit.emulate.problem: the NumPy cost against the compiled one, windows, solve."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.emulate import Corridor, Reward
from lfdkit.emulate._problem_kernels import planner_derivatives
from lfdkit.emulate.problem import Problem
from lfdkit.model.scene import Obstacle, Scene


def case(q: int, seed: int) -> tuple[Problem, np.ndarray]:
    """A curved nominal with obstacles beside it, and random offsets that reach them."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, 120)
    columns = [t, 0.1 * np.sin(np.pi * t)] + ([0.05 * t] if q == 3 else [])
    corridor = Corridor.from_path(np.column_stack(columns), 60)
    reward = Reward(10.0, {"a": rng.uniform(200.0, 3000.0, q), "b": rng.uniform(200.0, 3000.0, q)})
    obstacles = []
    for j in rng.integers(5, 55, size=4):
        lateral = rng.uniform(-0.04, 0.04, q - 1) @ corridor.normals[j]
        obstacles.append(
            Obstacle(str(rng.choice(["a", "b"])), corridor.points[j] + lateral, radius=0.005)
        )
    problem = Problem.from_scene(reward, corridor, Scene(tuple(obstacles)), 1.0, "auto")
    d = rng.uniform(-0.03, 0.03, (problem.n, problem.m))
    return problem, d


@pytest.mark.parametrize("q", [2, 3])
@pytest.mark.parametrize("seed", range(3))
def test_numpy_derivatives_are_the_compiled_ones(q: int, seed: int) -> None:
    # The NumPy form (reference solvers, checks) and the kernel the Newton solver
    # uses agree to round-off: same cost, gradient and Hessian blocks.
    problem, d = case(q, seed)
    cost, gradient, hessian = problem.derivatives(d)
    compiled_gradient = np.empty_like(d)
    compiled_hessian = np.empty((problem.n, problem.m, problem.m))
    compiled_cost = planner_derivatives(
        *problem.kernel_arguments(), d, compiled_gradient, compiled_hessian
    )
    assert cost == pytest.approx(compiled_cost, rel=1e-12)
    np.testing.assert_allclose(
        gradient, compiled_gradient, rtol=1e-12, atol=1e-12 * np.abs(compiled_gradient).max()
    )
    np.testing.assert_allclose(
        hessian, compiled_hessian, rtol=1e-12, atol=1e-12 * np.abs(compiled_hessian).max()
    )
    assert problem.cost(d) == pytest.approx(problem.total_cost(d), rel=1e-12)


@pytest.mark.parametrize("q", [2, 3])
def test_a_window_is_the_problem_of_its_offsets(q: int) -> None:
    problem, d = case(q, 1)
    window = problem.window(10, 22)
    assert (window.n, window.m) == (12, problem.m)
    full = problem.derivatives(d)
    part = window.derivatives(d[10:22])
    np.testing.assert_array_equal(part[1], full[1][10:22])
    np.testing.assert_array_equal(part[2], full[2][10:22])


@pytest.mark.parametrize("q", [2, 3])
def test_solve_is_stationary_on_its_free_actions(q: int) -> None:
    # At the solver's optimum the NumPy gradient, summed over the offsets an action
    # moves, vanishes wherever the action is inside its box.
    problem, _ = case(q, 2)
    d, cost, n_iter, converged = problem.solve(
        np.zeros(problem.m), np.zeros((problem.n, problem.m))
    )
    assert converged and n_iter > 0
    assert cost == pytest.approx(problem.total_cost(d), rel=1e-12)
    _, gradient, _ = problem.derivatives(d)
    action_gradient = np.cumsum(gradient[::-1], axis=0)[::-1]
    actions = np.diff(np.vstack([np.zeros((1, problem.m)), d]), axis=0)
    free = np.abs(actions) < problem.max_step * (1.0 - 1e-9)
    scale = 1.0 + 2.0 * problem.weight.min() * problem.max_step
    assert np.abs(action_gradient[free]).max() <= 1e-8 * scale
