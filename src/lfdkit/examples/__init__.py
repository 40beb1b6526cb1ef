"""Old home of the shipped example files, now :mod:`lfdkit.tasks.sweeping` (``examples``).

Kept so that old imports work: ``from lfdkit.examples import example_files``
and the submodules :mod:`.sweeping_demo` and :mod:`.sweeping_sim` find the
names in :mod:`lfdkit.tasks.sweeping` on first use, with a
``DeprecationWarning``. New code imports from :mod:`lfdkit.tasks.sweeping`.
"""

from lfdkit._moved import moved

__all__ = ["EXAMPLE_SEED", "example_dataset", "example_files", "write_example_files"]

__getattr__ = moved(__name__, "lfdkit.tasks.sweeping", __all__)
