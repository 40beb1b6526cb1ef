"""Tests for lfdkit.emulate.plan_path: closed forms, symmetry, optimality, local minima, errors."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.optimize import minimize

from lfdkit.emulate import Corridor, Reward, plan_path
from lfdkit.emulate.problem import Problem
from lfdkit.model.scene import Obstacle, Scene

REWARD = Reward(10.0, {"obstacle": [2500.0, 215.0]})


def straight(n: int = 200) -> np.ndarray:
    x = np.linspace(0.0, 1.0, n)
    return np.column_stack([x, np.zeros(n)])


def min_distance(points: np.ndarray, centre) -> float:
    return float(np.min(np.linalg.norm(points - np.asarray(centre), axis=1)))


def test_no_obstacle_gives_the_nominal() -> None:
    for horizon in (None, 6):
        plan = plan_path(REWARD, straight(), Scene(), horizon=horizon)
        np.testing.assert_allclose(plan.offsets, 0.0, atol=1e-14)
        np.testing.assert_allclose(plan.points, Corridor.from_path(straight()).points, atol=1e-14)


def test_a_far_obstacle_causes_no_deviation() -> None:
    plan = plan_path(REWARD, straight(), Scene((Obstacle("obstacle", [0.5, 3.0]),)))
    assert np.abs(plan.offsets).max() < 1e-12


def test_an_obstacle_on_the_path_is_passed_with_clearance() -> None:
    scene = Scene((Obstacle("obstacle", [0.5, 0.01], radius=0.02),))
    for horizon in (None, 12):
        plan = plan_path(REWARD, straight(), scene, horizon=horizon)
        assert plan.converged
        assert min_distance(plan.points, [0.5, 0.01]) > 0.02
        assert plan.offsets.min() < -0.05  # swerves away from the side the obstacle sits on
        np.testing.assert_allclose(plan.points[-1], [1.0, 0.0], atol=1e-3)


def test_mirrored_scene_gives_the_mirrored_plan() -> None:
    scene = Scene((Obstacle("obstacle", [0.45, 0.015]), Obstacle("obstacle", [0.7, -0.03])))
    for horizon in (None, 8):
        plan = plan_path(REWARD, straight(), scene, horizon=horizon)
        mirrored = plan_path(REWARD, straight(), scene.mirrored(axis=1), horizon=horizon)
        np.testing.assert_allclose(mirrored.points[:, 1], -plan.points[:, 1], atol=1e-8)
        np.testing.assert_allclose(mirrored.cost, plan.cost, rtol=1e-9)


def test_actions_stay_in_their_box() -> None:
    scene = Scene((Obstacle("obstacle", [0.5, 0.0]),))
    plan = plan_path(REWARD, straight(), scene, max_slope=0.3)
    corridor = Corridor.from_path(straight())
    assert np.abs(np.diff(plan.offsets[:, 0])).max() <= 0.3 * corridor.step * (1 + 1e-9)


def test_the_full_horizon_plan_is_a_local_optimum_scipy_cannot_improve() -> None:
    scene = Scene((Obstacle("obstacle", [0.4, 0.02]), Obstacle("obstacle", [0.62, -0.01])))
    plan = plan_path(REWARD, straight(), scene, goal_approach=None)
    corridor = Corridor.from_path(straight())
    problem = Problem.from_scene(REWARD, corridor, scene)
    actions = np.diff(plan.offsets[:, 0])

    def cost(a: np.ndarray) -> tuple[float, np.ndarray]:
        d = np.cumsum(a)[:, None]
        value, gradient, _ = problem.derivatives(d)
        return value, np.cumsum(gradient[::-1, 0])[::-1]

    bound = corridor.step
    result = minimize(
        cost,
        actions,
        jac=True,
        method="L-BFGS-B",
        bounds=[(-bound, bound)] * actions.size,
        options={"ftol": 1e-15, "gtol": 1e-12},
    )
    assert result.fun >= plan.cost - 1e-10
    np.testing.assert_allclose(np.cumsum(result.x), plan.offsets[1:, 0], atol=1e-6)


def test_concave_arrangement_is_passed_around() -> None:
    # Five obstacles forming a pocket that opens towards the oncoming path (thesis Fig 5.8).
    pocket = [[0.55, -0.06], [0.58, -0.03], [0.6, 0.0], [0.58, 0.03], [0.55, 0.06]]
    scene = Scene(tuple(Obstacle("obstacle", p, radius=0.015) for p in pocket))
    for horizon in (None, 12):
        plan = plan_path(REWARD, straight(), scene, horizon=horizon)
        for centre in pocket:
            assert min_distance(plan.points, centre) > 0.015
        assert np.abs(plan.offsets).max() > 0.06  # around the whole pocket, not into it


def test_three_dimensional_plans() -> None:
    x = np.linspace(0.0, 1.0, 100)
    nominal = np.column_stack([x, 0.1 * np.sin(np.pi * x), np.zeros_like(x)])
    reward = Reward(10.0, {"obstacle": [2500.0, 215.0, 215.0]})
    scene = Scene((Obstacle("obstacle", [0.5, 0.1, 0.01], radius=0.02),))
    plan = plan_path(reward, nominal, scene)
    assert plan.offsets.shape == (100, 2)
    assert min_distance(plan.points, [0.5, 0.1, 0.01]) > 0.02
    mpc = plan_path(reward, nominal, scene, horizon=10)
    assert min_distance(mpc.points, [0.5, 0.1, 0.01]) > 0.02


def test_plans_are_deterministic() -> None:
    scene = Scene((Obstacle("obstacle", [0.5, 0.0]),))
    a = plan_path(REWARD, straight(), scene, horizon=8)
    b = plan_path(REWARD, straight(), scene, horizon=8)
    np.testing.assert_array_equal(a.points, b.points)


def test_bad_requests_are_refused() -> None:
    scene = Scene((Obstacle("obstacle", [0.5, 0.0]),))
    with pytest.raises(ValueError, match="horizon: expected 4 <= H <= 12"):
        plan_path(REWARD, straight(), scene, horizon=3)
    with pytest.raises(ValueError, match="horizon: expected 4 <= H <= 12"):
        plan_path(REWARD, straight(), scene, horizon=13)
    with pytest.raises(ValueError, match="start: lies inside obstacle 0"):
        plan_path(REWARD, straight(), Scene((Obstacle("obstacle", [0.0, 0.0]),)))
    with pytest.raises(ValueError, match=r"inside obstacle 0 .*within its radius 0.05 plus"):
        plan_path(REWARD, straight(), Scene((Obstacle("obstacle", [0.03, 0.02], radius=0.05),)))
    # Physically clear of a small obstacle: planned even though its response reaches the start.
    plan_path(REWARD, straight(), Scene((Obstacle("obstacle", [0.01, 0.0], radius=0.005),)))
    with pytest.raises(ValueError, match="class 'cup' was never learned"):
        plan_path(REWARD, straight(), Scene((Obstacle("cup", [0.5, 0.0]),)))
    with pytest.raises(ValueError, match="nominal: contains NaN"):
        plan_path(REWARD, np.array([[0.0, 0.0], [np.nan, 1.0], [2.0, 0.0]]), scene)
    with pytest.raises(ValueError, match="3-D obstacles for a 2-D"):
        plan_path(REWARD, straight(), Scene((Obstacle("obstacle", [0.5, 0.0, 0.0]),)))


def test_goal_approach_brings_a_swerving_plan_back_to_the_goal() -> None:
    # A lateral obstacle late on the path leaves the thesis's plan beside the goal.
    reward = Reward(10.0, {"obstacle": [15.0, 1000.0]})
    scene = Scene((Obstacle("obstacle", [0.6, 0.01], radius=0.02),))
    for horizon in (None, 8):
        thesis = dict(horizon=horizon, goal_approach=None)
        free_end = plan_path(reward, straight(), scene, **thesis).offsets[-1, 0]
        assert abs(free_end) > 0.02
        for approach in (0.15, "auto"):  # "auto" is the default
            plan = plan_path(reward, straight(), scene, horizon=horizon, goal_approach=approach)
            np.testing.assert_allclose(plan.points[-1], [1.0, 0.0], atol=1e-4)
            assert plan.goal_error < 1e-4
            assert min_distance(plan.points, [0.6, 0.01]) > 0.02
        # before the approach the plan is the thesis's (same swerve past the obstacle)
        unconstrained = plan_path(reward, straight(), scene, **thesis)
        k = int(0.4 * (len(plan.points) - 1))
        np.testing.assert_allclose(plan.offsets[:k], unconstrained.offsets[:k], atol=2e-3)


def test_goal_weights_ramp_smoothly_from_q_to_the_gain() -> None:
    from lfdkit.emulate.problem import GOAL_GAIN, goal_weights

    corridor = Corridor.from_path(straight(), 101)  # step 0.01
    np.testing.assert_array_equal(goal_weights(corridor, 3.0, None), np.full(100, 3.0))
    w = goal_weights(corridor, 3.0, 0.2)
    assert np.all(w[:80] == 3.0)  # positions up to 0.8
    assert np.all(np.diff(w) >= 0.0)
    assert w[-1] == pytest.approx(3.0 * (1.0 + GOAL_GAIN))
    with pytest.raises(ValueError, match="goal_approach"):
        goal_weights(corridor, 3.0, -0.1)


def test_a_nominal_of_far_more_points_than_the_plan_is_resampled_with_a_warning():
    # A 250-point nominal planned without n_points gave a silent 100-point plan (e3a8c41).
    x = np.linspace(0.0, 1.0, 250)
    nominal = np.column_stack([x, 0.1 * np.sin(np.pi * x)])
    reward = Reward(5.0, {"cup": [400.0, 400.0]})
    scene = Scene((Obstacle("cup", [0.5, 0.12], 0.02),))
    with pytest.warns(
        UserWarning, match=r"its 250 points are resampled to a plan of 100.*n_points=250"
    ):
        plan = plan_path(reward, nominal, scene)
    assert plan.points.shape == (100, 2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert plan_path(reward, nominal, scene, n_points=250).points.shape == (250, 2)
        np.testing.assert_array_equal(
            plan_path(reward, nominal, scene, n_points=100).points, plan.points
        )
        # Up to twice the plan's points (a curve passed densely), or fewer: unsaid.
        assert plan_path(reward, nominal[:200], scene).points.shape == (100, 2)
        assert plan_path(reward, nominal[::5], scene).points.shape == (100, 2)


@pytest.mark.parametrize("inside", [0.005, 0.011, 0.02])
def test_a_response_along_the_path_bends_with_it_and_keeps_the_short_way_round(inside) -> None:
    # A trough (an arc of radius 0.3 m about (0, 0.3)) and a box `inside` the bend at its
    # lowest point; the box's response ten times as long along the path as across it.
    # Kept straight (world axes, or turned only where the box is passed) its band lies
    # across the outside of the bend on both sides, and the plan goes the long way round,
    # inside the bend; along the path it bends with the trough: the short way, outside.
    angles = np.radians(np.linspace(-150.0, -30.0, 200))
    nominal = np.column_stack([0.3 * np.cos(angles), 0.3 + 0.3 * np.sin(angles)])
    box = Scene((Obstacle("box", [0.0, inside], radius=0.05),))
    sides = {}
    for along in (False, True):
        reward = Reward(20.0, {"box": [40.0, 4000.0]}, along_path=along)
        plan = plan_path(reward, nominal, box, horizon=8, lookahead=False, clearance=0.005)
        lowest = plan.points[np.argmin(np.abs(plan.points[:, 0]))]
        sides[along] = "inside" if lowest[1] > inside else "outside"
        assert plan.clearance.min() >= 0.005 - 1e-9
    assert sides == {False: "inside", True: "outside"}
