"""Old home of the ``lfdkit demo`` workflow, now :mod:`lfdkit.tasks.sweeping.demo`.

Kept so that old imports work (with a ``DeprecationWarning``); new code
imports from :mod:`lfdkit.tasks.sweeping`.
"""

# ruff: noqa: F822 (the names of __all__ are found by __getattr__)
from lfdkit._moved import moved

__all__ = ["INCOMPLETE_MARKER", "NEW_GOAL", "N_STEPS", "UNSEEN_DESIGNS", "demo_outputs", "run_demo"]

__getattr__ = moved(__name__, "lfdkit.tasks.sweeping", __all__)
