"""Old home of the sweeping experiment, now :mod:`lfdkit.tasks.sweeping` (``scenarios``, ``demo``).

Kept so that old imports work (with a ``DeprecationWarning``); new code
imports from :mod:`lfdkit.tasks.sweeping`.
"""

# ruff: noqa: F822 (the names of __all__ are found by __getattr__)
from lfdkit._moved import moved

__all__ = [
    "GOAL_APPROACH",
    "NOMINAL_DUSTPAN",
    "SweepScenario",
    "default_planners",
    "random_scenarios",
    "run_experiment",
    "summarize",
]

__getattr__ = moved(__name__, "lfdkit.tasks.sweeping", __all__)
