"""The taut plan (issue 26): the shortest way round the obstacles that keeps their clearance.

Known answers: the taut string through a corridor with one bound is the two
straight lines through that bound's point; round one disc on a straight
nominal, the shortest path is the tangent, the arc and the tangent (closed
form), also where the side search's grid cannot tell the two sides apart
(it stays off a gap narrower than its spacing); a person who takes that
path, keeping a fixed margin, is emulated by the taut model, which the skill
chooses by cross-validated replanning.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from lfdkit.emulate import metrics
from lfdkit.emulate.taut import taut_plan, taut_string
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill

X = np.linspace(0.0, 1.0, 100)
FREE = [np.column_stack([X, 0.002 * s * np.sin(np.pi * X)]) for s in (-1.0, 0.0, 1.0)]


def around_disc(x: np.ndarray, centre: np.ndarray, reach: float) -> np.ndarray:
    """The shortest path from (0, 0) to (1, 0) outside a disc, as heights at ``x``.

    It passes on the side away from the centre: the tangents from each end and
    the arc between their tangent points.
    """
    side = -1.0 if centre[1] >= 0.0 else 1.0
    ends = (np.array([0.0, 0.0]), np.array([1.0, 0.0]))
    # Tangent point from an end: at angle ±acos(R/d) from the direction to the end.
    angles = []
    for end, turn in zip(ends, (1.0, -1.0), strict=True):
        rel = end - centre
        base = np.arctan2(rel[1], rel[0])
        angles.append(base - turn * side * np.arccos(reach / np.linalg.norm(rel)))
    t1, t2 = (centre + reach * np.array([np.cos(a), np.sin(a)]) for a in angles)
    y = np.empty_like(x)
    first, last = x <= t1[0], x >= t2[0]
    y[first] = t1[1] * x[first] / t1[0]
    y[last] = t2[1] * (1.0 - x[last]) / (1.0 - t2[0])
    mid = ~(first | last)
    y[mid] = centre[1] + side * np.sqrt(np.maximum(reach**2 - (x[mid] - centre[0]) ** 2, 0.0))
    return y


def test_the_taut_string_is_straight_between_the_bounds_it_touches() -> None:
    lower, upper = np.full(11, -np.inf), np.full(11, np.inf)
    lower[0] = upper[0] = upper[-1] = lower[-1] = 0.0
    lower[3] = 1.0  # a peg at station 3, and one under the line that stays slack
    lower[7] = 0.2
    y = taut_string(lower, upper)
    expected = np.where(np.arange(11) <= 3, np.arange(11) / 3.0, (10 - np.arange(11)) / 7.0)
    np.testing.assert_allclose(y, expected, atol=1e-12)
    # Between a floor and a ceiling the string bends at each.
    lower, upper = np.full(9, -np.inf), np.full(9, np.inf)
    lower[0] = upper[0] = lower[-1] = upper[-1] = 0.0
    lower[2], upper[6] = 1.0, -1.0
    y = taut_string(lower, upper)
    np.testing.assert_allclose(y[[0, 2, 6, 8]], [0.0, 1.0, -1.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(np.diff(y[2:7]), -0.5, atol=1e-12)  # straight from peg to peg


def test_round_one_disc_the_taut_plan_is_the_tangent_path() -> None:
    nominal = np.column_stack([X, np.zeros_like(X)])
    cup = Obstacle("cup", [0.45, 0.01], radius=0.02)
    scene = Scene((cup,))
    plan = taut_plan(nominal, scene, 0.03, n_points=100, max_slope=1.0)
    assert plan is not None
    expected = around_disc(plan.points[:, 0], cup.position, 0.05)
    assert np.abs(plan.points[:, 1] - expected).max() < 2e-3  # the barrier's widening: 0.6 mm
    assert scene.distances(plan.points)[0] >= 0.03 - 1e-9  # the margin kept, segments too
    assert plan.clearance[0] >= 0.0
    np.testing.assert_allclose(plan.points[[0, -1]], nominal[[0, -1]], atol=1e-12)
    # Two obstacles: the shorter way round both, not between them (the gap is 1 cm).
    pair = Scene((cup, Obstacle("cup", [0.45, -0.05], radius=0.02)))
    plan = taut_plan(nominal, pair, 0.03, n_points=100, max_slope=1.0)
    assert pair.distances(plan.points).min() >= 0.03 - 1e-9
    assert plan.points[:, 1].max() > 0.05  # above both: the upper cup is nearer the path
    # No room within the action bound: no taut plan (the caller plans as before).
    wall = Scene(tuple(Obstacle("cup", [0.5, y], radius=0.02) for y in np.arange(-1, 1, 0.03)))
    assert taut_plan(nominal, wall, 0.0, n_points=100, max_slope=1.0) is None
    with pytest.raises(ValueError, match="clearance: expected finite values >= 0"):
        taut_plan(nominal, pair, [0.03, -0.01])


def test_the_shorter_side_is_taken_where_the_grid_cannot_tell_them_apart() -> None:
    # A disc 0.1 mm above the nominal: going below is shorter, by less than the
    # side search's grid (2.5 mm apart) can tell (on main the plan went above).
    nominal = np.column_stack([X, np.zeros_like(X)])
    cup = Obstacle("cup", [0.5, 0.0001], radius=0.02)
    plan = taut_plan(nominal, Scene((cup,)), 0.03, n_points=100, max_slope=1.0)
    assert plan is not None
    expected = around_disc(plan.points[:, 0], cup.position, 0.05)  # below: away from the centre
    assert np.abs(plan.points[:, 1] - expected).max() < 2e-3  # the barrier's widening: 0.6 mm


def test_a_gap_narrower_than_the_side_search_grid_stays_closed() -> None:
    # Two cups whose barrier covers leave 1.5 mm at station 50 (the grid is 2.5 mm
    # apart): through it is shorter, but a gap that narrow is within the learned
    # clearances' error, so the plan goes round a cup as the grid does.
    nominal = np.column_stack([X, np.zeros_like(X)])
    step = 1.0 / 99.0
    reach = np.hypot(0.02, 0.5 * 1.1 * np.hypot(step, step))  # the cover of plan_path's barrier
    x = 50 * step
    scene = Scene(
        (
            Obstacle("cup", [x, 0.0005 - reach], radius=0.02),
            Obstacle("cup", [x, 0.0020 + reach], radius=0.02),
        )
    )
    plan = taut_plan(nominal, scene, 0.0, n_points=100, max_slope=1.0)
    assert plan is not None
    assert np.abs(plan.offsets[:, 0]).max() > 0.04
    assert plan.clearance.min() >= 0.0


@pytest.mark.slow
def test_a_person_who_keeps_a_margin_on_the_shortest_way_is_emulated(tmp_path) -> None:
    rng = np.random.default_rng(3)
    demos, scenes = [], []
    for j in range(6):
        centre = np.array([0.3 + 0.08 * j, rng.choice([-1.0, 1.0]) * rng.uniform(0.0, 0.03)])
        scenes.append(Scene((Obstacle("cup", centre, radius=0.01),)))
        demos.append(np.column_stack([X, around_disc(X, centre, 0.01 + 0.03)]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        skill = Skill().fit(FREE, demos, scenes)
    selection = skill.model_selection_
    assert selection["chosen"] == "taut+typical" and skill.route_ == "taut"
    assert skill.clearances_["cup"] == pytest.approx(0.03, abs=1e-3)
    # A new scene: a cup further along, on the other side, nearer the path.
    cup = Obstacle("cup", [0.62, -0.004], radius=0.01)
    plan = skill.plan(scene=Scene((cup,)))
    expected = np.column_stack([X, around_disc(X, cup.position, 0.04)])
    assert Scene((cup,)).distances(plan.positions)[0] >= skill.clearances_["cup"] - 1e-9
    nominal = skill.nominal()
    pr = metrics.improvement(
        metrics.mse_paths([nominal], [expected]), metrics.mse_paths([plan.positions], [expected])
    )
    assert pr > 95.0
    # The model is kept in the skill's file: the same plan read back.
    again = Skill.load(skill.save(tmp_path / "skill.json"))
    assert again.route_ == "taut"
    np.testing.assert_allclose(again.plan(scene=Scene((cup,))).positions, plan.positions)
