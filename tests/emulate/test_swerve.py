"""Tests for the swerve model (issue 26): a class's response stretched along the path.

Known answers: the shift's closed form on a straight nominal, the thesis's
model unchanged to the bit without a swerve, exact IOC gradients against
finite differences (full horizon and MPC), and a demonstrator of the model's
own making recovered from its demonstrations.
"""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.emulate import IOC, Reward, plan_path
from lfdkit.emulate.ioc import TrainingLoss, _finite_difference, prepare_demos
from lfdkit.emulate.problem import Corridor, Problem, swerve_shifts
from lfdkit.model.scene import Obstacle, Scene

BASE = Reward(10.0, {"cup": [2500.0, 400.0]})
#: Starts early (stretched 1.8 before the cup) and returns slowly (2.5 after).
SWERVING = Reward(10.0, {"cup": [2500.0, 400.0]}, swerve={"cup": [1.8, 2.5]})


def nominal() -> np.ndarray:
    x = np.linspace(0.0, 1.0, 200)
    return np.column_stack([x, 0.1 * np.sin(np.pi * x)])


def demonstrations(reward: Reward, n: int = 5, horizon: int | None = None, seed: int = 0):
    rng = np.random.default_rng(seed)
    path = nominal()
    demos, scenes = [], []
    for _ in range(n):
        i = int(rng.uniform(0.3, 0.6) * (len(path) - 1))
        scene = Scene((Obstacle("cup", path[i] + [0.0, rng.uniform(-0.03, 0.03)]),))
        plan = plan_path(reward, path, scene, horizon=horizon, goal_approach=None, lookahead=False)
        demos.append(plan.points)
        scenes.append(scene)
    return demos, scenes


def test_shift_is_the_along_path_warp_on_a_straight_nominal() -> None:
    # Points on the x axis, an anchor at x = 0.5: τ = x − 0.5, τ' = τ / w.
    x = np.linspace(0.0, 1.0, 11)
    rel = np.column_stack([x - 0.5, np.full(11, 0.2)])[:, None, :]
    tangents = np.tile([1.0, 0.0], (11, 1))
    shift, rate, side = swerve_shifts(rel, tangents, np.array([[2.0, 4.0]]))
    tau = x - 0.5
    expected = np.where(tau < 0, tau / 2.0, tau / 4.0)
    np.testing.assert_allclose((rel + shift)[:, 0, 0], expected, atol=1e-15)
    np.testing.assert_array_equal(shift[:, 0, 1], 0.0)  # nothing across the path
    np.testing.assert_array_equal(side[:, 0], (tau >= 0).astype(int))
    np.testing.assert_allclose(rate[:, 0, 0], -expected, atol=1e-15)


def test_without_a_swerve_the_problem_is_the_thesis_one_to_the_bit() -> None:
    corridor = Corridor.from_path(nominal(), 100)
    scene = Scene((Obstacle("cup", [0.45, 0.1]),))
    plain = Problem.from_scene(BASE, corridor, scene)
    flat = Problem.from_scene(Reward(10.0, BASE.precisions, {"cup": [1.0, 1.0]}), corridor, scene)
    assert plain.shift is None
    for name in ("c", "b", "a"):
        np.testing.assert_array_equal(getattr(plain, name), getattr(flat, name))
    a = plan_path(BASE, nominal(), scene, horizon=8, goal_approach=None, lookahead=False)
    b = plan_path(BASE, nominal(), scene, horizon=8, goal_approach=None, lookahead=False)
    np.testing.assert_array_equal(a.points, b.points)


def test_a_later_return_keeps_the_plan_away_longer_after_the_obstacle() -> None:
    scene = Scene((Obstacle("cup", [0.4, 0.09]),))
    plain = plan_path(BASE, nominal(), scene, goal_approach=None, lookahead=False)
    slow = Reward(10.0, BASE.precisions, {"cup": [1.0, 3.0]})
    late = plan_path(slow, nominal(), scene, goal_approach=None, lookahead=False)
    offset_plain, offset_late = np.abs(plain.offsets[:, 0]), np.abs(late.offsets[:, 0])
    after = slice(55, 80)  # past the cup (at about point 40)
    before = slice(10, 30)
    assert np.all(offset_late[after] > offset_plain[after])
    np.testing.assert_allclose(offset_late[before], offset_plain[before], atol=2e-3)


def training_loss(demos, scenes) -> TrainingLoss:
    return TrainingLoss(prepare_demos(demos, scenes, nominal(), 80), ("cup",), 1.0)


def swerve_theta(reward: Reward) -> np.ndarray:
    return np.concatenate([reward.theta, reward.swerve_theta])


def test_full_horizon_gradient_with_a_swerve_matches_finite_differences() -> None:
    demos, scenes = demonstrations(SWERVING, 2)
    loss = training_loss(demos, scenes)
    theta = swerve_theta(SWERVING) + np.array([0.2, -0.2, 0.3, -0.3, 0.25])
    warm = [np.where(d.found[1:, None], d.target[1:], 0.0) for d in loss.data]
    _, gradient = loss.full_horizon(theta, [w.copy() for w in warm])
    fd = _finite_difference(
        lambda t: loss.full_horizon(t, [w.copy() for w in warm])[0], theta, eps=1e-3
    )
    assert np.all(np.abs(gradient[3:]) > 1e-5)  # the swerve's columns are not trivially zero
    np.testing.assert_allclose(gradient, fd, rtol=1e-5, atol=1e-9)


def test_mpc_gradient_with_a_swerve_matches_finite_differences() -> None:
    demos, scenes = demonstrations(SWERVING, 2, horizon=8)
    loss = training_loss(demos, scenes)
    theta = swerve_theta(SWERVING) + np.array([0.2, -0.2, 0.3, -0.3, 0.25])
    _, gradient = loss.mpc(theta, 8)
    fd = _finite_difference(lambda t: loss.mpc(t, 8)[0], theta)
    assert np.all(np.abs(gradient[3:]) > 1e-5)
    np.testing.assert_allclose(gradient, fd, rtol=1e-4, atol=1e-9)


def test_a_swerving_demonstrator_is_recovered() -> None:
    # Noise-free demonstrations of the swerve model; the fit starts from a symmetric
    # reward off the true one (as the skill's does, from the thesis's fit).
    demos, scenes = demonstrations(SWERVING, 5)
    start = Reward(6.0, {"cup": [1500.0, 700.0]})
    ioc = IOC(init=start, swerve=True, n_starts=1, n_points=80, diagnose=False)
    ioc.fit(demos, scenes, nominal())
    learned = ioc.reward_
    np.testing.assert_allclose(learned.swerve["cup"], SWERVING.swerve["cup"], rtol=0.05)
    np.testing.assert_allclose(
        np.diag(learned.precisions["cup"]), np.diag(SWERVING.precisions["cup"]), rtol=0.05
    )
    assert learned.nominal_weight == pytest.approx(SWERVING.nominal_weight, rel=0.05)
    # The thesis's symmetric model cannot replay them as closely.
    thesis = IOC(init=start, n_starts=1, n_points=80, diagnose=False).fit(demos, scenes, nominal())
    assert ioc.loss_ < 0.1 * thesis.loss_


@pytest.mark.filterwarnings("ignore:the reward fit did not converge")  # 5 iterations: enough here
def test_swerve_only_fits_the_stretches_and_holds_q_and_the_precisions() -> None:
    demos, scenes = demonstrations(SWERVING, 2)
    start = Reward(6.0, {"cup": [1500.0, 700.0]})
    ioc = IOC(init=start, swerve=True, swerve_only=True, n_starts=1, n_points=50, max_iter=5)
    ioc.set_params(diagnose=False).fit(demos, scenes, nominal())
    learned = ioc.reward_
    # held to the bit (the data's units and back: a rounding at most)
    assert learned.nominal_weight == pytest.approx(6.0, rel=1e-12)
    np.testing.assert_allclose(np.diag(learned.precisions["cup"]), [1500.0, 700.0], rtol=1e-12)
    # the stretches moved toward the person's (it starts early and returns slowly)
    before, after = learned.swerve["cup"]
    assert before > 1.2 and after > 1.5
    assert ioc.loss_ < ioc.training_loss(start)


def test_swerve_only_without_init_is_refused_in_one_line() -> None:
    path = nominal()  # refused before the data are looked at
    with pytest.raises(ValueError, match=r"^swerve_only: needs swerve=True and an init"):
        IOC(swerve_only=True, swerve=True).fit([path], [Scene()], path)


def test_the_swerve_wall_gradient_matches_finite_differences() -> None:
    ioc = IOC(swerve=True)
    ioc.classes_, ioc._q = ("cup", "box"), 2
    # Q, two precisions a class, then (before, after) a class: one stretch beyond 5.
    theta = np.array([1.0, 2.0, 3.0, 2.5, 1.5, np.log(8.0), 0.1, -0.2, np.log(0.1)])
    value, gradient = ioc._penalty(theta)
    assert value == pytest.approx(np.log(8.0 / 5.0) ** 2 + np.log(0.2 / 0.1) ** 2)
    fd = _finite_difference(lambda t: ioc._penalty(t)[0], theta, eps=1e-6)
    np.testing.assert_allclose(gradient, fd, atol=1e-8)


@pytest.mark.filterwarnings("ignore:the reward fit did not converge")  # 5 iterations: enough here
def test_swerve_shape_fits_the_widths_with_the_stretches_and_holds_q() -> None:
    demos, scenes = demonstrations(SWERVING, 2)
    start = Reward(6.0, {"cup": [1500.0, 700.0]})
    ioc = IOC(init=start, swerve=True, swerve_only=True, swerve_shape=True, n_starts=1)
    ioc.set_params(n_points=50, max_iter=5, diagnose=False).fit(demos, scenes, nominal())
    learned = ioc.reward_
    assert learned.nominal_weight == pytest.approx(6.0, rel=1e-12)  # held
    # the width across moved toward the person's (400; along, the width trades off with the
    # stretches), and the loss fell below the
    # stretches-only fit's from the same start
    p_across = np.diag(learned.precisions["cup"])[1]
    assert p_across < 650.0
    only = IOC(init=start, swerve=True, swerve_only=True, n_starts=1)
    only.set_params(n_points=50, max_iter=5, diagnose=False).fit(demos, scenes, nominal())
    assert ioc.loss_ < only.loss_


def test_swerve_shape_without_swerve_only_is_refused_in_one_line() -> None:
    path = nominal()
    with pytest.raises(ValueError, match=r"^swerve_shape: fits the precisions with the stretches"):
        IOC(init=BASE, swerve=True, swerve_shape=True).fit([path], [Scene()], path)
