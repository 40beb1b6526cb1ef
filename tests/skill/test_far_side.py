"""A swerve carried on from one obstacle does not take the next one on its far side (issue 26).

A skill whose nominal weight ``Q`` holds the path nowhere (on its lower
plausibility wall, ``Q ℓ² ≤ 2e-3``: a potential-field person's fit ends there)
swerves below a box that touches the path, 15-20 cm out, and stays there:
before, it went round a second box, 2 cm clear of the path below it, on that
box's far side (12.6 cm below its centre); every person of the fidelity
benchmark passes such a box on the nominal's side. With a nominal weight that
holds the path (``Q = 1``) it passes it on the nominal's side already.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from lfdkit.emulate import Reward
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill

X = np.linspace(0.0, 1.0, 100)
FREE = [np.column_stack([X, 0.002 * s * np.sin(np.pi * X)]) for s in (-1.0, 0.0, 1.0)]
SCENE = Scene(
    (Obstacle("box", [0.2, 0.04], radius=0.05), Obstacle("box", [0.5, -0.07], radius=0.05))
)


@pytest.mark.parametrize("q", [0.0016, 1.0])
def test_a_clear_box_is_passed_on_the_nominal_side(q: float) -> None:
    skill = Skill().fit(FREE).adopt(Reward(q, {"box": [73.0, 796.0]}))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plan = skill.plan_details([0.0, 0.0], [1.0, 0.0], SCENE)
    above = float(np.interp(0.5, plan.points[:, 0], plan.points[:, 1])) - (-0.07)
    assert above > 0.05  # above the second box: the nominal's side
    assert plan.clearance.min() >= 0.0
