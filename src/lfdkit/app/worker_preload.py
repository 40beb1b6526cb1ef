"""What every local batch worker has loaded before its first task, loaded once (issue 30).

:class:`lfdkit.app.batch.ProcessExecutor` starts its workers on Linux from a
``forkserver`` that imports this module once: the fork server keeps one
BLAS/OpenMP/numba thread (set before NumPy loads), imports NumPy and the
skill, and plans one small path around one obstacle with the planner's NumPy
kernels (:mod:`lfdkit.core.kernels`), so the planner's modules are loaded
and warm. Each worker is a fork of that process and starts warm, instead of
each one paying the imports again. A local Dask cluster's workers
(``make_executor(dask_local=N)``) fork from the same server.

numba is not loaded here: its start-up (about 1.1 s of CPU, most of it
numba setting itself up and importing ``scipy.linalg``) would run in the one
fork server before any worker exists, while the workers stood idle. Each
worker instead runs the NumPy kernels from its first task and turns to
numba's by the kernels' own rule, after a second of CPU in them: in
parallel, on each worker's core, while it already works. The fork server's
start-up: 1.9–2.0 → 0.56–0.7 s of CPU (``python -c "import
lfdkit.app.worker_preload"``, a loaded 2-core machine).
A worker's task that needs numba for another kernel (the IOC, MuJoCo's
checks) loads it then. 2-D plans are the same bit for bit with either
kernels; 3-D plans agree to round-off (about 1e-11).

For a long batch the fork server imports
:mod:`lfdkit.app.worker_preload_compiled` instead: numba first, then this
module, whose warm-up then loads numba's cached kernels once for every
worker (:func:`lfdkit.app.batch.start_worker_server` chooses).

Importing this module does the warm-up; only the fork server, that module and
:func:`lfdkit.app.batch.load_modules` (a Dask worker, a long serial batch) import it. It never
raises: a warm-up that fails leaves the workers to load what they need
themselves, as spawned workers do.
"""

from __future__ import annotations

import os
import sys
import warnings

from lfdkit.app.batch import ONE_THREAD_ENV
from lfdkit.core.kernels import restart_clock

__all__ = ["warm_up"]


def warm_up() -> bool:
    """Import what a worker needs and plan one small path; whether it all worked.

    The planner is called directly on a drawn nominal path: fitting a skill
    here would import SciPy's signal and interpolation packages, which a
    worker that plans from a skill file never needs. The kernels' clock is
    restarted after: the forks count their own CPU seconds from zero.
    """
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
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
            restart_clock()
    except Exception:  # best effort: a worker loads what it needs itself
        return False
    return True


if "numpy" not in sys.modules:  # a fork server: the forks inherit the thread pools
    os.environ.update(ONE_THREAD_ENV)  # (a serial batch's process keeps its own)
warm_up()
