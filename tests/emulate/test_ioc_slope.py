"""How steeply the demonstrations swerve, against the planner's action bound (``max_slope``).

A person who swerves more steeply than the plan may (a late swerver: out at
slope 1.5, against the default bound 1) cannot be followed: on the fidelity
benchmark its plans passed a quarter of the obstacles on other sides. The
fit measures the slope and warns; a skill's way back to the goal may be as
steep (``test_planner_goal.py``).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from lfdkit.emulate import IOC, plan_path
from lfdkit.emulate.ioc import demonstrated_slope, prepare_demos
from lfdkit.model.scene import Obstacle, Scene

from .test_ioc import TRUE, demonstrations, nominal


def straight() -> np.ndarray:
    x = np.linspace(0.0, 1.0, 300)
    return np.column_stack([x, np.zeros_like(x)])


def swerve(out: float, back: float, height: float = 0.1) -> np.ndarray:
    """Out at slope ``out`` from x = 0.4, ``height`` up, back at ``back`` (straight nominal)."""
    x = np.linspace(0.0, 1.0, 2001)
    up = np.clip((x - 0.4) * out, 0.0, height)
    top = 0.4 + height / out
    down = np.clip(height - (x - top - 0.05) * back, 0.0, height)
    return np.column_stack([x, np.minimum(up, down)])


@pytest.mark.parametrize("out", [0.5, 1.5, 3.0])
def test_the_slope_of_a_ramp_is_its_slope(out: float) -> None:
    demos = [swerve(out, 0.2) for _ in range(3)]
    data = prepare_demos(demos, [Scene()] * 3, straight(), 100)
    assert demonstrated_slope(data) == pytest.approx(out, rel=0.02)


def test_plans_within_the_action_bound_are_within_it() -> None:
    path = nominal()
    scenes = [Scene((Obstacle("obstacle", path[i] + [0.0, 0.01]),)) for i in (90, 150, 210)]
    for max_slope in (0.3, 1.0):
        plans = [
            plan_path(TRUE, path, s, goal_approach=None, max_slope=max_slope).points for s in scenes
        ]
        slope = demonstrated_slope(prepare_demos(plans, scenes, path, 100))
        assert 0.5 * max_slope < slope <= max_slope * (1.0 + 1e-6)


def test_a_swerve_steeper_than_the_action_bound_is_warned() -> None:
    demos, scenes = demonstrations(3)
    steep = [swerve(1.5, 0.2) for _ in range(3)]
    flat_scenes = [Scene((Obstacle("obstacle", [0.44, 0.0]),))] * 3
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ioc = IOC(max_iter=2, n_starts=1).fit(steep, flat_scenes, straight())
    said = [str(w.message) for w in caught if "steeper than max_slope 1" in str(w.message)]
    assert ioc.demonstrated_slope_ == pytest.approx(1.5, rel=0.02)
    assert len(said) == 1 and "max_slope=1.5 lets them" in said[0], said
    # Demonstrations the planner itself made (bound 1) or a bound as steep: nothing said.
    for fit in (
        lambda: IOC(max_iter=2, n_starts=1).fit(demos, scenes, nominal()),
        lambda: IOC(max_iter=2, n_starts=1, max_slope=1.5).fit(steep, flat_scenes, straight()),
    ):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fit()
        assert not [w for w in caught if "max_slope" in str(w.message)]
