"""Emulation: learn how the demonstrator reacts to obstacles (a reward) and plan in new scenes.

Layout, each module with its compiled loops beside it:

* the scenes it works in are :mod:`lfdkit.model.scene` (data model) and
  :mod:`lfdkit.io.scenes` (files), re-exported here;
* :mod:`.reward`: the reward ``R(x)`` of a point (nominal weight, one
  precision per obstacle class) and its parameters;
* :mod:`.problem`: the planning problem both the planner and the IOC solve,
  the nominal's normals (:class:`Corridor`), the cost of lateral offsets
  (:class:`~.problem.Problem`) and its projected Newton solver
  (``_problem_kernels``);
* :mod:`.planner`: global grid search, receding horizon and safety checks,
  :func:`plan_path` (``_planner_kernels``);
* :mod:`.taut`: the shortest path round the obstacles that keeps their
  clearances, :func:`taut_plan` (a person who keeps a margin);
* :mod:`.moving`: moving obstacles in closed loop, :class:`RecedingPlanner`
  (one MPC window per control step, the obstacles where they are predicted);
* :mod:`.metrics`: measures of paths against demonstrations and scenes
  (e1, e2, clearance, MSE_R, ...);
* :mod:`.ioc`: the reward fitted to demonstrations, :class:`IOC`, with exact
  gradients (``_ioc_kernels``).
"""

from lfdkit.core.lazy import lazy_names
from lfdkit.io.scenes import load_scene, load_scenes, save_scenes
from lfdkit.model.box import Box
from lfdkit.model.half_space import HalfSpace
from lfdkit.model.scene import Capsule, Obstacle, Scene

# Loaded on first use (PEP 562): `lfdkit plan` needs the planner, not the IOC
# (NumPy/SciPy optimisation set-up) or the moving-obstacle MPC (issue 30).
__getattr__, __dir__ = lazy_names(
    __name__,
    {
        "IOC": "ioc",
        "RecedingPlanner": "moving",
        "Plan": "planner",
        "UnsafePlanError": "planner",
        "plan_path": "planner",
        "taut_plan": "taut",
        "Corridor": "problem",
        "Reward": "reward",
    },
    globals(),
)

__all__ = [
    "IOC",
    "Box",
    "Capsule",
    "Corridor",
    "HalfSpace",
    "Obstacle",
    "Plan",
    "RecedingPlanner",
    "Reward",
    "Scene",
    "UnsafePlanError",
    "load_scene",
    "load_scenes",
    "plan_path",
    "save_scenes",
    "taut_plan",
]
