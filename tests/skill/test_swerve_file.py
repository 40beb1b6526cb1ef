"""The swerve model in the skill file (issue 26): optional, older files load unchanged."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lfdkit.emulate import Reward
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill

X = np.linspace(0.0, 1.0, 60)
FREE = [np.column_stack([X, 0.002 * s * np.sin(np.pi * X)]) for s in (-1.0, 0.0, 1.0)]
SCENE = Scene((Obstacle("cup", [0.45, 0.01], radius=0.01),))
PLAIN = Reward(10.0, {"cup": [300.0, 2500.0]})
SWERVING = Reward(10.0, {"cup": [300.0, 2500.0]}, swerve={"cup": [0.5, 3.0]})


@pytest.fixture(scope="module")
def base() -> Skill:
    return Skill(n_points=60).fit(FREE)


def test_a_swerve_round_trips_through_the_file(base) -> None:
    skill = Skill(**base.get_params()).fit(FREE).adopt(SWERVING)
    document = json.loads(json.dumps(skill.to_dict()))
    assert document["emulation"]["swerve"] == {"cup": [0.5, 3.0]}
    loaded = Skill.from_dict(document)
    np.testing.assert_array_equal(loaded.reward_.swerve["cup"], [0.5, 3.0])
    np.testing.assert_array_equal(loaded.plan(scene=SCENE).points, skill.plan(scene=SCENE).points)
    # the swerve changes the plan (it is not silently dropped anywhere on the way)
    plain = Skill(**base.get_params()).fit(FREE).adopt(PLAIN)
    assert np.abs(plain.plan(scene=SCENE).points - skill.plan(scene=SCENE).points).max() > 1e-3


def test_a_file_without_a_swerve_is_the_symmetric_model(base) -> None:
    skill = Skill(**base.get_params()).fit(FREE).adopt(PLAIN)
    document = json.loads(json.dumps(skill.to_dict()))
    assert "swerve" not in (document.get("emulation") or {})
    loaded = Skill.from_dict(document)
    assert loaded.reward_.swerve == {}
    np.testing.assert_array_equal(loaded.plan(scene=SCENE).points, skill.plan(scene=SCENE).points)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ([0.5], r"f\.json: emulation\.swerve\.cup: expected shape 2"),
        ([0.5, -1.0], r"swerve\['cup'\]: expected two positive stretches"),
    ],
)
def test_a_bad_swerve_in_a_file_is_one_line_naming_it(base, value, message) -> None:
    skill = Skill(**base.get_params()).fit(FREE).adopt(SWERVING)
    document = json.loads(json.dumps(skill.to_dict()))
    document["emulation"]["swerve"]["cup"] = value
    with pytest.raises(ValueError, match=message) as caught:
        Skill.from_dict(document, source="f.json")
    assert "\n" not in str(caught.value)


def test_units_keep_the_swerve(base) -> None:
    skill = Skill(**base.get_params()).fit(FREE).adopt(SWERVING)
    in_mm = skill.to_units("mm")
    np.testing.assert_array_equal(in_mm.reward_.swerve["cup"], [0.5, 3.0])
    np.testing.assert_allclose(
        in_mm.plan(scene=SCENE.scaled(1000.0)).points,
        1000.0 * skill.plan(scene=SCENE).points,
        atol=1e-6,
    )


def test_a_reward_refuses_a_swerve_it_cannot_use() -> None:
    with pytest.raises(ValueError, match=r"swerve: class 'box' has no precision"):
        Reward(10.0, {"cup": [1.0, 1.0]}, swerve={"box": [1.0, 1.0]})
    with pytest.raises(ValueError, match=r"swerve\['cup'\]: expected two positive"):
        Reward(10.0, {"cup": [1.0, 1.0]}, swerve={"cup": [1.0, np.nan]})
