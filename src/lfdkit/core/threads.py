"""One BLAS thread for a block of many small linear-algebra calls.

Threaded BLAS makes many small eigen-solves and matrix products several times
slower on a busy machine. ``threadpoolctl.threadpool_limits`` finds the loaded
BLAS libraries on every call (reading the process's memory map, milliseconds);
the controller here finds them once, so the limit costs microseconds inside
hot paths such as every plan.
"""

from __future__ import annotations

import os
from contextlib import AbstractContextManager

from threadpoolctl import ThreadpoolController

_controller: ThreadpoolController | None = None


def one_blas_thread() -> AbstractContextManager:
    """Context manager limiting BLAS (and OpenMP) to one thread."""
    global _controller
    if _controller is None:
        _controller = ThreadpoolController()
    return _controller.limit(limits=1)


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity; all of them off Linux)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1
