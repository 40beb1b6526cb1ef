"""The compiled 2-D MPC loop plans what the planner's Python loop plans, bit for bit.

``receding_horizon_2d`` (:mod:`lfdkit.emulate._planner_kernels`) runs the
whole receding horizon of a 2-D scene in one call; the Python loop of
:func:`lfdkit.emulate.planner._receding_horizon` stays for the NumPy forms,
3-D and a moving problem's own window grids. Here both run numba's kernels
(the Python loop by turning the planner's choice of loop off), so any
difference is the loop's: random scenes with hard radii, both routes
(lookahead or the window's own grid), the goal approach, short and long
horizons and a moving obstacle.
"""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.core import kernels
from lfdkit.emulate import Reward, UnsafePlanError, plan_path, planner
from lfdkit.model.motion import ConstantVelocity
from lfdkit.model.scene import Obstacle, Scene

REWARD = Reward(6.0, {"a": [3000.0, 250.0], "b": [600.0, 1500.0]})


def scene_of(seed: int, nominal: np.ndarray, moving: bool) -> Scene:
    """2–4 obstacles near random points of ``nominal``, some with a radius."""
    rng = np.random.default_rng(seed)
    obstacles = []
    for o, k in enumerate(rng.integers(8, len(nominal) - 8, size=int(rng.integers(2, 5)))):
        centre = nominal[k] + [0.0, rng.normal(0.0, 0.03)]
        motion = ConstantVelocity([0.0, 0.2]) if moving and o == 0 else None
        obstacles.append(
            Obstacle("ab"[o % 2], centre, float(rng.uniform(0.0, 0.02)), motion=motion)
        )
    return Scene(tuple(obstacles))


def planned(compiled: bool, monkeypatch: pytest.MonkeyPatch, **args):
    monkeypatch.setattr(planner, "use_compiled", lambda: compiled)
    try:
        return plan_path(**args)
    except UnsafePlanError as error:
        return str(error)


@pytest.mark.parametrize("seed", range(6))
def test_compiled_loop_plans_the_python_loops_plan(monkeypatch, seed: int) -> None:
    monkeypatch.setenv(kernels.KERNELS_VARIABLE, "numba")
    x = np.linspace(0.0, 1.0, 50)
    nominal = np.column_stack([x, (seed - 2.5) * 0.06 * np.sin(np.pi * x)])
    moving = seed == 5
    scene = scene_of(seed, nominal, moving)
    times = {"times": np.linspace(0.0, 1.0, 40)} if moving else {}
    for horizon, lookahead, goal, clearance in [
        (12, False, None, 0.0),
        (8, False, "auto", 0.01),
        (12, True, "auto", 0.0),
        (5, True, None, 0.01),
    ]:
        args = dict(
            reward=REWARD,
            nominal=nominal,
            scene=scene,
            horizon=horizon,
            lookahead=lookahead,
            goal_approach=goal,
            clearance=clearance,
            n_points=40,
            **times,
        )
        python_loop, compiled_loop = (planned(c, monkeypatch, **args) for c in (False, True))
        if isinstance(python_loop, str):
            assert compiled_loop == python_loop
            continue
        np.testing.assert_array_equal(compiled_loop.points, python_loop.points)
        assert (compiled_loop.n_iter, compiled_loop.converged) == (
            python_loop.n_iter,
            python_loop.converged,
        )
