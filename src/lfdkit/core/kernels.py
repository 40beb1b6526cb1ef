"""Which form of a kernel a process runs: numba's compiled one or its NumPy form.

Why (issue 30): before its first compiled kernel runs, a fresh process pays
about 1.1 s of CPU for numba on a 2-core machine (importing numba 0.4 s,
``scipy.linalg`` for its BLAS check 0.3 s, its one-time set-up 0.5 s, the
cached kernels 0.1 s), for a plan of the README's example that then takes
0.07 s of CPU. The planner's kernels (the DMP's quintics, the grid search,
the projected Newton solver) also have NumPy forms
(:mod:`lfdkit.emulate._planner_numpy`, ``lfdkit.imitate._dmp_numerics``)
that need no numba: about 2× slower per plan (0.14–0.15 s of CPU for that
example, its 2-D receding-horizon windows solved on Python floats;
``benchmarks/startup.py``) but without the start-up, so a
one-shot ``lfdkit plan`` runs them (1.85 → 0.79 s of CPU), and so does a
batch worker until it has planned for a second (it starts without numba:
:mod:`lfdkit.app.worker_preload`).

The rule, ``LFDKIT_KERNELS`` in the environment:

``auto`` (the default)
    numba's kernels once numba is loaded in the process (something else
    needed it: the IOC, GMR, MuJoCo's checks), or once the process
    has taken :data:`SWITCH_SECONDS` of CPU since its first NumPy form ran
    (looked at every :data:`CHECK_SECONDS` of wall time) — a rent-or-buy
    rule: a process that plans many times pays numba's start-up once and at
    most about twice what the better choice would have cost. The choice is
    made per kernel call, so a long plan may finish on numba's kernels.
``numba`` / ``numpy``
    always that form.

The NumPy forms do the compiled kernels' floating-point operations in the
same order (sums accumulated one term at a time, not NumPy's pairwise sums),
so on the machines tested they give the same plans bit for bit; where
NumPy's ``exp`` or LAPACK's Cholesky factor differs from numba's in the last
bit, plans agree to round-off (``tests/emulate/test_planner_numpy.py`` holds
them to 1e-9 relative on random scenes and reports exact equality).
The planner's 2-D receding-horizon loop is one compiled kernel
(``receding_horizon_2d``, issue 26: its Python glue was four fifths of an MPC
plan); its NumPy form is the planner's Python loop, which
:func:`use_compiled` chooses the same way (``tests/emulate/test_planner_loop.py``).
"""

from __future__ import annotations

import importlib
import os
import sys
import time
from collections.abc import Callable
from typing import Any

__all__ = [
    "CHECK_SECONDS",
    "KERNELS_VARIABLE",
    "SWITCH_SECONDS",
    "cached_njit",
    "kernel",
    "restart_clock",
    "use_compiled",
]

#: The environment variable choosing the kernels: "auto", "numba" or "numpy".
KERNELS_VARIABLE = "LFDKIT_KERNELS"
#: CPU seconds since its first NumPy kernel after which "auto" turns a process to numba
#: (about numba's start-up, 1.1 s of CPU here).
SWITCH_SECONDS = 1.0
#: Wall seconds between two looks at the CPU clock once it may have passed the switch
#: (reading it is a system call: hundreds of µs on a loaded machine, too slow per kernel).
CHECK_SECONDS = 0.1
_CHOICES = ("auto", "numba", "numpy")

# The process's CPU clock at its first NumPy kernel (None: none yet), when to look at it
# next (a wall-clock time: wall time never runs slower than one thread's CPU time), and
# whether it has passed the switch.
_clock: dict = {"cpu_start": None, "next_look": 0.0, "switched": False}
# The kernel modules already imported whole (import_module returned), by name: an MPC
# plan asks for a kernel several times a step, and import_module's look-up was a tenth
# of a 2-D plan's CPU time (issue 26).
_modules: dict = {}


def use_compiled() -> bool:
    """Whether a kernel called now should be numba's (see the module's rule)."""
    mode = os.environ.get(KERNELS_VARIABLE, "auto").strip().lower() or "auto"
    if mode not in _CHOICES:
        raise ValueError(
            f"{KERNELS_VARIABLE}={mode!r}: not a kernel choice; use one of {', '.join(_CHOICES)}"
        )
    if mode != "auto":
        return mode == "numba"
    if _clock["switched"] or "numba" in sys.modules:
        return True
    if _clock["cpu_start"] is None:
        return False
    now = time.perf_counter()
    if now < _clock["next_look"]:
        return False
    _clock["next_look"] = now + CHECK_SECONDS
    _clock["switched"] = time.process_time() - _clock["cpu_start"] >= SWITCH_SECONDS
    return _clock["switched"]


def restart_clock() -> None:
    """Forget the CPU spent in NumPy forms so far: the rule starts afresh.

    For a process forked from one that warmed the NumPy forms up (a batch
    worker's fork server): the child's CPU clock starts at zero, so the
    parent's would otherwise hold the switch back by the parent's seconds.
    """
    _clock.update(cpu_start=None, next_look=0.0, switched=False)


def kernel(name: str, compiled: str, numpy_form: str) -> Callable[..., Any]:
    """The function ``name`` from module ``compiled`` or ``numpy_form``, by :func:`use_compiled`.

    Both modules define ``name`` with the same arguments and effects. The
    first NumPy form handed out starts the clock of the switch.
    """
    if use_compiled():
        module = compiled
    else:
        module = numpy_form
        if _clock["cpu_start"] is None:
            _clock["cpu_start"] = time.process_time()
            _clock["next_look"] = time.perf_counter() + SWITCH_SECONDS
    # import_module, not a look-up in sys.modules: it waits for a module another thread
    # is still importing (the IOC plans on threads) instead of handing out a half-made one;
    # once it has returned, the module is whole and kept.
    loaded = _modules.get(module)
    if loaded is None:
        loaded = _modules[module] = importlib.import_module(module)
    return getattr(loaded, name)


def cached_njit(**options: Any) -> Callable[[Callable[..., Any]], Any]:
    """``numba.njit(cache=True, **options)``, or without the cache where none can be written.

    Numba caches machine code in ``__pycache__`` next to the source file, or
    in the user's cache folder (``NUMBA_CACHE_DIR``) when that is read-only,
    as in a system-wide installation. Where neither is writable it refuses to
    cache; the function is then compiled in every process, silently. For the
    compiled kernel modules of every floor; numba is imported only by them.
    """
    import numba

    def decorate(function: Callable[..., Any]) -> Any:
        try:
            return numba.njit(cache=True, **options)(function)
        except RuntimeError:  # "cannot cache function ...: no locator available"
            return numba.njit(**options)(function)

    return decorate
