"""One compiled version of each emulate kernel: the call sites agree on argument types.

numba compiles a kernel once per distinct argument types; a Fortran-ordered
or strided array, or an int literal passed from another kernel, is a new
version (10–30 s of compile CPU each, cold: the whole first learn and plan
after an install, and CI's fresh clone). Static and moving-obstacle plans (2-D
and 3-D, full horizon and MPC) and the IOC's two sensitivities run in a fresh
process with numba's kernels; every kernel then holds one signature.
A fresh process because this one's kernels already hold whatever other tests
called them with; its kernels come from numba's cache the suite fills (about
5 s then; cold, about 100 s of compiling the suite would otherwise do itself).
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from lfdkit.emulate import Corridor, Reward
from lfdkit.emulate.problem import Problem
from lfdkit.model.motion import ConstantVelocity
from lfdkit.model.scene import Obstacle, Scene

SCRIPT = textwrap.dedent(
    """
    import sys
    import numpy as np
    from numba.core.dispatcher import Dispatcher
    from lfdkit.emulate import Reward, plan_path
    from lfdkit.emulate.ioc import TrainingLoss, prepare_demos
    from lfdkit.model.motion import ConstantVelocity
    from lfdkit.model.scene import Obstacle, Scene

    x = np.linspace(0.0, 1.0, 60)
    nominal = np.column_stack([x, 0.2 * np.sin(np.pi * x)])
    reward = Reward(10.0, {"cup": [2500.0, 215.0]})
    scenes = [Scene((Obstacle("cup", nominal[k] + [0.0, dy]),))
              for k, dy in ((25, 0.01), (35, -0.02))]
    demos = [plan_path(reward, nominal, s, horizon=8, lookahead=False).points for s in scenes]
    loss = TrainingLoss(prepare_demos(demos, scenes, nominal, 40), ("cup",), 1.0)
    loss.mpc(reward.theta, 8)
    warm = [np.where(d.found[1:, None], d.target[1:], 0.0) for d in loss.data]
    loss.full_horizon(reward.theta, warm)
    for horizon in (None, 8):
        plan_path(reward, nominal, scenes[0], horizon=horizon, n_points=40, clearance=0.01)
        crossing = Obstacle("cup", [0.5, -0.2], 0.03, motion=ConstantVelocity([0.0, 0.3]))
        moving = Scene((crossing, Obstacle("cup", [0.3, 0.05])))  # two: (n, 2) terms
        plan_path(reward, nominal, moving, horizon=horizon, n_points=40,
                  times=np.linspace(0.0, 1.0, 40), clearance=0.01)
        nominal3 = np.column_stack([nominal, 0.1 * x * x])
        reward3 = Reward(10.0, {"cup": [2500.0, 300.0, 215.0]})
        scene3 = Scene((Obstacle("cup", nominal3[30] + [0.0, 0.01, 0.0], 0.01),))
        plan_path(reward3, nominal3, scene3, horizon=horizon, n_points=40, clearance=0.01)
    for name, module in sorted(sys.modules.items()):
        if name.startswith("lfdkit"):
            for attr, obj in vars(module).items():
                if isinstance(obj, Dispatcher) and obj.__module__ == name:
                    print(f"{name}.{attr}", len(obj.signatures), obj.signatures)
    """
)


@pytest.mark.slow
def test_each_kernel_compiles_one_version() -> None:
    env = dict(os.environ, LFDKIT_KERNELS="numba", OMP_NUM_THREADS="1")
    env["PYTHONPATH"] = os.pathsep.join([*sys.path])
    result = subprocess.run(
        [sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=600
    )
    assert result.returncode == 0, result.stderr[-2000:]
    counts = {line.split()[0]: int(line.split()[1]) for line in result.stdout.splitlines()}
    # The kernels called from Python (a renamed or dropped one is noticed here). Those
    # only called from other kernels (offsets_newton) are compiled, with the versions
    # they need of their callees, only when the cache is cold: loaded from the cache,
    # their callers hold them, so their own count is 0 then.
    for name in (
        "lfdkit.emulate._problem_kernels.planner_newton",
        "lfdkit.emulate._ioc_kernels.mpc_sensitivity",
        "lfdkit.emulate._ioc_kernels.plan_sensitivity",
        "lfdkit.emulate._planner_kernels.grid_state_costs",
        "lfdkit.emulate._planner_kernels.grid_hard_costs",
        "lfdkit.emulate._planner_kernels.grid_backward",
        "lfdkit.emulate._planner_kernels.receding_horizon_2d",
    ):
        assert counts.get(name) == 1, name
    several = [line for line in result.stdout.splitlines() if int(line.split()[1]) > 1]
    assert not several, "\n".join(several)


def test_moving_obstacles_give_c_ordered_kernel_arrays() -> None:
    # Predicted centres per point made Fortran-ordered terms (and strided windows):
    # a second compiled version of every planner kernel.
    x = np.linspace(0.0, 1.0, 30)
    corridor = Corridor.from_path(np.column_stack([x, 0.1 * x]), 30)
    cup = Obstacle("cup", [0.5, -0.2], 0.03, motion=ConstantVelocity([0.0, 0.3]))
    problem = Problem.from_scene(
        Reward(10.0, {"cup": [2500.0, 215.0]}),
        corridor,
        Scene((cup, Obstacle("cup", [0.3, 0.05]))),
        times=np.linspace(0.0, 1.0, 30),
    )
    assert problem.moving and problem.c.shape[1] == 2
    for arrays in (problem.kernel_arguments(), problem.window(3, 11).kernel_arguments()):
        assert all(np.isscalar(array) or array.flags.c_contiguous for array in arrays)
