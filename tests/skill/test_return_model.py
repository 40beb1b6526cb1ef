"""The slow-return model (issue 26): learned bound, gated candidate, skill file.

A late, reactive person swerves steeply and returns slowly. The fit measures
how steeply the demonstrations come back
(``ioc_info_["demonstrated_return"]``); where they come back much more
slowly than they swerve, the model choice also scores the thesis's window
with its return bounded by that slope (``"window+demonstrated/return"``),
chosen only where it replans the held-out demonstrations closer. The chosen
bound (``return_fraction_``) goes through the skill file; older files plan
with none.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from lfdkit.emulate import Reward
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill
from lfdkit.skill.selection import ASYMMETRIC_RETURN

X = np.linspace(0.0, 1.0, 60)
FREE = [np.column_stack([X, 0.002 * s * np.sin(np.pi * X)]) for s in (-1.0, 0.0, 1.0)]
SCENE = Scene((Obstacle("cup", [0.45, 0.01], radius=0.01),))
REWARD = Reward(10.0, {"cup": [300.0, 2500.0]})


@pytest.fixture(scope="module")
def base() -> Skill:
    return Skill(n_points=60).fit(FREE)


def slow_skill(base: Skill, fraction: float) -> Skill:
    """A skill whose model choice chose the slow return with this bound (as ``_select_model``)."""
    skill = Skill(**base.get_params()).fit(FREE).adopt(REWARD)
    skill.route_ = "window"
    skill.return_fraction_ = fraction
    return skill


def test_the_bound_round_trips_through_the_file_and_plans_the_same(base) -> None:
    skill = slow_skill(base, 0.2)
    document = json.loads(json.dumps(skill.to_dict()))
    assert document["emulation"]["return_fraction"] == 0.2
    loaded = Skill.from_dict(document)
    assert loaded.return_fraction_ == 0.2
    plan = skill.plan(scene=SCENE).points
    np.testing.assert_array_equal(loaded.plan(scene=SCENE).points, plan)
    # the bound changes the plan (it is not dropped on the way) ...
    symmetric = slow_skill(base, 1.0)
    assert np.abs(symmetric.plan(scene=SCENE).points - plan).max() > 1e-3
    # ... and is kept through a change of units (a ratio)
    assert skill.to_units("mm").return_fraction_ == 0.2


def test_a_file_without_it_plans_symmetrically(base) -> None:
    skill = slow_skill(base, 1.0)
    document = json.loads(json.dumps(skill.to_dict()))
    assert "return_fraction" not in document["emulation"]
    loaded = Skill.from_dict(document)
    assert loaded.return_fraction_ == 1.0
    np.testing.assert_array_equal(loaded.plan(scene=SCENE).points, skill.plan(scene=SCENE).points)


@pytest.mark.parametrize("value", [0.0, 1.5, "slow", True])
def test_a_bad_bound_in_a_file_is_one_line_naming_it(base, value) -> None:
    document = json.loads(json.dumps(slow_skill(base, 0.2).to_dict()))
    document["emulation"]["return_fraction"] = value
    with pytest.raises(ValueError, match=r"f\.json: emulation\.return_fraction: expected") as err:
        Skill.from_dict(document, source="f.json")
    assert "\n" not in str(err.value)


def test_a_full_horizon_plan_of_a_slow_skill_has_no_bound(base) -> None:
    skill = slow_skill(base, 0.2)
    full = skill.plan(scene=SCENE, planner="full").points
    np.testing.assert_array_equal(
        full, slow_skill(base, 1.0).plan(scene=SCENE, planner="full").points
    )


@pytest.mark.parametrize(
    ("measured", "offered"),
    [
        ({"out": 1.5, "back": 0.2, "ratio": 0.13, "count": 7}, 0.2),  # a late swerver
        ({"out": 0.4, "back": 0.33, "ratio": 0.81, "count": 8}, None),  # a symmetric bump
        ({"out": 3.0, "back": 1.2, "ratio": 0.4 * ASYMMETRIC_RETURN, "count": 5}, None),  # steep
        ({"out": None, "back": None, "ratio": None, "count": 0}, None),  # not measured
    ],
)
def test_the_candidate_is_offered_only_for_a_slow_return(base, measured, offered) -> None:
    skill = Skill(**base.get_params()).fit(FREE).adopt(REWARD)
    skill.ioc_info_ = {"horizon": 8, "demonstrated_return": measured}
    names = [c for c in skill._behaviour_candidates() if "return" in c]
    assert skill._demonstrated_return() == offered
    assert len(names) == (offered is not None)
    if offered is not None:
        # Asymmetric along the motion: planned relative to it (the path frame, 2-D).
        assert names[0] == {
            "route": "window",
            "floor": "demonstrated",
            "frame": "path",
            "return": "slow",
        }
    skill.ioc_info_ = {"horizon": None, "demonstrated_return": measured}  # a full-horizon fit
    assert not [c for c in skill._behaviour_candidates() if "return" in c]


@pytest.mark.parametrize("model", ["auto", "path", "thesis"])
def test_asymmetric_candidates_plan_in_the_path_frame_in_the_plane_only(model) -> None:
    slow = {"out": 1.5, "back": 0.2, "ratio": 0.13, "count": 7}
    frames = {}
    for dims in (2, 3):
        free = FREE if dims == 2 else [np.column_stack([d, 0.0 * X]) for d in FREE]
        reward = REWARD if dims == 2 else Reward(10.0, {"cup": [300.0, 2500.0, 2500.0]})
        skill = Skill(n_points=60, model=model).fit(free).adopt(reward)
        skill.ioc_info_ = {"horizon": 8, "demonstrated_return": slow}
        frames[dims] = {
            ("swerve" in c or "return" in c, c["route"]): c["frame"]
            for c in skill._behaviour_candidates()
        }
    if model == "thesis":  # one candidate, the thesis's model exactly
        assert frames == {2: {(False, "window"): "world"}, 3: {(False, "window"): "world"}}
        return
    symmetric = "path" if model == "path" else "world"
    assert frames[2] == {
        (True, "window"): "path",  # the swerve and the slow return turn with the motion
        (False, "window"): symmetric,
        (False, "full"): symmetric,
        (False, "taut"): "world",  # no learned response to turn
    }
    # In space the responses are not turned (model="path" refuses to plan there).
    assert set(frames[3].values()) == {symmetric}
