"""What every local batch worker has loaded before its first task, loaded once (issue 30).

:class:`lfdkit.app.batch.ProcessExecutor` starts its workers on Linux from a
``forkserver`` that imports this module once: the fork server keeps one
BLAS/OpenMP/numba thread (set before NumPy loads), imports NumPy, numba and
the skill, and plans one small path around one obstacle, so numba's
compiler is set up and the planner's cached kernels are loaded. Each worker
is then a fork of that process and starts warm, instead of each one paying
the imports and the kernel loading again (about 1.4 s of CPU a worker, most
of it numba setting itself up; the first plan of a warm worker takes
about 0.1 s). numba is imported first: with it loaded, the planner runs its
compiled kernels, not the NumPy forms a one-shot ``lfdkit plan`` runs
(:mod:`lfdkit.core.kernels`), which are several times slower per plan.

Importing this module does the warm-up; nothing else imports it. It never
raises: a warm-up that fails leaves the workers to load what they need
themselves, as spawned workers do.
"""

from __future__ import annotations

import os
import warnings

from lfdkit.app.batch import ONE_THREAD_ENV

__all__ = ["warm_up"]


def warm_up() -> bool:
    """Import what a worker needs and plan one small path; whether it all worked.

    The planner is called directly on a drawn nominal path: fitting a skill
    here would import SciPy's signal and interpolation packages, which a
    worker that plans from a skill file never needs.
    """
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            import numba  # noqa: F401  (so the plans below, and the workers', run numba's kernels)
            import numpy as np

            import lfdkit.skill  # noqa: F401  (what a task unpickles a skill into)
            from lfdkit.emulate import Reward, plan_path
            from lfdkit.model.scene import Scene

            u = np.linspace(0.0, 1.0, 50)
            nominal = np.column_stack([u, 0.2 * np.sin(np.pi * u)])
            reward = Reward(1.0, {"cup": 400.0 * np.eye(2)})
            scene = Scene.from_arrays(["cup"], [[0.5, 0.25]], [0.05])
            plan_path(reward, nominal, scene, horizon=8)
            plan_path(reward, nominal, scene)
    except Exception:  # best effort: a worker loads what it needs itself
        return False
    return True


os.environ.update(ONE_THREAD_ENV)  # before NumPy loads: the forks inherit the thread pools
warm_up()
