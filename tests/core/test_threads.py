"""Tests for lfdkit.core.threads: the one-thread limit reaches every BLAS loaded; the
shared pool; warnings caught per thread."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from lfdkit.core.threads import available_cores, one_blas_thread

# In a fresh interpreter: the limit is first used with NumPy's OpenBLAS alone, then
# SciPy's (numba's np.linalg calls it) is loaded and set to 2 threads; inside the
# limit every BLAS must run on one.
_SCRIPT = """
import json
import numpy
from threadpoolctl import threadpool_info, threadpool_limits
from lfdkit.core.threads import one_blas_thread
with one_blas_thread():
    pass
before = len(threadpool_info())
import scipy.linalg
threadpool_limits(2)  # both libraries threaded, as on a user's machine
with one_blas_thread():
    inside = [(i["filepath"], i["num_threads"]) for i in threadpool_info()
              if i["user_api"] == "blas"]
print(json.dumps({"before": before, "inside": inside}))
"""


def test_a_blas_loaded_after_the_first_limit_is_limited_too() -> None:
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    done = subprocess.run(
        [sys.executable, "-c", _SCRIPT], capture_output=True, text=True, env=env, timeout=60
    )
    assert done.returncode == 0, done.stderr
    found = json.loads(done.stdout.strip().splitlines()[-1])
    libraries = {path for path, _ in found["inside"]}
    assert len(libraries) > found["before"]  # SciPy brought its own BLAS after the first limit
    assert all(threads == 1 for _, threads in found["inside"]), found["inside"]


def test_the_limit_is_undone_on_leaving() -> None:
    from threadpoolctl import threadpool_info

    before = {i["filepath"]: i["num_threads"] for i in threadpool_info()}
    with one_blas_thread():
        assert all(i["num_threads"] == 1 for i in threadpool_info() if i["user_api"] == "blas")
    assert {i["filepath"]: i["num_threads"] for i in threadpool_info()} == before


def test_available_cores_is_at_least_one() -> None:
    assert 1 <= available_cores() <= (os.cpu_count() or 1)


def test_each_thread_catches_its_own_warnings_side_by_side() -> None:
    """Two threads, each warning in turn: each list holds its own thread's, nothing is shown."""
    import threading
    import warnings

    from lfdkit.core.threads import caught_in_thread, warnings_by_thread

    turns = threading.Barrier(2)

    def work(name: str) -> list[str]:
        with caught_in_thread() as caught:
            for k in range(20):
                turns.wait()  # interleaved: a shared list or filter would mix them
                warnings.warn(f"{name} {k}", UserWarning, stacklevel=1)
        return [str(w.message) for w in caught]

    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        with warnings_by_thread():
            results: dict[str, list[str]] = {}
            threads = [
                threading.Thread(target=lambda n=n: results.__setitem__(n, work(n))) for n in "ab"
            ]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            warnings.warn("outside", UserWarning, stacklevel=1)  # no list: shown as before
        warnings.warn("after", UserWarning, stacklevel=1)
    assert results == {n: [f"{n} {k}" for k in range(20)] for n in "ab"}
    assert [str(w.message) for w in shown] == ["outside", "after"]


def test_caught_blocks_nest_and_work_alone() -> None:
    import warnings

    from lfdkit.core.threads import caught_in_thread

    hook, filters = warnings.showwarning, list(warnings.filters)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the caller's filters: UserWarning is still caught
        with caught_in_thread() as outer:
            warnings.warn("one", UserWarning, stacklevel=1)
            with caught_in_thread() as inner:
                warnings.warn("two", UserWarning, stacklevel=1)
            warnings.warn("three", UserWarning, stacklevel=1)
            warnings.warn("ignored", DeprecationWarning, stacklevel=1)
    assert [str(w.message) for w in outer] == ["one", "three"]
    assert [str(w.message) for w in inner] == ["two"]
    assert warnings.showwarning is hook and warnings.filters == filters


@pytest.mark.skipif(not hasattr(os, "fork"), reason="os.fork: POSIX only")
def test_the_shared_pool_is_made_once_and_anew_in_a_forked_child() -> None:
    from lfdkit.core.threads import shared_pool

    assert shared_pool() is shared_pool()
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: the parent's threads are not there, a new pool is made
        try:
            from lfdkit.core import threads

            ok = threads._POOL is None and shared_pool().submit(int, "7").result() == 7
            os.write(write, b"1" if ok else b"0")
        finally:
            os._exit(0)
    os.waitpid(pid, 0)
    assert os.read(read, 1) == b"1"


def test_side_by_side_keeps_the_order_and_says_each_task_s_warnings_in_it(monkeypatch) -> None:
    """Results and warnings in the items' order, whichever thread finished first.

    The first task sleeps, so on two threads the second finishes first; the
    tasks' warnings are said once all are done, in order, identical ones once.
    """
    import time
    import warnings

    from lfdkit.core import threads

    monkeypatch.setattr(threads, "available_cores", lambda: 2)

    def work(k: int) -> int:
        if k == 0:
            time.sleep(0.05)
        warnings.warn(f"task {k}", UserWarning, stacklevel=1)
        warnings.warn("the same", UserWarning, stacklevel=1)
        return k * k

    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("default")
        assert threads.side_by_side(work, range(4)) == [0, 1, 4, 9]
    assert [str(w.message) for w in said] == ["task 0", "the same", "task 1", "task 2", "task 3"]


def test_side_by_side_on_its_own_threads_may_use_the_pool(monkeypatch) -> None:
    """Tasks that hand work to the shared pool and wait run on threads of their own.

    On the pool itself two such tasks would take both its threads and wait for ever.
    """
    import warnings

    from lfdkit.core import threads

    monkeypatch.setattr(threads, "available_cores", lambda: 2)
    monkeypatch.setattr(threads, "_POOL", None)

    def work(k: int) -> list[int]:
        # The pool's tasks say into the caller's list (map_on_threads carries it).
        def inner(i: int) -> int:
            warnings.warn(f"inner {k}.{i}", UserWarning, stacklevel=1)
            return 10 * k + i

        return threads.map_on_threads(inner, range(3))

    try:
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            got = threads.side_by_side(work, range(2), own_threads=True)
    finally:
        threads.shared_pool().shutdown()  # this test's own pool
    assert got == [[0, 1, 2], [10, 11, 12]]
    assert [str(w.message) for w in said] == [f"inner {k}.{i}" for k in range(2) for i in range(3)]


def test_a_pool_task_that_maps_on_threads_runs_its_work_itself(monkeypatch) -> None:
    """Two pool tasks each mapping on the pool would take both threads and wait for ever."""
    import threading

    from lfdkit.core import threads

    monkeypatch.setattr(threads, "available_cores", lambda: 2)
    monkeypatch.setattr(threads, "_POOL", None)

    def outer(k: int) -> tuple[str, list[str]]:
        names = threads.map_on_threads(lambda i: threading.current_thread().name, range(3))
        return threading.current_thread().name, names

    try:
        got = threads.map_on_threads(outer, range(2))
    finally:
        threads.shared_pool().shutdown()
    for name, inner in got:
        assert inner == [name] * 3  # in the task's own thread
