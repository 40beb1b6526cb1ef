"""The thesis's receding horizon in 3-D among three boxes: not refused where a plan passes.

Scenes and learned rewards of ``benchmarks/boxes3d.py`` (three boxes, seed 1,
folds 6 and 7, rewards as fitted there), planned at 100 points with the
person's 1 cm clearance. Both were refused ("at point 48 of 100 every move
... enters an obstacle's radius plus clearance"): the window swerved beyond
the look-ahead route's grid (±30 action bounds), whose dead-end check then
judged from the grid's edge, inside a box's reach.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from lfdkit.emulate import Box, Reward, Scene, metrics, plan_path

GOAL = np.array([0.65, 0.0, 0.12])
CLEARANCE = 0.01
SIZES = ([0.1, 0.14, 0.2], [0.08, 0.08, 0.3], [0.16, 0.12, 0.06])
TURNS = (
    [0.0, 0.0, 0.17364817766693033, 0.984807753012208],
    [0.0, 0.0, -0.08715574274765817, 0.9961946980917455],
    [0.0, 0.0, 0.3420201433256687, 0.9396926207859084],
)
FOLDS = {  # start, box centres, Q, box precisions (1/m²)
    6: (
        [0.0, 0.15955817753996476, 0.107630435223148],
        (
            [0.25964645989995333, 0.10830011804520945, 0.1],
            [0.4045414221210151, -0.09030106286952316, 0.15],
            [0.5041398528651426, 0.11580309028997261, 0.03],
        ),
        2.584101777501276,
        [160.37649149413303, 155.38154291466398, 158.34846056692743],
    ),
    7: (
        [0.0, 0.19453337621651445, 0.12191452423367112],
        (
            [0.2435059970133583, 0.10785722228585737, 0.1],
            [0.4365078045845945, -0.11185268567252377, 0.15],
            [0.5157240817144778, 0.13894443823428712, 0.03],
        ),
        2.4860591606008557,
        [161.23896863847884, 157.88179325736937, 158.5794140507366],
    ),
}


def _fold(held: int) -> tuple[Reward, np.ndarray, Scene]:
    start, centres, weight, precision = FOLDS[held]
    scene = Scene(
        tuple(
            Box("box", centre, 0.0, size, turn)
            for centre, size, turn in zip(centres, SIZES, TURNS, strict=True)
        )
    )
    nominal = np.asarray(start) + np.linspace(0.0, 1.0, 100)[:, None] * (GOAL - start)
    return Reward(weight, {"box": precision}), nominal, scene


def _thesis(reward, nominal, scene, **options):
    return plan_path(
        reward, nominal, scene, horizon=8, clearance=CLEARANCE, lookahead=False, **options
    )


@pytest.mark.slow
def test_window_beyond_the_route_grid_is_not_a_dead_end():
    """Fold 6: the check on a grid that spans the window's offsets passes it, unsaid."""
    reward, nominal, scene = _fold(6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the thesis's own plan: no escape taken
        plan = _thesis(reward, nominal, scene, goal_approach=None)
    assert metrics.collisions(plan.points, scene) == 0
    assert metrics.clearance(plan.points, scene).min() >= CLEARANCE * (1 - 1e-6)
    # It swerves more than the route's grid spans (30 action bounds, 0.20 m).
    step = np.linalg.norm(np.diff(nominal, axis=0), axis=1).mean()
    assert np.abs(plan.offsets).max() > 30 * step


@pytest.mark.slow
def test_dead_end_takes_the_route_step_and_says_so():
    """Fold 7: a true dead end of the window; the look-ahead's step instead, warned."""
    reward, nominal, scene = _fold(7)
    with pytest.warns(UserWarning, match="walked into a dead end"):
        plan = _thesis(reward, nominal, scene)
    assert metrics.collisions(plan.points, scene) == 0
    assert metrics.clearance(plan.points, scene).min() >= CLEARANCE * (1 - 1e-6)
    assert np.linalg.norm(plan.points[-1] - GOAL) < 1e-3  # at the goal (1 mm)


def test_the_goal_join_polishes_its_starts_side_by_side_with_the_same_plan(monkeypatch):
    """In 3-D the join's two polished tails run on two threads: the plan of one thread."""
    from lfdkit.core import threads
    from lfdkit.emulate import planner

    reward, nominal, scene = _fold(6)
    sizes = []
    mapped = planner.map_on_threads

    def counting(work, *items):
        sizes.append(len(items[0]))
        return mapped(work, *items)

    monkeypatch.setattr(planner, "map_on_threads", counting)
    plans = {}
    for cores in (1, 2):
        monkeypatch.setattr(threads, "available_cores", lambda cores=cores: cores)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            plans[cores] = plan_path(
                reward, nominal, scene, clearance=CLEARANCE, goal_approach=0.2
            ).points
    assert sizes == [2, 2]  # the route's tail and the grid's, each time
    np.testing.assert_array_equal(plans[1], plans[2])
    assert np.linalg.norm(plans[2][-1] - GOAL) < 1e-3
