"""Tests for lfdkit.emulate.IOC: exact gradients, parameter recovery, errors."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.emulate import IOC, Obstacle, Reward, Scene, plan_path

TRUE = Reward(10.0, {"obstacle": [2500.0, 215.0]})


def nominal() -> np.ndarray:
    x = np.linspace(0.0, 1.0, 300)
    return np.column_stack([x, 0.2 * np.sin(np.pi * x)])


def demonstrations(n: int = 6, horizon: int | None = None, seed: int = 0):
    rng = np.random.default_rng(seed)
    path = nominal()
    demos, scenes = [], []
    for _ in range(n):
        i = int(rng.uniform(0.25, 0.75) * (len(path) - 1))
        scene = Scene((Obstacle("obstacle", path[i] + [0.0, rng.uniform(-0.03, 0.03)]),))
        demos.append(
            plan_path(
                TRUE, path, scene, horizon=horizon, goal_approach=None, lookahead=False
            ).points
        )
        scenes.append(scene)
    return demos, scenes


def prepared(ioc: IOC, demos, scenes):
    data = ioc._prepare(demos, scenes, nominal())
    ioc.classes_, ioc._q = ("obstacle",), 2
    return data


def finite_difference(fun, theta: np.ndarray, eps: float = 1e-4) -> np.ndarray:
    # Central differences: truncation O(eps²) about 1e-8 here; smaller steps meet the
    # inner solver's tolerance.
    out = np.empty_like(theta)
    for i in range(theta.size):
        step = np.zeros_like(theta)
        step[i] = eps
        out[i] = (fun(theta + step) - fun(theta - step)) / (2 * eps)
    return out


def test_full_horizon_gradient_matches_finite_differences() -> None:
    demos, scenes = demonstrations(4)
    ioc = IOC()
    data = prepared(ioc, demos, scenes)
    theta = TRUE.theta + np.array([0.3, -0.2, 0.4])
    warm = [np.where(d.found[1:, None], d.target[1:], 0.0) for d in data]
    _, gradient = ioc._objective(theta, data, [w.copy() for w in warm])
    # A step of 1e-3: truncation about 2e-7 here, while at 1e-4 the difference of two
    # losses meets the inner solver's tolerance (1e-11 on the gradient).
    fd = finite_difference(
        lambda t: ioc._objective(t, data, [w.copy() for w in warm])[0], theta, eps=1e-3
    )
    np.testing.assert_allclose(gradient, fd, rtol=1e-6)


def test_mpc_gradient_matches_finite_differences() -> None:
    demos, scenes = demonstrations(3, horizon=8)
    ioc = IOC(horizon=8)
    data = prepared(ioc, demos, scenes)
    theta = TRUE.theta + np.array([0.3, -0.2, 0.4])
    _, gradient = ioc._objective_mpc(theta, data)
    fd = finite_difference(lambda t: ioc._objective_mpc(t, data)[0], theta)
    np.testing.assert_allclose(gradient, fd, rtol=1e-5)


def test_recovers_the_true_parameters_from_noise_free_demonstrations() -> None:
    demos, scenes = demonstrations(6)
    ioc = IOC().fit(demos, scenes, nominal())
    np.testing.assert_allclose(np.exp(ioc.theta_), np.exp(TRUE.theta), rtol=1e-2)
    assert ioc.loss_ < 1e-10
    assert ioc.reward_.classes == ("obstacle",)


def test_staged_fit_recovers_mpc_demonstrations() -> None:
    demos, scenes = demonstrations(4, horizon=8)
    ioc = IOC(horizon=8, max_iter=30).fit(demos, scenes, nominal())
    assert [stage["planner"] for stage in ioc.stages_] == [
        "initial grid",
        "full horizon",
        "MPC H=8",
    ]
    assert ioc.stages_[-1]["loss"] < 1e-12  # the MPC demonstrator is explained exactly
    np.testing.assert_allclose(np.exp(ioc.theta_), np.exp(TRUE.theta), rtol=1e-3)


def test_fit_is_deterministic() -> None:
    demos, scenes = demonstrations(3)
    a = IOC(max_iter=5).fit(demos, scenes, nominal())
    b = IOC(max_iter=5).fit(demos, scenes, nominal())
    np.testing.assert_array_equal(a.theta_, b.theta_)


def test_bad_inputs_are_refused() -> None:
    demos, scenes = demonstrations(2)
    with pytest.raises(ValueError, match="scenes: 1 scenes for 2 demonstrations"):
        IOC().fit(demos, scenes[:1], nominal())
    with pytest.raises(ValueError, match="horizon"):
        IOC(horizon=20).fit(demos, scenes, nominal())
    with pytest.raises(ValueError, match="classes: the scenes contain 'obstacle'"):
        IOC(classes=("cup",)).fit(demos, scenes, nominal())
    with pytest.raises(TypeError, match=r"scenes\[0\]: expected a Scene"):
        IOC().fit(demos, [None, scenes[1]], nominal())
    far = np.column_stack([np.linspace(0, 1, 50), np.full(50, 5.0)])
    with pytest.raises(ValueError, match=r"demos\[0\]: crosses only"):
        IOC().fit([far, demos[1]], scenes, nominal())


def test_score_on_held_out_demonstrations() -> None:
    demos, scenes = demonstrations(6)
    ioc = IOC().fit(demos[:4], scenes[:4], nominal())
    full = ioc.score(demos[4:], scenes[4:], nominal())
    assert full < 1e-10
    # The demonstrator planned the full horizon: a receding horizon explains it less well.
    assert full < ioc.score(demos[4:], scenes[4:], nominal(), horizon=8) < 1e-2
    with pytest.raises(ValueError, match="never learned"):
        ioc.score(demos[4:5], [Scene((Obstacle("cup", [0.5, 0.2]),))], nominal())
