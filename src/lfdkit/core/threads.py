"""Threads: one BLAS thread for many small linear-algebra calls, work side by side.

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

Also the process's pool of worker threads (:func:`shared_pool`,
:func:`map_on_threads`: the IOC's demonstrations, the model choice's
replans; the compiled kernels release the GIL) and :func:`side_by_side`,
which catches each task's warnings in its own thread
(:func:`warnings_by_thread`, :func:`caught_in_thread`) and says them again
in order: ``warnings.catch_warnings`` changes the process's filters and
hook, so two threads using it side by side undo each other's, and that had
kept a skill's model choice on one thread. With its folds and replans side
by side, a 3-D fold's fit (``benchmarks/boxes_sides.py``, 2 cores) went
from 10.2–10.6 to 7.6–7.8 s of wall time at the median, the same results.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
import warnings
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import AbstractContextManager
from typing import Any, TypeVar

from threadpoolctl import ThreadpoolController

T = TypeVar("T")

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


#: The threads work runs on side by side, made once per process: a pool made per
#: use (about 320 loss evaluations in a 2-D skill fit of 10 demonstrations) started
#: and joined its threads each time. Issue 26, CPU s of ``Skill.fit`` (median of 3
#: alternated runs, loaded 2 cores): field person 6.0 -> 5.0 (10 demonstrations),
#: 4.8 -> 3.5 (6); thesis person 3.8 -> 3.7, 2.6 -> 2.6. Results the same to the bit.
_POOL: ThreadPoolExecutor | None = None


def shared_pool() -> ThreadPoolExecutor:
    """The process's pool of :func:`available_cores` threads (made on first use).

    Work submitted to it must not wait on other work submitted to it (a full
    pool would wait for ever): :func:`map_on_threads` runs serially there.
    """
    global _POOL
    if _POOL is None:
        _POOL = ThreadPoolExecutor(max_workers=available_cores(), thread_name_prefix="lfdkit")
    return _POOL


def map_on_threads(work: Callable[..., T], *arguments: Iterable[Any]) -> list[T]:
    """``[work(*a) for a in zip(*arguments)]``, on :func:`shared_pool` where there are cores.

    In order; serially with one core, one item, or when called from one of
    the pool's own tasks (waiting there on the pool could wait for ever: every
    thread of a full pool waiting for a task none is free to run). A task
    runs with the caller's :func:`caught_in_thread` list, if any: a warning it
    shows goes where the caller's would.
    """
    items = list(zip(*arguments, strict=True))
    if min(available_cores(), len(items)) <= 1 or getattr(_sinks, "in_pool", False):
        return [work(*item) for item in items]
    caught = getattr(_sinks, "caught", None)

    def run(item: tuple[Any, ...]) -> T:
        outer = getattr(_sinks, "caught", None)
        _sinks.caught, _sinks.in_pool = caught, True
        try:
            return work(*item)
        finally:
            _sinks.caught, _sinks.in_pool = outer, False

    return list(shared_pool().map(run, items))


def side_by_side(
    work: Callable[[Any], T], items: Iterable[Any], *, own_threads: bool = False
) -> list[T]:
    """``[work(x) for x in items]`` on threads, each one's warnings given again here, in order.

    Each task's warnings are caught in its thread (:func:`caught_in_thread`)
    and given again by the caller once all are done, in the items' order
    (identical ones once per call, as the "default" filter would), so what is
    said does not depend on which thread ran first; BLAS keeps one thread
    throughout (limits entered and left side by side would restore each
    other's). ``own_threads``: the tasks run on threads made for this call,
    not :func:`shared_pool`'s, for work that itself hands tasks to the pool
    and waits for them.
    """
    items = list(items)

    def run(item: Any) -> tuple[T, list[warnings.WarningMessage]]:
        with caught_in_thread() as caught:
            return work(item), caught

    with one_blas_thread(), warnings_by_thread():
        workers = min(available_cores(), len(items))
        if not own_threads or workers <= 1:
            done = map_on_threads(run, items)
        else:
            with ThreadPoolExecutor(workers, thread_name_prefix="lfdkit-own") as pool:
                done = list(pool.map(run, items))
    registry: dict[Any, Any] = {}
    for _, caught in done:
        for w in caught:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno, registry=registry)
    return [result for result, _ in done]


def _forget_pool() -> None:
    global _POOL
    _POOL = None


# A forked child (batch workers) has none of the parent's threads: it makes its own.
os.register_at_fork(after_in_child=_forget_pool)

# .caught: the list the current thread's warnings go to; .in_pool: a task of the pool's
_sinks = threading.local()
_hooks = 0  # warnings_by_thread contexts open (the hook is the process's)
_hooks_lock = threading.Lock()


@contextlib.contextmanager
def warnings_by_thread() -> Iterator[None]:
    """While open, a warning shown in a thread inside :func:`caught_in_thread` goes to its list.

    Entered by the thread that hands work to others, around all of it: it
    sets the process's warnings hook once and makes every ``UserWarning``
    shown ("always", as a ``catch_warnings(record=True)`` that counts them
    would), restoring both on exit. A warning shown outside a
    :func:`caught_in_thread` block goes where it went before.
    """
    global _hooks
    with warnings.catch_warnings():
        warnings.simplefilter("always", UserWarning)
        shown = warnings.showwarning

        def show(message, category, filename, lineno, file=None, line=None):  # type: ignore[no-untyped-def]
            caught = getattr(_sinks, "caught", None)
            if caught is None:
                shown(message, category, filename, lineno, file, line)
            else:
                caught.append(
                    warnings.WarningMessage(message, category, filename, lineno, file, line)
                )

        warnings.showwarning = show
        with _hooks_lock:
            _hooks += 1
        try:
            yield
        finally:
            with _hooks_lock:
                _hooks -= 1


@contextlib.contextmanager
def caught_in_thread() -> Iterator[list[warnings.WarningMessage]]:
    """The warnings this thread shows while inside, in a list (not shown).

    Inside :func:`warnings_by_thread`, each thread its own; outside, it opens
    one for itself (as ``catch_warnings(record=True)`` with ``UserWarning``
    "always": other threads must not use warnings meanwhile). Nested blocks
    keep their own: the inner one's warnings are not the outer one's, as
    nested ``catch_warnings(record=True)``.
    """
    if _hooks <= 0:
        with warnings_by_thread(), caught_in_thread() as caught:
            yield caught
        return
    outer = getattr(_sinks, "caught", None)
    caught = []
    _sinks.caught = caught
    try:
        yield caught
    finally:
        _sinks.caught = outer
