"""Which form of a kernel a process runs: numba's compiled one or its NumPy form.

Why (issue 30): before its first compiled kernel runs, a fresh process pays
about 1.1 s of CPU for numba on a 2-core machine (importing numba 0.4 s,
``scipy.linalg`` for its BLAS check 0.3 s, its one-time set-up 0.5 s, the
cached kernels 0.1 s), for a plan of the README's example that then takes
0.07 s of CPU. The planner's kernels (the DMP's quintics, the grid search,
the projected Newton solver) also have NumPy forms
(:mod:`lfdkit.emulate._planner_numpy`, ``lfdkit.imitate._dmp_numerics``)
that need no numba: about 7× slower per plan (0.5 s of CPU for that example
at load 15, ``benchmarks/startup.py``) but without the start-up, so a
one-shot ``lfdkit plan`` runs them (1.85 → 0.79 s of CPU) and a batch runs
numba's.

The rule, ``LFDKIT_KERNELS`` in the environment:

``auto`` (the default)
    numba's kernels once numba is loaded in the process (something else
    needed it: a preloaded batch worker, the IOC, GMR), or once the NumPy
    forms have taken :data:`SWITCH_SECONDS` of CPU in it — a rent-or-buy
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
"""

from __future__ import annotations

import functools
import importlib
import os
import sys
import time
from collections.abc import Callable
from typing import Any

__all__ = ["KERNELS_VARIABLE", "SWITCH_SECONDS", "counted", "kernel", "use_compiled"]

#: The environment variable choosing the kernels: "auto", "numba" or "numpy".
KERNELS_VARIABLE = "LFDKIT_KERNELS"
#: Seconds the NumPy forms may take in one process before "auto" turns to numba
#: (about numba's start-up, 1.1 s of CPU here).
SWITCH_SECONDS = 1.0
_CHOICES = ("auto", "numba", "numpy")

# Seconds spent in the NumPy forms in this process, and the nesting depth of counted calls.
_spent = {"seconds": 0.0, "depth": 0}


def use_compiled() -> bool:
    """Whether a kernel called now should be numba's (see the module's rule)."""
    mode = os.environ.get(KERNELS_VARIABLE, "auto").strip().lower() or "auto"
    if mode not in _CHOICES:
        raise ValueError(
            f"{KERNELS_VARIABLE}={mode!r}: not a kernel choice; use one of {', '.join(_CHOICES)}"
        )
    if mode != "auto":
        return mode == "numba"
    return "numba" in sys.modules or _spent["seconds"] >= SWITCH_SECONDS


def kernel(name: str, compiled: str, numpy_form: str) -> Callable[..., Any]:
    """The function ``name`` from module ``compiled`` or ``numpy_form``, by :func:`use_compiled`.

    Both modules define ``name`` with the same arguments and effects.
    """
    module = compiled if use_compiled() else numpy_form
    return getattr(importlib.import_module(module), name)


def counted(function: Callable[..., Any]) -> Callable[..., Any]:
    """Decorate a NumPy form: its wall seconds count towards :data:`SWITCH_SECONDS`.

    Nested calls of counted functions count once (the outermost).
    """

    @functools.wraps(function)
    def timed(*args: Any, **kwargs: Any) -> Any:
        if _spent["depth"]:
            return function(*args, **kwargs)
        _spent["depth"] = 1
        start = time.process_time()  # CPU: wall time on a loaded machine would switch early
        try:
            return function(*args, **kwargs)
        finally:
            _spent["depth"] = 0
            _spent["seconds"] += time.process_time() - start

    return timed
