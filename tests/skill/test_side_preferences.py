"""A class kept on one side of the path (issue 26): planned so, stored in the file."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lfdkit.emulate import Reward
from lfdkit.model.box import Box
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill

X = np.linspace(0.0, 1.0, 60)
FREE = [np.column_stack([X, 0.002 * s * np.sin(np.pi * X)]) for s in (-1.0, 0.0, 1.0)]
PLAIN = Reward(10.0, {"cup": [300.0, 2500.0]})
# A cup 5 mm right of the path: the short way round is on its left (above).
RIGHT_OF_PATH = Scene((Obstacle("cup", [0.5, -0.005], radius=0.01),))
KEPT_LEFT = {"cup": {"side": "left", "within": 0.03}}


@pytest.fixture(scope="module")
def base() -> Skill:
    return Skill(n_points=60).fit(FREE)


def _side(plan: np.ndarray, cup: np.ndarray) -> float:
    """The plan's lateral offset from the cup's centre where it passes it (+: above)."""
    return float(np.interp(cup[0], plan[:, 0], plan[:, 1]) - cup[1])


def test_a_side_preference_is_planned_and_round_trips_through_the_file(base) -> None:
    skill = Skill(**base.get_params()).fit(FREE).adopt(PLAIN)
    cup = RIGHT_OF_PATH.positions[0]
    assert _side(skill.plan(scene=RIGHT_OF_PATH).points, cup) > 0.01  # the short way
    skill.side_preferences_ = dict(KEPT_LEFT)
    plan = skill.plan(scene=RIGHT_OF_PATH).points
    assert _side(plan, cup) < -0.01  # the cup on the path's left: the long way round
    assert RIGHT_OF_PATH.distances(plan)[0] > 0.0
    document = json.loads(json.dumps(skill.to_dict()))
    assert document["emulation"]["sides"] == KEPT_LEFT
    loaded = Skill.from_dict(document)
    assert loaded.side_preferences_ == KEPT_LEFT
    np.testing.assert_array_equal(loaded.plan(scene=RIGHT_OF_PATH).points, plan)
    mm = skill.to_units("mm")
    assert mm.side_preferences_["cup"]["within"] == pytest.approx(30.0)
    np.testing.assert_allclose(
        mm.plan(scene=RIGHT_OF_PATH.scaled(1000.0)).points / 1000.0, plan, atol=1e-9
    )


def test_a_file_without_sides_plans_as_before(base) -> None:
    skill = Skill(**base.get_params()).fit(FREE).adopt(PLAIN)
    document = json.loads(json.dumps(skill.to_dict()))
    assert "sides" not in (document.get("emulation") or {})
    loaded = Skill.from_dict(document)
    assert loaded.side_preferences_ == {}
    np.testing.assert_array_equal(
        loaded.plan(scene=RIGHT_OF_PATH).points, skill.plan(scene=RIGHT_OF_PATH).points
    )


def test_a_bad_side_in_a_file_is_one_line_naming_it(base) -> None:
    skill = Skill(**base.get_params()).fit(FREE).adopt(PLAIN)
    skill.side_preferences_ = dict(KEPT_LEFT)
    document = json.loads(json.dumps(skill.to_dict()))
    document["emulation"]["sides"]["cup"] = {"side": "up", "within": 0.03}
    with pytest.raises(ValueError, match=r"f\.json: emulation\.sides\.cup: expected") as caught:
        Skill.from_dict(document, source="f.json")
    assert "\n" not in str(caught.value)


def test_a_box_kept_below_is_passed_over_in_3d_and_round_trips() -> None:
    """A box 1 cm above the path: the learned response passes under it, the preference over."""
    free = [np.column_stack([X, d[:, 1], d[:, 1]]) for d in FREE]
    skill = Skill(n_points=60).fit(free).adopt(Reward(10.0, {"box": [300.0, 2500.0, 2500.0]}))
    box = Box("box", [0.5, 0.005, 0.01], 0.0, [0.06, 0.04, 0.04])
    scene = Scene((box,))

    def passed(plan: np.ndarray) -> np.ndarray:
        return plan[np.argmin(np.abs(plan[:, 0] - 0.5))]

    assert passed(skill.plan(scene=scene).points)[2] < box.position[2] - 0.02  # the short way
    skill.side_preferences_ = {"box": {"side": "below", "within": 0.03}}
    plan = skill.plan(scene=scene).points
    assert passed(plan)[2] > box.position[2] + 0.02  # over its top, the long way
    assert 0.0 < scene.distances(plan)[0] < 0.04  # close over it, not round the blockers
    skill.side_preferences_ = {"box": {"side": "left", "within": 0.03}}
    assert passed(skill.plan(scene=scene).points)[1] < box.position[1] - 0.02  # on its right
    skill.side_preferences_ = {"box": {"side": "below", "within": 0.03}}
    loaded = Skill.from_dict(json.loads(json.dumps(skill.to_dict())))
    assert loaded.side_preferences_ == skill.side_preferences_
    np.testing.assert_array_equal(loaded.plan(scene=scene).points, plan)


def test_a_box_kept_below_is_passed_over_at_its_sides_clearance_in_3d() -> None:
    """Over a box kept below, the learned response pushes the plan down onto it.

    Nothing learned holds the plan off the box the long way round: it kept only
    the tool's clearance over it where the person kept more. With the side's
    clearance (the class's learned floor) it keeps that, through the file and
    in millimetres; without one (older files) it plans as before.
    """
    free = [np.column_stack([X, d[:, 1], d[:, 1]]) for d in FREE]
    skill = Skill(n_points=60).fit(free).adopt(Reward(10.0, {"box": [300.0, 2500.0, 2500.0]}))
    scene = Scene((Box("box", [0.5, 0.005, 0.01], 0.0, [0.06, 0.04, 0.04]),))
    skill.side_preferences_ = {"box": {"side": "below", "within": 0.03}}
    before = skill.plan(scene=scene).points
    assert scene.distances(before)[0] < 0.025  # close over it: the response pushes it down
    skill.side_preferences_ = {"box": {"side": "below", "within": 0.03, "clearance": 0.03}}
    plan = skill.plan(scene=scene).points
    assert scene.distances(plan)[0] >= 0.03
    top = plan[np.argmin(np.abs(plan[:, 0] - 0.5)), 2]
    assert top > 0.03 + 0.03 > before[np.argmin(np.abs(before[:, 0] - 0.5)), 2]  # over its top
    document = json.loads(json.dumps(skill.to_dict()))
    assert document["emulation"]["sides"]["box"]["clearance"] == 0.03
    loaded = Skill.from_dict(document)
    assert loaded.side_preferences_ == skill.side_preferences_
    np.testing.assert_array_equal(loaded.plan(scene=scene).points, plan)
    mm = skill.to_units("mm")
    assert mm.side_preferences_["box"]["clearance"] == pytest.approx(30.0)
    np.testing.assert_allclose(mm.plan(scene=scene.scaled(1000.0)).points / 1000.0, plan, atol=1e-6)
    document["emulation"]["sides"]["box"]["clearance"] = -1.0
    with pytest.raises(ValueError, match=r"f\.json: emulation\.sides\.clearance\.box: expected"):
        Skill.from_dict(document, source="f.json")
