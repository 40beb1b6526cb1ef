"""A window's grid search over the levels reachable from its start equals the search over all."""

import numpy as np
import pytest

from lfdkit.datasets.planning import N_POINTS, random_case_with_radii
from lfdkit.emulate import planner as P
from lfdkit.emulate.problem import Corridor, Problem


def _full_search(window: Problem, anchor: np.ndarray) -> tuple[np.ndarray, float]:
    """The same search without the cut: the whole grid to the kernel."""
    levels, cells = P._lateral_levels(window, anchor)
    out = np.zeros((window.n, window.m))
    total = P._grid_kernel("lateral_dp")(
        *window.kernel_arguments(), window.max_step, anchor, levels, cells, False,
        np.zeros((0, 0)), out,
    )  # fmt: skip
    return out, total


@pytest.mark.parametrize("seed", range(6))
def test_reachable_levels_give_the_same_path_bit_for_bit(seed):
    reward, path, scene, clearance = random_case_with_radii(seed)
    corridor = Corridor.from_path(path, N_POINTS)
    problem = Problem.from_scene(reward, corridor, scene, 1.0, None, np.full(len(scene), clearance))
    rng = np.random.default_rng(seed)
    cut = 0
    for k in range(0, problem.n - 12, 7):
        window = problem.window(k, k + 12)
        # Anchors on the nominal and far aside (where the cut removes most of the grid).
        for anchor in (np.zeros(1), rng.uniform(-20, 20, 1) * problem.max_step):
            levels, cells = P._lateral_levels(window, anchor)
            kept = P._reachable(levels, cells, window.max_step, anchor, window.n)
            cut += levels.size - kept.size
            expected, total = _full_search(window, anchor)
            got = P._global_start(window, anchor, False)
            if not np.isfinite(total):
                assert got is None
            else:
                assert np.array_equal(got, expected)
    assert cut > 0  # the cut was exercised


@pytest.mark.parametrize("seed", range(4))
def test_per_plan_window_numbers_are_the_windows_own_bit_for_bit(seed):
    """The MPC's once-per-plan reaches and obstacle test equal those of each window itself."""
    reward, path, scene, clearance = random_case_with_radii(seed)
    corridor = Corridor.from_path(path, N_POINTS)
    problem = Problem.from_scene(reward, corridor, scene, 1.0, None, np.full(len(scene), clearance))
    assert P._WindowReaches.usable(problem)
    reaches, near = P._WindowReaches(problem), P._ObstacleNear(problem)
    rng = np.random.default_rng(seed)
    for k in range(0, problem.n, 5):
        stop = min(k + 12, problem.n)
        window = problem.window(k, stop)
        for anchor in (np.zeros(1), rng.uniform(-20, 20, 1) * problem.max_step):
            laterals, reach = P._obstacle_reaches(window)
            got_laterals, got_reach = reaches.at(k, stop)
            assert np.array_equal(got_laterals, laterals) and np.array_equal(got_reach, reach)
            for span in (0.0, 2.0 * problem.max_step, 0.3):
                assert reaches.widest(k, stop, span) == P._widest(span, laterals, reach)
            assert near(k, stop, anchor) == P._obstacle_near(window, anchor)


def _problem_3d(seed: int) -> Problem:
    """A 3-D problem among two turned boxes and a round obstacle, with a clearance."""
    from lfdkit.emulate import Reward
    from lfdkit.model.box import Box
    from lfdkit.model.scene import Obstacle, Scene

    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, 120)[:, None]
    path = t * np.array([0.8, 0.0, 0.2]) + np.sin(np.pi * t) * np.array([0.0, 0.1, 0.0])
    turn = rng.uniform(-0.5, 0.5, 2)
    scene = Scene(
        (
            Box("a", path[30] + rng.uniform(-0.03, 0.03, 3), 0.0, [0.06, 0.06, 0.2],
                [0.0, 0.0, np.sin(turn[0] / 2), np.cos(turn[0] / 2)]),
            Box("b", path[70] + rng.uniform(-0.03, 0.03, 3), 0.0, [0.05, 0.08, 0.1],
                [0.0, 0.0, np.sin(turn[1] / 2), np.cos(turn[1] / 2)]),
            Obstacle("a", path[95] + rng.uniform(-0.03, 0.03, 3), radius=0.02),
        )
    )  # fmt: skip
    reward = Reward(10.0, {"a": [2500.0, 300.0, 215.0], "b": [400.0, 600.0, 900.0]})
    corridor = Corridor.from_path(path, N_POINTS)
    return Problem.from_scene(reward, corridor, scene, 1.0, None, np.full(len(scene), 0.01))


@pytest.mark.parametrize("seed", range(3))
def test_per_plan_window_reaches_in_3d_are_the_windows_own_bit_for_bit(seed):
    """In 3-D (issue 34) too: each window's reaches from the one pass equal its own."""
    problem = _problem_3d(seed)
    assert problem.m == 2 and P._WindowReaches.usable(problem) and problem.hard.sum() > 3
    reaches = P._WindowReaches(problem)
    inside = 0
    for k in range(problem.n):
        stop = min(k + 8, problem.n)
        laterals, reach = P._obstacle_reaches(problem.window(k, stop))
        got_laterals, got_reach = reaches.at(k, stop)
        assert np.array_equal(got_laterals, laterals) and np.array_equal(got_reach, reach)
        for span in (0.0, 2.0 * problem.max_step, 0.3):
            assert reaches.widest(k, stop, span) == P._widest(span, laterals, reach)
        inside += P._widest(0.0, laterals, reach) > 0.0
    assert inside > 10  # windows within an obstacle's reach were compared


@pytest.mark.parametrize("seed", range(3))
def test_3d_window_states_costs_sliced_from_the_whole_grid_are_its_own(seed):
    """A window's levels on the whole grid's spacing, or twice it, take the whole grid's
    states' costs (issue 34): the numbers :func:`P._node_costs` gives on its own levels."""
    problem = _problem_3d(seed)
    step = problem.max_step
    whole = (step / 2.0) * np.arange(-30, 31)
    node = P._node_costs(problem, whole)
    assert np.isinf(node).any() and (np.isfinite(node) & (node > 0.0)).any()
    hard = 0
    for k in range(0, problem.n - 8, 9):
        # the window grid's spacings (_lateral_levels: the step over 1 or 2 cells)
        for spacing, count in ((step / 2.0, 30), (step / 2.0, 11), (step, 15), (step, 4)):
            levels = spacing * np.arange(-count, count + 1)
            got = P._shared_states(whole, node, k, k + 8, levels)
            np.testing.assert_array_equal(got, P._node_costs(problem.window(k, k + 8), levels))
            hard += bool(np.isinf(got).any())
    assert hard > 0  # windows whose states reach into a hard radius were compared
    # Levels off the whole grid, or beyond it, are not taken from it.
    for levels in (
        (step / 3.0) * np.arange(-10, 11),
        step * np.arange(-16, 17),
        (step / 2.0) * np.arange(-31, 32),
        (step / 4.0) * np.arange(-10, 11),
        (step / 2.0) * np.arange(-10, 11) + step / 8.0,
    ):
        assert P._shared_states(whole, node, 0, 8, levels) is None
