"""Tests for lfdkit.emulate.problem: the NumPy cost against the compiled one, windows, solve."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from lfdkit.core.memo import DigestMemo
from lfdkit.emulate import Corridor, Reward, _problem_kernels
from lfdkit.emulate._problem_kernels import (
    LISTED_TERMS,
    live_terms,
    planner_cost,
    planner_derivatives,
    point_cost,
)
from lfdkit.emulate.problem import Problem, _obstacle_terms
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
@pytest.mark.parametrize("clearance", [None, 0.002])
def test_planner_cost_is_its_points_costs_to_the_bit(q: int, clearance: float | None) -> None:
    # The line search's cost is written out on the offsets' rows; it must stay the sum
    # of point_cost (what the grid search scores) over the points, to the bit, with
    # and without hard radii (fits are reproducible to the bit across this rewrite).
    problem, d = case(q, 0)
    if clearance is not None:
        corridor = Corridor.from_path(problem_nominal(q), 60)
        reward = Reward(10.0, {"a": np.full(q, 900.0), "b": np.full(q, 400.0)})
        scene = Scene(
            (
                Obstacle("a", corridor.points[20] + 0.021 * corridor.normals[20, 0], radius=0.01),
                Obstacle("b", corridor.points[40] - 0.022 * corridor.normals[40, 0], radius=0.01),
            )
        )
        problem = Problem.from_scene(reward, corridor, scene, 1.0, "auto", clearance=clearance)
        d = np.random.default_rng(1).uniform(-0.001, 0.001, (problem.n, problem.m))
    args = problem.kernel_arguments()
    bumps = np.arange(problem.c.shape[1])
    hards = np.arange(problem.rr.shape[1])
    assert len(hards) == (0 if clearance is None else 2)
    total = 0.0
    for k in range(problem.n):
        total += point_cost(*args, k, np.ascontiguousarray(d[k]), bumps, hards)
    value = planner_cost(*args, d)
    assert np.isfinite(value) and value == total
    if clearance is not None:  # the barrier is in it
        assert value > problem.cost(d)


def problem_nominal(q: int) -> np.ndarray:
    t = np.linspace(0.0, 1.0, 120)
    return np.column_stack([t, 0.1 * np.sin(np.pi * t)] + ([0.05 * t] if q == 3 else []))


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


@pytest.mark.parametrize("q", [2, 3])
@pytest.mark.parametrize("kind", ["diagonal", "full", "one class"])
def test_obstacle_terms_are_their_definitions(q: int, kind: str) -> None:
    # The fast forms (diagonal scaling, batched products, A once per run of anchors
    # sharing a precision) against c = rᵀPr, b = N P r, A = N P Nᵀ written out.
    rng = np.random.default_rng(q)
    n, n_anchors = 30, 7
    problem, _ = case(q, 0)
    normals = problem.normals[:n]
    rel = rng.normal(scale=0.1, size=(n, n_anchors, q))
    if kind == "full":
        root = rng.normal(size=(n_anchors, q, q))
        precision = root @ root.transpose(0, 2, 1) * 100.0
    else:
        classes = [rng.uniform(50.0, 500.0, q) for _ in range(3)]
        runs = [0, 0, 1, 1, 1, 2, 0] if kind == "diagonal" else [0] * n_anchors
        precision = np.array([np.diag(classes[j]) for j in runs])
    c, b, a = _obstacle_terms(rel, normals, precision)
    pr = np.einsum("lij,klj->kli", precision, rel)
    np.testing.assert_allclose(c, np.einsum("kli,kli->kl", rel, pr), rtol=1e-14)
    expected_b = np.einsum("kmq,klq->klm", normals, pr)
    np.testing.assert_allclose(b, expected_b, rtol=0, atol=1e-14 * np.abs(expected_b).max())
    expected_a = np.einsum("kmq,lqr,knr->klmn", normals, precision, normals)
    np.testing.assert_allclose(a, expected_a, rtol=0, atol=1e-14 * np.abs(expected_a).max())
    assert all(x.flags.c_contiguous for x in (c, b, a))  # as the kernels take them
    empty = _obstacle_terms(rel[:, :0], normals, precision[:0])
    assert [x.shape for x in empty] == [(n, 0), (n, 0, q - 1), (n, 0, q - 1, q - 1)]


# ------------------------------------------------------------------ issue 34
@pytest.mark.parametrize("seed", range(4))
def test_block_tree_solve_matches_a_dense_solve_and_its_numpy_twin(seed):
    """The 3-D Newton step's O(n) elimination of grouped 2 x 2 blocks against the dense
    matrix it stands for (random held actions, so groups of one component span several
    of the other's), and the NumPy twin to the bit; an indefinite matrix is refused."""
    from lfdkit.emulate import _planner_numpy
    from lfdkit.emulate._problem_kernels import block_tree_solve, offset_groups

    rng = np.random.default_rng(seed)
    for _ in range(25):
        n = int(rng.integers(2, 40))
        free = rng.random((n, 2)) < rng.uniform(0.2, 1.0)
        index = np.empty((n, 2), dtype=np.int64)
        n_vars = offset_groups(free, index)
        if n_vars == 0:
            continue
        root = rng.normal(size=(n, 2, 2))
        blocks = root @ root.transpose(0, 2, 1) + 0.01 * np.eye(2)
        h00, h01, h11 = (np.ascontiguousarray(blocks[:, i, j]) for i, j in ((0, 0), (0, 1), (1, 1)))
        dense = np.zeros((n_vars, n_vars))
        for k in range(n):
            for i in range(2):
                for j in range(2):
                    if index[k, i] >= 0 and index[k, j] >= 0:
                        dense[index[k, i], index[k, j]] += blocks[k, i, j]
        rhs = rng.normal(size=(n_vars, 3))
        x, ok = block_tree_solve(h00, h01, h11, index, n_vars, rhs)
        assert ok
        np.testing.assert_allclose(dense @ x, rhs, rtol=0, atol=1e-9 * np.abs(rhs).max())
        rows = (index >= 0).any(axis=1)
        twin, twin_ok = _planner_numpy.block_tree_solve(
            h00[rows], h01[rows], h11[rows], index[rows], n_vars, rhs
        )
        assert twin_ok and np.array_equal(twin, x)
    # a negative block: not positive definite, said
    index = np.array([[0, 1]], dtype=np.int64)
    _, ok = block_tree_solve(
        np.array([-1.0]), np.array([0.0]), np.array([1.0]), index, 2, np.ones((2, 1))
    )
    assert not ok


@pytest.mark.parametrize("q", [2, 3])
@pytest.mark.parametrize("clearance", [None, 0.002])
def test_a_problem_like_another_is_the_problem_built_afresh(
    q: int, clearance: float | None
) -> None:
    # The IOC builds each demonstration's problem on its first one's geometry (like=):
    # every array must be the fresh build's to the bit, whatever the reward (another Q,
    # other precisions, a swerve, the goal ramp).
    corridor = Corridor.from_path(problem_nominal(q), 60)
    scene = Scene(
        (
            Obstacle("a", corridor.points[20] + 0.03 * corridor.normals[20, 0], radius=0.01),
            Obstacle("b", corridor.points[40] - 0.02 * corridor.normals[40, 0], radius=0.01),
        )
    )
    first = Reward(10.0, {"a": np.full(q, 900.0), "b": np.full(q, 400.0)})
    like = Problem.from_scene(first, corridor, scene, 1.0, clearance=clearance)
    rewards = [
        Reward(3.0, {"a": np.linspace(200.0, 700.0, q), "b": np.full(q, 1500.0)}),
        Reward(5.0, {"a": np.full(q, 800.0), "b": np.full(q, 300.0)}, {"a": [0.5, 2.0]}),
    ]
    for reward in rewards:
        for approach in (None, "auto"):
            fresh = Problem.from_scene(reward, corridor, scene, 1.0, approach, clearance)
            reused = Problem.from_scene(
                reward, corridor, scene, 1.0, approach, clearance, like=like
            )
            assert set(vars(reused)) == set(vars(fresh))
            for name, value in vars(fresh).items():
                if isinstance(value, np.ndarray):
                    np.testing.assert_array_equal(getattr(reused, name), value, err_msg=name)
                else:
                    assert getattr(reused, name) == value, name
    assert like.weight[0] == 10.0  # the shared problem is left as it was


@pytest.mark.parametrize("q", [2, 3])
def test_a_corridor_is_made_once_per_path_and_point_count(monkeypatch, q: int) -> None:
    # Corridor.from_path keeps what it made by the path's digest (a skill plans one nominal
    # many times): the same object again, read-only, equal to one made afresh; another
    # path or point count is another corridor; the oldest go first past the bound.
    from lfdkit.emulate import problem as module

    t = np.linspace(0.0, 1.0, 80)
    path = np.column_stack([t, 0.1 * np.sin(np.pi * t)] + ([0.05 * t * t] if q == 3 else []))
    first = Corridor.from_path(path, 40)
    assert Corridor.from_path(path.copy(), 40) is first
    assert Corridor.from_path(np.asfortranarray(path), 40) is first
    for array in (first.points, first.normals, first.tangents):
        assert not array.flags.writeable
        with pytest.raises(ValueError):
            array[0] = 0.0
    monkeypatch.setattr(module, "_CORRIDORS", DigestMemo(max_items=256))
    fresh = Corridor.from_path(path, 40)
    assert fresh is not first
    for name in ("points", "normals", "tangents", "step"):
        np.testing.assert_array_equal(getattr(fresh, name), getattr(first, name))
    assert Corridor.from_path(path, 41) is not fresh
    assert Corridor.from_path(path + 1e-12, 40) is not fresh
    monkeypatch.setattr(module._CORRIDORS, "max_items", 2)
    Corridor.from_path(path, 42)
    assert len(module._CORRIDORS) == 2 and Corridor.from_path(path, 40) is not fresh


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    seed=st.integers(0, 2**32 - 1),
    m=st.sampled_from([1, 2, 3]),
    scale=st.sampled_from([1e-3, 1.0, 1e3]),
)
def test_a_term_left_off_the_live_lists_is_exactly_zero_nearby(seed: int, m: int, scale: float):
    # live_terms leaves a bump out only where exp(-s) is 0.0 and a hard radius only
    # where the barrier is 0.0, for every offset within the radius: points drawn in
    # the ball and on its surface, with curvatures of either sign, in any unit.
    rng = np.random.default_rng(seed)
    n, n_obs, n_hard = 4, 8, 8
    c = rng.uniform(-5.0, 3000.0, (n, n_obs))
    b = rng.normal(0.0, 300.0, (n, n_obs, m)) / scale
    a = rng.normal(0.0, 1.0, (n, n_obs, m, m)) * rng.uniform(0.0, 2e5, (n, n_obs, 1, 1))
    a /= scale**2
    nr = rng.normal(0.0, 0.2, (n, n_hard, m)) * scale
    rr = np.einsum("khi,khi->kh", nr, nr) + rng.uniform(0.0, 0.01, (n, n_hard)) * scale**2
    outer2 = (rng.uniform(0.01, 0.2, n_hard) * scale) ** 2
    centre = rng.normal(0.0, 0.05, (n, m)) * scale
    radius = float(rng.uniform(0.0, 0.1)) * scale
    bumps, hards = np.empty((n, n_obs), np.int64), np.empty((n, n_hard), np.int64)
    n_bumps, n_hards = np.empty(n, np.int64), np.empty(n, np.int64)
    live_terms(c, b, a, rr, nr, outer2, centre, radius, bumps, n_bumps, hards, n_hards)
    directions = rng.normal(size=(400, m))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    lengths = radius * np.concatenate([np.ones(100), rng.uniform(0.0, 1.0, 300) ** (1.0 / m)])
    for k in range(n):
        listed_bumps, listed_hards = bumps[k, : n_bumps[k]], hards[k, : n_hards[k]]
        assert np.all(np.diff(listed_bumps) > 0) and np.all(np.diff(listed_hards) > 0)
        d = centre[k] + lengths[:, None] * directions
        for o in sorted(set(range(n_obs)) - set(listed_bumps.tolist())):
            s = (
                c[k, o]
                + np.einsum("pi,i->p", d, 2.0 * b[k, o])
                + np.einsum("pi,ij,pj->p", d, a[k, o], d)
            )
            assert np.all(np.exp(-s) == 0.0)
        for h in sorted(set(range(n_hard)) - set(listed_hards.tolist())):
            u = rr[k, h] + np.einsum("pi,pi->p", 2.0 * nr[k, h] + d, d)
            assert np.all(u >= outer2[h])


def test_a_solve_over_listed_terms_is_the_solve_over_all_of_them() -> None:
    # A 3-D plan among many obstacles (more than LISTED_TERMS terms a point, most far
    # off): the Newton solve sums only each point's live terms, and ends on the same
    # offsets, cost and iterations to the bit as sums over every term (the NumPy form).
    from lfdkit.emulate import _planner_numpy

    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 1.0, 120)
    corridor = Corridor.from_path(np.column_stack([t, 0.1 * np.sin(np.pi * t), 0.05 * t]), 60)
    reward = Reward(10.0, {"a": [2500.0, 300.0, 215.0], "b": [400.0, 600.0, 900.0]})
    obstacles = []
    for j in rng.integers(5, 55, size=24):
        lateral = rng.uniform(-0.15, 0.15, 2) @ corridor.normals[j]
        centre = corridor.points[j] + lateral
        obstacles.append(Obstacle(str(rng.choice(["a", "b"])), centre, radius=0.004))
    scene = Scene(tuple(obstacles))
    problem = Problem.from_scene(reward, corridor, scene, 1.0, "auto", clearance=0.004)
    args = problem.kernel_arguments()
    assert args[0].shape[1] + args[4].shape[1] > LISTED_TERMS
    results = []
    for form in (_problem_kernels, _planner_numpy):
        d = np.zeros((problem.n, problem.m))
        cost, n_iter, ok = form.planner_newton(
            *args, problem.max_step, np.zeros(problem.m), d, 1e-10, 100
        )
        results.append((d, cost, n_iter, ok))
    (d_listed, *listed), (d_all, *every) = results
    assert listed[2] and listed[1] > 20  # converged, after many line searches
    np.testing.assert_allclose(d_listed, d_all, rtol=0.0, atol=1e-12 * np.abs(d_all).max())
    assert listed[0] == pytest.approx(every[0], rel=1e-12)
    # The forms' exp differ in the last bit, so the final convergence test may pass one
    # iteration apart (the offsets then agree to 1e-17).
    assert abs(listed[1] - every[1]) <= 1


def test_3d_newton_steps_use_the_exact_hessian_where_the_reduced_system_is_definite(
    monkeypatch,
) -> None:
    # A 3-D solve's reduced Newton system sums each point's 2×2 block over the offsets
    # an action held at its bound ties together. Each block was made positive first: where
    # one point of a group curves down (on a response's flank) and the group's sum is
    # still positive definite, that lengthened the curvature and shortened every step,
    # and the solve crept along linearly (3-D IOC plans: median 20 iterations, 9 % stopped
    # at 200). Now the blocks as they are, where the reduced system is definite (pivots
    # above the floor), else made positive as before: the same optima in far fewer
    # iterations (issue 34).
    from lfdkit.emulate import _planner_numpy

    exact = _planner_numpy.block_tree_solve

    def floored_first(h00, h01, h11, index, n_vars, rhs, least=0.0):
        if least > 0.0:  # the exact attempt refused: each block made positive, as before
            return np.zeros((n_vars, 1)), False
        return exact(h00, h01, h11, index, n_vars, rhs)

    t = np.linspace(0.0, 1.0, 120)
    corridor = Corridor.from_path(np.column_stack([t, 0.1 * np.sin(np.pi * t), 0.05 * t]), 50)
    reward = Reward(3.0, {"a": [150.0] * 3})
    iterations, same = {"exact": 0, "floored": 0}, 0
    for seed in range(8):
        rng = np.random.default_rng(seed)
        centres = corridor.points[rng.integers(10, 40, size=3)] + rng.uniform(-0.03, 0.03, (3, 3))
        scene = Scene(tuple(Obstacle("a", centre, radius=0.0) for centre in centres))
        problem = Problem.from_scene(reward, corridor, scene, 0.5, None)
        solved = {}
        for name, solve in (("exact", exact), ("floored", floored_first)):
            monkeypatch.setattr(_planner_numpy, "block_tree_solve", solve)
            d = np.zeros((problem.n, problem.m))
            cost, n_iter, ok = _planner_numpy.planner_newton(
                *problem.kernel_arguments(), problem.max_step, np.zeros(2), d, 1e-11, 300
            )
            assert ok, (seed, name)
            iterations[name] += n_iter
            solved[name] = (cost, d)
        same += abs(solved["exact"][0] - solved["floored"][0]) <= 1e-12 * solved["floored"][0]
        np.testing.assert_allclose(solved["exact"][1], solved["floored"][1], atol=1e-7)
    assert same == 8
    assert iterations["exact"] < 0.6 * iterations["floored"], iterations


def _along_path(reward: Reward, turn: float) -> Reward:
    """``reward`` with its precisions in the axes of a path running at ``turn`` (rad)."""
    c, s = np.cos(turn), np.sin(turn)
    axes = np.array([[c, -s], [s, c]])  # columns: along and across, in the room
    precisions = {k: axes.T @ p @ axes for k, p in reward.precisions.items()}
    return Reward(reward.nominal_weight, precisions, reward.swerve, along_path=True)


@pytest.mark.parametrize("degrees", [0.0, 30.0, 135.0])
def test_a_reward_along_a_straight_path_has_the_world_axis_terms(degrees) -> None:
    # Straightening a straight nominal out is a rigid motion: the same terms, to
    # rounding, anchors beyond either end included (their arc length runs on).
    turn = np.radians(degrees)
    direction = np.array([np.cos(turn), np.sin(turn)])
    nominal = np.outer(np.linspace(0.0, 0.8, 50), direction) + np.array([0.1, -0.2])
    corridor = Corridor.from_path(nominal, 60)
    reward = Reward(
        20.0,
        {"cup": [[300.0, 120.0], [120.0, 2500.0]], "box": [40.0, 900.0]},
        swerve={"box": [0.5, 2.0]},
    )
    left = np.array([-direction[1], direction[0]])
    scene = Scene(
        (
            Obstacle("cup", nominal[0] + 0.3 * direction + 0.02 * left, radius=0.01),
            Obstacle("box", nominal[0] - 0.05 * direction - 0.03 * left, radius=0.02),
            Obstacle("box", nominal[-1] + 0.04 * direction + 0.01 * left, radius=0.02),
        )
    )
    world = Problem.from_scene(reward, corridor, scene, 1.0)
    unrolled = Problem.from_scene(_along_path(reward, turn), corridor, scene, 1.0)
    assert world.unrolled is None and unrolled.unrolled is not None
    for name in ("c", "b", "a"):
        np.testing.assert_allclose(
            getattr(unrolled, name), getattr(world, name), rtol=1e-9, atol=1e-9
        )
    # The geometry's precisions (widths, reach): back in world axes.
    np.testing.assert_allclose(unrolled.precision, world.precision, rtol=1e-12, atol=1e-9)


def test_a_reward_along_a_bending_path_keeps_its_shape_along_it() -> None:
    # A trough: an arc of radius R about (0, R), run anticlockwise, so the left
    # normal points to the centre. An anchor δ inside the bend at its lowest point is at
    # arc length s_o = R·π/3 and lateral offset δ; a point k at (s_k, d) sees
    # u = (s_k − s_o, d − δ) through the precision in the path's axes.
    radius, delta = 0.3, 0.011
    angles = np.radians(np.linspace(-150.0, -30.0, 121))
    nominal = np.column_stack([radius * np.cos(angles), radius + radius * np.sin(angles)])
    corridor = Corridor.from_path(nominal, 121)
    precision = np.array([[40.0, 15.0], [15.0, 4000.0]])
    reward = Reward(20.0, {"box": precision}, along_path=True)
    problem = Problem.from_scene(reward, corridor, Scene((Obstacle("box", [0.0, delta]),)), 1.0)
    s = corridor.step * np.arange(1, 121)
    s_o = radius * np.pi / 3  # the chord-sampled arc is shorter by about 1e-5
    u = np.column_stack([s - s_o, np.full(120, -delta)])
    np.testing.assert_allclose(
        problem.c[:, 0], np.einsum("ki,ij,kj->k", u, precision, u), rtol=2e-3, atol=1e-6
    )
    np.testing.assert_allclose(problem.b[:, 0, 0], u @ precision[:, 1], rtol=2e-3, atol=1e-6)
    np.testing.assert_allclose(problem.a[:, 0, 0, 0], precision[1, 1])
