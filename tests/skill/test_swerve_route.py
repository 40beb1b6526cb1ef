"""A swerve skill's route among several obstacles (issue 26): a head-on pass, decided by the pull.

The reward and stored route are those the skill learned from six demonstrations
of the fidelity benchmark's potential-field person (seed 0, rounded), the scene
its clutter scene where that person, held 0.8 cm below the second box's centre
line by its swerve round the first, passes the second box on the nominal's side.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from lfdkit.emulate import Reward
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill

X = np.linspace(0.0, 0.8, 100)
FREE = [np.column_stack([X, 0.002 * s * np.sin(np.pi * X / 0.8)]) for s in (-1.0, 0.0, 1.0)]
SWERVE = {"cup": [0.197, 1.074], "box": [0.211, 1.028]}
REWARD = Reward(0.00156, {"cup": [98.5, 2181.0], "box": [73.5, 796.0]}, swerve=SWERVE)
SELECTION = {
    "chosen": "window/swerve",
    "swerve": SWERVE,
    "swerve_route": {
        "width_ratios": {"cup": [1.14, 0.71], "box": [1.03, 0.75]},
        "swerve": {"cup": [0.31, 1.04], "box": [0.22, 1.16]},
    },
}
FIRST = Obstacle("box", [0.144, 0.047], radius=0.05)
SECOND = Obstacle("box", [0.41, -0.068], radius=0.05)
CUP = Obstacle("cup", [0.654, -0.018], radius=0.03)


@pytest.fixture(scope="module")
def skill() -> Skill:
    skill = Skill().fit(FREE).adopt(REWARD)
    skill.model_selection_ = SELECTION
    skill.ioc_info_ = {"model_selection": SELECTION}
    skill.route_ = "window"
    return skill


def _plan(skill: Skill, *obstacles: Obstacle) -> np.ndarray:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return skill.plan([0.0, 0.0], [0.8, 0.0], Scene(obstacles)).points


def test_a_head_on_box_is_passed_on_the_nominals_side(skill) -> None:
    plan = _plan(skill, FIRST, SECOND, CUP)
    at = np.interp([FIRST.position[0], SECOND.position[0]], plan[:, 0], plan[:, 1])
    assert at[0] < FIRST.position[1] - FIRST.radius  # below the first, as the person
    # above the second (the person: +7 cm; with the fitted pull alone the plan held its
    # swerve and went round it 19 cm below the nominal)
    assert at[1] > SECOND.position[1] + SECOND.radius
    for obstacle in (FIRST, SECOND, CUP):
        assert np.min(np.linalg.norm(plan - obstacle.position, axis=1)) > obstacle.radius


def test_a_single_obstacle_is_planned_with_the_fitted_reward(skill) -> None:
    fitted = Skill().fit(FREE).adopt(REWARD)
    fitted.route_ = "window"
    np.testing.assert_array_equal(_plan(skill, SECOND), _plan(fitted, SECOND))
