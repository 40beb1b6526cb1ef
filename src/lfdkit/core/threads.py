"""One BLAS thread for a block of many small linear-algebra calls.

Threaded BLAS makes many small eigen-solves and matrix products several times
slower on a busy machine. ``threadpoolctl.threadpool_limits`` finds the loaded
BLAS libraries on every call (reading the process's memory map, milliseconds);
the controller here finds them once, so the limit costs microseconds inside
hot paths such as every plan.

A controller knows only the libraries loaded when it was made, and SciPy
ships its own OpenBLAS, loaded with ``scipy.linalg`` (numba's ``np.linalg``
calls it), often after NumPy's: a controller made before it left that one
threaded, and a 200 × 200 Cholesky (a 3-D full-horizon plan's Newton step)
took 61 ms of CPU on its 2 threads against 0.4 ms on one, on the busy 2-core
machine (issue 34). A library is loaded by an import, so the controller is
made again when modules were imported since (``len(sys.modules)`` changed:
a few milliseconds, never inside a hot loop, which imports nothing).
"""

from __future__ import annotations

import os
import sys
from contextlib import AbstractContextManager

from threadpoolctl import ThreadpoolController

_controller: ThreadpoolController | None = None
_modules_seen = -1  # len(sys.modules) when the controller was made


def _current_controller() -> ThreadpoolController:
    """The controller of every BLAS (and OpenMP) library loaded now."""
    global _controller, _modules_seen
    modules = len(sys.modules)
    if _controller is None or modules != _modules_seen:
        _controller, _modules_seen = ThreadpoolController(), modules
    return _controller


def one_blas_thread() -> AbstractContextManager:
    """Context manager limiting BLAS (and OpenMP) to one thread."""
    return _current_controller().limit(limits=1)


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity; all of them off Linux)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1
