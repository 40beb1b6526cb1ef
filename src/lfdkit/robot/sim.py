"""Old home of the sweeping simulation, now :mod:`lfdkit.tasks.sweeping` (``sim``, ``scenarios``).

The sweeping scene is a task built on the robot layer, not part of it. Kept so
that old imports (``from lfdkit.robot import sim``) work: each name is found in
:mod:`lfdkit.tasks.sweeping` on first use, with a ``DeprecationWarning``; this
module imports nothing of the task itself. New code imports from
:mod:`lfdkit.tasks.sweeping`.
"""

# ruff: noqa: F822 (the names of __all__ are found by __getattr__)
from lfdkit._moved import moved

__all__ = [
    "BRUSH",
    "CUBE_SIZE",
    "HOME",
    "SETTLE_TIME",
    "TIMESTEP",
    "TRACKING_TOLERANCE",
    "Brush",
    "Dustpan",
    "SweepResult",
    "SweepingTask",
    "build_model",
    "execute_sweep",
    "simulate_sweep",
    "sweep_motion",
    "sweeping_mjcf",
]

__getattr__ = moved(__name__, "lfdkit.tasks.sweeping", __all__)
