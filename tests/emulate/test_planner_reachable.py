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
