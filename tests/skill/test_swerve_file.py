"""The swerve model in the skill file (issue 26): optional, older files load unchanged."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lfdkit.emulate import Reward
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill
from lfdkit.skill.selection import ROUTE_PULL

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


# A swerve whose widths were refitted (issue 26), and the stretches-only reward it routes
# with among several obstacles: stored as width ratios (unit-free) and stretches.
ROUTE = {"width_ratios": {"cup": [2.0, 0.5]}, "swerve": {"cup": [0.8, 1.5]}}
SELECTION = {"chosen": "window/swerve", "swerve": {"cup": [0.5, 3.0]}, "swerve_route": ROUTE}


def routed_skill(base) -> Skill:
    skill = Skill(**base.get_params()).fit(FREE).adopt(SWERVING)
    skill.model_selection_ = json.loads(json.dumps(SELECTION))
    skill.ioc_info_ = {"model_selection": skill.model_selection_}
    return skill


def test_the_route_reward_is_rebuilt_from_the_ratios_in_any_units(base) -> None:
    skill = routed_skill(base)
    route = skill._swerve_route_reward()
    # each axis's width times its ratio: precision / ratio²
    np.testing.assert_allclose(np.diag(route.precisions["cup"]), [300.0 / 4.0, 2500.0 / 0.25])
    np.testing.assert_array_equal(route.swerve["cup"], [0.8, 1.5])
    assert route.nominal_weight == ROUTE_PULL * skill.reward_.nominal_weight
    loaded = Skill.from_dict(json.loads(json.dumps(skill.to_dict())))
    again = loaded._swerve_route_reward()
    np.testing.assert_array_equal(again.precisions["cup"], route.precisions["cup"])
    in_mm = skill.to_units("mm")._swerve_route_reward()
    np.testing.assert_allclose(in_mm.precisions["cup"], route.precisions["cup"] / 1e6)
    # another swerve adopted for the class: its own response, no stale route
    skill.adopt(Reward(10.0, {"cup": [300.0, 2500.0]}, swerve={"cup": [0.6, 2.0]}))
    np.testing.assert_array_equal(skill._swerve_route_reward().swerve["cup"], [0.6, 2.0])
    assert Skill(**base.get_params()).fit(FREE).adopt(PLAIN)._swerve_route_reward() is None


class _Plan:
    def __init__(self, points: np.ndarray) -> None:
        self.points = points


def test_the_route_reward_decides_the_sides_only_where_they_differ(base) -> None:
    import warnings

    skill = routed_skill(base)
    nominal = np.column_stack([X, np.zeros_like(X)])
    scene = Scene((Obstacle("cup", [0.3, 0.0], radius=0.01), Obstacle("cup", [0.7, 0.0], 0.01)))
    bump = 0.05 * np.sin(np.pi * X)
    left, right = nominal + np.c_[0 * X, bump], nominal - np.c_[0 * X, bump]
    lower_left = nominal + np.c_[0 * X, 0.5 * bump]
    route = skill._swerve_route_reward()

    def planner(own: np.ndarray, routed: np.ndarray):
        def plan_with(reward):
            warnings.warn("own" if reward is skill.reward_ else "routed", UserWarning, stacklevel=2)
            return _Plan(own if reward is skill.reward_ else routed)

        return plan_with

    for own, routed, expected, said in (
        (left, lower_left, left, "own"),  # same sides: the swerve's own plan and warnings
        (left, right, right, "routed"),  # another side: the route reward's
    ):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            plan = skill._swerve_routed(planner(own, routed), route, nominal, scene)
        assert plan.points is expected
        assert [str(w.message) for w in caught] == [said]
    assert np.diag(route.precisions["cup"])[1] == 10000.0


def test_a_swerve_skill_plans_one_obstacle_with_its_own_widths(base) -> None:
    skill = routed_skill(base)
    own = Skill(**base.get_params()).fit(FREE).adopt(SWERVING)
    np.testing.assert_array_equal(skill.plan(scene=SCENE).points, own.plan(scene=SCENE).points)
    # among two, the plan is one of the two rewards' plans
    two = Scene((Obstacle("cup", [0.35, 0.01], radius=0.01), Obstacle("cup", [0.6, -0.01], 0.01)))
    route = Skill(**base.get_params()).fit(FREE).adopt(skill._swerve_route_reward())
    planned = skill.plan(scene=two).points
    assert any(np.array_equal(planned, other.plan(scene=two).points) for other in (own, route))
