"""Batch runs: many independent tasks on one process, local processes or a Dask cluster.

One seam, the :class:`concurrent.futures.Executor` protocol, runs the work
units (:func:`make_executor`):

* serial (the default): :class:`SerialExecutor`, in this process;
* local processes (``workers=N``): a :class:`~concurrent.futures.ProcessPoolExecutor`
  whose workers are forks of a fresh, single-threaded ``forkserver`` process that
  has loaded lfdkit and warmed its planner once (:mod:`lfdkit.app.worker_preload`),
  so each worker starts warm; ``spawn`` where there is no ``forkserver`` (not
  ``fork``: MuJoCo and numba's threads in the calling process do not survive one).
  The fork server starts when the pool is made, or earlier with
  :func:`start_worker_server` (``lfdkit batch`` calls it once its options are
  checked, before loading the skill), so it loads beside the calling process;
  for a long batch it loads numba too, once for every worker
  (:mod:`lfdkit.app.worker_preload_compiled`), and a long batch's workers
  forked from a server an earlier short batch started without numba load it
  before their first task (:func:`load_compiled`), as a long serial batch does;
* a Dask distributed cluster (``scheduler="tcp://HOST:PORT"``, or
  ``dask_local=N`` to start a :class:`distributed.LocalCluster` of N
  single-threaded worker processes): ``Client.get_executor()``. A local
  cluster's workers start as local processes do: on Linux its nannies fork
  them from the same preloaded fork server (Dask's ``forkserver`` method),
  elsewhere each imports the preload itself (``LocalCluster(preload=...)``).

Work units are pure top-level functions of picklable inputs (their random
numbers derive from a base seed and the task's index only, and they run with
one BLAS thread), so the results are the same whatever the executor and
however many workers run them.

:func:`run_batch` submits tasks with a bounded number in flight (a window of
a few tasks per worker, never all of them at once) and writes each result as one
JSON line (flushed) in the tasks' order, whatever order they finish in: a
task's row is written as soon as every task before it is, so only the
results that finished ahead of a slower earlier task wait, in memory
(:data:`REORDER_PER_WORKER` a worker at most, then no more tasks are sent
until it comes back). The caller keeps nothing else: its memory does not
grow with the number of tasks, and a serial run, local processes and a Dask
cluster write the same file, byte for byte. A batch that ends early (a
broken executor, Ctrl-C) still writes the results it holds, out of order. The results file
starts with a header line naming the batch (its ``spec`` and a hash of it);
run the same batch again and the tasks already in the file are skipped, so an
interrupted batch resumes where it stopped. A task that raises is recorded as
``{"task": ID, "error": "Type: message"}`` and the batch goes on.

A worker's warnings reach the user as the serial run's do: each unit runs
under :func:`run_unit`, which records the warnings its tasks raise and sends
them back with the results, and :func:`run_batch` raises them again in the
calling process (where they were raised, so the same warning is shown once
and a command line's one-line format applies), not as Python's two lines on
the worker's stderr.

Short tasks travel in chunks (issue 30): on any executor but the serial one,
:func:`run_batch` times the tasks as they come back and sends the next ones
as chunks of about :data:`CHUNK_SECONDS` of work (one task at a time while
tasks take longer), never so many that a worker would be left without a
share at the end. A Dask cluster spends milliseconds on each unit it
schedules; a 30 ms plan paid that per task, a chunk of ten pays it once.
Tasks of seconds (a MuJoCo sweep) stay one per unit, so the last ones still
spread over the workers. The local Dask cluster's workers run without Dask's
statistical profiler, which samples every thread's stack every 10 ms: it
cost a MuJoCo sweep about a quarter more CPU time than the same task in a
plain process.

The results file is a regular file or nothing: a FIFO, device or symbolic
link is refused (with ``overwrite`` too; a link is never written through).
One batch writes it at a time: the file is locked (``flock``) while a batch
runs and a second one is refused, naming the first one's pid. Rows written
twice for one task (by an older, unlocked run) are kept once on resume, with
a warning.

:func:`learn_task` is the generic work unit of ``lfdkit batch learn`` (one
skill per folder of demonstrations); the sweeping task's scenario evaluation
is :func:`lfdkit.tasks.sweeping.batch.evaluate_scenario`, any skill on any
arm's is :func:`lfdkit.app.execute_batch.evaluate_task`; what every
``lfdkit batch evaluate`` shares (the arguments' checks, the results file's
spec, a row's first fields, the skill parsed once per worker) is here, so the
tasks' batches differ only in what their tasks do.

This module imports only the standard library at import time; NumPy, the
skill and Dask are imported where they are used.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import stat
import sys
import time
import warnings
from collections.abc import Callable, Hashable, Iterable, Iterator, Mapping
from concurrent.futures import (
    FIRST_COMPLETED,
    Executor,
    Future,
    ProcessPoolExecutor,
    wait,
)
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from lfdkit.core.progress import ProgressLike, as_progress

__all__ = [
    "COMPILED_TASKS_PER_WORKER",
    "FORMAT",
    "WORKER_PRELOAD",
    "WORKER_PRELOAD_COMPILED",
    "WORKER_PRELOAD_EXECUTION",
    "BatchSummary",
    "DaskExecutor",
    "ExecutorBrokenError",
    "ProcessExecutor",
    "ResultsInUseError",
    "SerialExecutor",
    "check_evaluate_arguments",
    "check_random_count",
    "describe_executor",
    "error_line",
    "evaluate_row",
    "evaluate_spec",
    "learn_batch",
    "learn_outputs",
    "learn_task",
    "load_compiled",
    "load_modules",
    "make_executor",
    "read_results",
    "results_header",
    "run_batch",
    "run_chunk",
    "run_unit",
    "skill_ends",
    "skill_from_text",
    "spec_hash",
    "start_worker_server",
    "worker_cached",
    "worker_modules",
    "worker_preload",
]

#: The first key of a results file's header line, and its format version.
FORMAT = "lfdkit-batch"
FORMAT_VERSION = 1
#: Tasks (or chunks of tasks) in flight per worker: enough to keep every worker busy
#: while the client writes results, few enough that the client holds almost nothing.
WINDOW_PER_WORKER = 4
#: Seconds of work a chunk of short tasks aims at: a Dask cluster's few milliseconds
#: per unit it schedules are then under 5 % of the work (:func:`run_batch`).
CHUNK_SECONDS = 0.25
#: Most tasks in one chunk.
MAX_CHUNK = 64
#: Finished tasks per worker :func:`run_batch` holds back at most while an earlier task
#: still runs (it writes rows in the tasks' order); beyond that it sends no more.
REORDER_PER_WORKER = 256
#: Dask settings of a local cluster's workers: no statistical profiler (it samples every
#: thread's stack every 10 ms and cost a MuJoCo sweep about 25 % more CPU time).
DASK_WORKER_CONFIG = {"distributed.worker.profile.enabled": False}
#: Environment that keeps BLAS and OpenMP to one thread in a worker process.
ONE_THREAD_ENV = {
    name: "1"
    for name in (
        "OMP_NUM_THREADS",
        "OPENBLAS_NUM_THREADS",
        "MKL_NUM_THREADS",
        "NUMBA_NUM_THREADS",
        "VECLIB_MAXIMUM_THREADS",
    )
}


# ------------------------------------------------------------------ executors
class SerialExecutor(Executor):
    """Runs each task in this process as it is submitted: the default, and the reference.

    :meth:`submit` returns a finished :class:`~concurrent.futures.Future`
    holding the result or the exception.
    """

    workers = 1

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future:
        future: Future = Future()
        try:
            result = fn(*args, **kwargs)
        except BaseException as exc:
            if not isinstance(exc, Exception):  # Ctrl-C, SystemExit: end the batch
                raise
            future.set_exception(exc)
        else:
            future.set_result(result)
        return future

    def __repr__(self) -> str:
        return "SerialExecutor()"


#: The module a worker's fork server imports first (:class:`ProcessExecutor`).
WORKER_PRELOAD = "lfdkit.app.worker_preload"
#: The same with numba and the planner's compiled kernels, for a long batch
#: (:func:`start_worker_server`).
WORKER_PRELOAD_COMPILED = "lfdkit.app.worker_preload_compiled"
#: What the fork server loads too where the tasks carry plans onto a robot (``executes``):
#: the execution pipeline and SciPy, once for every worker.
WORKER_PRELOAD_EXECUTION = "lfdkit.app.worker_preload_execution"
#: Tasks a worker must have for its fork server to load numba for it: numba's
#: start-up, about 1.1 s of CPU, against about 0.07 s a plan saved over the NumPy
#: kernels; a worker without it would load numba itself after about 7 plans.
COMPILED_TASKS_PER_WORKER = 8


class ProcessExecutor(ProcessPoolExecutor):
    """Local worker processes that start warm, one BLAS thread each.

    On Linux the workers are forks of a ``forkserver`` process that imported
    :data:`WORKER_PRELOAD` once (NumPy, the skill, the planner warmed up on
    its NumPy kernels), so a worker's first plan takes about 0.2 s of CPU
    instead of about 1.5 s, and 16 workers do not load the same things 16
    times; each loads numba itself, in parallel, once it has planned for a
    second (:mod:`lfdkit.core.kernels`), unless the fork server was started
    for a long batch (:func:`start_worker_server`: numba loaded once, in the
    fork server). The fork server is Python's, one per calling process,
    started by the first pool that needs it (when the pool is made, so it
    loads while the caller goes on) or by :func:`start_worker_server`; a
    fork server already running without the preload still works (its
    workers load what they need themselves). Elsewhere the workers are
    spawned.

    Parameters
    ----------
    workers : int
        Number of worker processes.
    tasks : int or None
        Tasks the pool will run, for what its workers load before their first
        (:func:`worker_preload`; None: not known, taken as many). 0 (not
        told): the NumPy kernels first, numba by the kernels' rule. A long
        batch's worker whose fork server was started without numba (by an
        earlier, shorter batch of this process: a process has one) loads
        numba itself before its first task, in parallel with the others.
    executes : bool
        Whether the tasks carry plans onto a robot: the fork server also loads
        the execution pipeline (:data:`WORKER_PRELOAD_EXECUTION`).
    """

    def __init__(self, workers: int, *, tasks: int | None = 0, executes: bool = False) -> None:
        compiled = worker_preload(tasks, workers, executes) == WORKER_PRELOAD_COMPILED
        super().__init__(
            max_workers=workers,
            mp_context=_worker_context(),
            initializer=_start_worker,
            initargs=(compiled,),
        )
        self.workers = workers
        start_worker_server(tasks, workers, executes)  # unless started already: loads meanwhile

    def __repr__(self) -> str:
        return f"ProcessExecutor(workers={self.workers})"


class DaskExecutor(Executor):
    """A Dask distributed client as an :class:`~concurrent.futures.Executor`.

    Wraps ``client.get_executor(pure=False)``: :meth:`submit` returns
    :class:`concurrent.futures.Future` objects.

    Parameters
    ----------
    client : distributed.Client
        Connected to a scheduler with at least one worker.

    Attributes
    ----------
    client : distributed.Client
    workers : int
        Threads of the cluster's workers when it was wrapped (its capacity).
    """

    def __init__(self, client: Any) -> None:
        self.client = client
        self._executor = client.get_executor(pure=False)
        self.workers = max(1, sum(client.nthreads().values()))

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future:
        return self._executor.submit(fn, *args, **kwargs)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        self._executor.shutdown(wait=wait)

    def __repr__(self) -> str:
        return f"DaskExecutor({self.client.scheduler.address}, workers={self.workers})"


def _local_cluster_start(
    tasks: int | None, workers: int, executes: bool = False
) -> tuple[dict[str, Any], list[str]]:
    """The Dask settings and worker preloads of a local cluster of ``workers`` for ``tasks``.

    On Linux the nannies fork their workers from the fork server local
    processes use (:func:`start_worker_server`, started now unless it runs),
    so each Dask worker starts with lfdkit, the warm planner and, for a long
    batch, numba loaded once for all of them (2 workers, 32 plan tasks, a
    loaded 2-core machine: 3.2-3.4 s of CPU a worker and 1.5-2.0 s in the fork
    server, against 5.2-6.1 s a worker spawned). Elsewhere each spawned worker
    imports the same preload itself at its start, before its first task.
    """
    if start_worker_server(tasks, workers, executes):
        return {**DASK_WORKER_CONFIG, "distributed.worker.multiprocessing-method": "forkserver"}, []
    return dict(DASK_WORKER_CONFIG), worker_modules(tasks, workers, executes)


def _worker_context() -> Any:
    """``forkserver`` preloading :data:`WORKER_PRELOAD` on Linux, else ``spawn``."""
    import multiprocessing

    if not sys.platform.startswith("linux"):  # macOS frameworks and fork do not mix
        return multiprocessing.get_context("spawn")
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload([WORKER_PRELOAD])  # read when the fork server starts
    return context


def start_worker_server(tasks: int | None = None, workers: int = 1, executes: bool = False) -> bool:
    """Start local workers' fork server now; whether there is one (Linux) to start.

    The fork server loads its preload (:data:`WORKER_PRELOAD`, about 0.6 s of
    CPU; with numba, :data:`WORKER_PRELOAD_COMPILED`, about 1.7 s) on its
    own core while this process goes on with its own loading (a command's
    NumPy, its skill), instead of after it: the first
    :meth:`ProcessExecutor.submit` then finds it ready or nearly so. Starting
    it does not wait for it; a second call, or a :class:`ProcessExecutor`,
    reuses the one running (one per process, whatever it preloaded).

    Parameters
    ----------
    tasks : int, optional
        Tasks the batch will run (None: not known, taken as many).
    workers : int
        Workers that will share them. With at least
        :data:`COMPILED_TASKS_PER_WORKER` tasks a worker (or an unknown
        number), the fork server loads numba and the planner's compiled
        kernels once, for every worker; with fewer, each worker starts on
        the NumPy kernels (:mod:`lfdkit.core.kernels`), which serve a few
        plans faster than numba's start-up.
    executes : bool
        Whether the tasks carry plans onto a robot (:func:`worker_modules`).
    """
    context = _worker_context()
    if context.get_start_method() != "forkserver":
        return False
    from multiprocessing import forkserver

    context.set_forkserver_preload(worker_modules(tasks, workers, executes))
    forkserver.ensure_running()
    return True


def worker_preload(tasks: int | None, workers: int, executes: bool = False) -> str:
    """The module the workers' fork server preloads for ``tasks`` on ``workers``.

    :data:`WORKER_PRELOAD_COMPILED` (numba loaded once, for every worker)
    when each worker gets at least :data:`COMPILED_TASKS_PER_WORKER` tasks,
    their number is not known (``None``: a scene file, a ``learn`` batch,
    whose IOC needs numba anyway) or the tasks carry plans onto a robot
    (``executes``: the timing law's NumPy form agrees with numba's to
    round-off only, about 1e-12 s in a motion's duration, so a row would
    depend on the kernels a worker ran and not equal the serial run's; and
    such a task takes 0.1-3 s, numba's start-up is soon earned);
    :data:`WORKER_PRELOAD` otherwise, or with ``LFDKIT_KERNELS=numpy``.
    """
    if os.environ.get("LFDKIT_KERNELS", "").strip().lower() == "numpy":
        return WORKER_PRELOAD
    if executes or tasks is None or tasks >= COMPILED_TASKS_PER_WORKER * max(1, workers):
        return WORKER_PRELOAD_COMPILED
    return WORKER_PRELOAD


def worker_modules(tasks: int | None, workers: int, executes: bool = False) -> list[str]:
    """The modules every worker of a batch loads before its first task, in this order.

    :func:`worker_preload`'s module, then, where the tasks carry plans onto a
    robot (``executes``: checks ``robot`` and ``mujoco``),
    :data:`WORKER_PRELOAD_EXECUTION` (SciPy's splines and rotations and the
    execution pipeline: about 0.3 s of CPU a worker's first such task paid,
    a loaded 2-core machine). The fork server of local processes imports
    them (:func:`start_worker_server`), a Dask cluster's workers too
    (:func:`load_modules`), and a long serial batch (:func:`make_executor`),
    so every executor's tasks start from the same warm process.
    """
    modules = [worker_preload(tasks, workers, executes)]
    if executes:
        modules.append(WORKER_PRELOAD_EXECUTION)
    return modules


def load_modules(modules: Iterable[str]) -> None:
    """Import ``modules`` (:func:`worker_modules`) in this process, each best effort.

    What a Dask worker runs before a batch's first task (``client.run``), and a
    long serial batch before its first; a module that fails to import leaves
    the tasks to load what they need themselves (and to report what is missing).
    """
    import importlib

    for name in modules:
        with contextlib.suppress(Exception):
            importlib.import_module(name)


def _start_worker(compiled: bool = False) -> None:
    """Initializer of a worker process: one BLAS/OpenMP thread (set before NumPy loads).

    With ``compiled`` (a long batch), numba too, unless the fork server had it
    already (:func:`load_compiled`).
    """
    os.environ.update(ONE_THREAD_ENV)
    if compiled:
        load_compiled()


def load_compiled() -> bool:
    """Load numba now, so that the planner's kernels are numba's from the first call.

    For a process about to run many tasks (:func:`worker_preload`'s rule): the
    kernels' own rule (:mod:`lfdkit.core.kernels`) would first run the NumPy
    forms for a second of CPU, about 5 of a random sweeping scene's plans, and
    then load numba anyway. A serial batch of 64 ``plan`` tasks: 5.0 → 3.9 s
    of CPU (a loaded 2-core machine). Nothing is done with
    ``LFDKIT_KERNELS=numpy``; a numba that fails to import leaves the NumPy
    forms. Returns whether numba is loaded.
    """
    if os.environ.get("LFDKIT_KERNELS", "").strip().lower() == "numpy":
        return False
    with contextlib.suppress(Exception):
        import numba  # noqa: F401  (loaded: the kernels' rule picks numba's from the first call)
    return "numba" in sys.modules


def _check_count(value: Any, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ValueError(f"{name}: expected a whole number of workers >= 1, got {value!r}")
    return value


def describe_executor(
    workers: int | None = None, scheduler: str | None = None, dask_local: int | None = None
) -> str:
    """A few words for the executor :func:`make_executor` makes from the same arguments."""
    if scheduler is not None:
        return f"the Dask cluster at {scheduler}"
    if dask_local is not None:
        return f"a local Dask cluster of {dask_local} worker process{'es' * (dask_local > 1)}"
    if workers is not None:
        return f"{workers} local worker process{'es' * (workers > 1)}"
    return "this process"


@contextlib.contextmanager
def make_executor(
    workers: int | None = None,
    scheduler: str | None = None,
    dask_local: int | None = None,
    *,
    connect_timeout: float = 30.0,
    tasks: int | None = None,
    executes: bool = False,
) -> Iterator[Executor]:
    """The executor that runs a batch's tasks, as a context manager.

    Give at most one of the three; none gives :class:`SerialExecutor`.

    Parameters
    ----------
    workers : int, optional
        Local worker processes (:class:`ProcessExecutor`).
    scheduler : str, optional
        Address of a running Dask scheduler, e.g. ``"tcp://10.0.0.5:8786"``
        (started with ``dask scheduler``; workers with ``dask worker ADDRESS
        --nworkers N --nthreads 1``, in the same Python environment).
    dask_local : int, optional
        Start a :class:`distributed.LocalCluster` of this many worker
        processes, one thread each, for the batch.
    connect_timeout : float
        Seconds to wait for the scheduler and its first worker.
    tasks : int, optional
        Tasks the batch will run (None: not known): what a local Dask
        cluster's workers preload (:func:`worker_preload`), as local
        processes' fork server and workers do (:class:`ProcessExecutor`; not
        known: the NumPy kernels first). A serial batch of at least
        :data:`COMPILED_TASKS_PER_WORKER` tasks loads numba before its first
        (:func:`load_compiled`).
    executes : bool
        Whether the tasks carry plans onto a robot (:func:`worker_modules`).

    Yields
    ------
    concurrent.futures.Executor
        With a ``workers`` attribute: how many tasks it runs at once. Before
        it is yielded, the processes that run the tasks are warm, the same
        for every executor (:func:`worker_modules`): a long serial batch has
        loaded them in this process, local processes' fork server has (and
        one worker is forked from it), a Dask cluster's workers have
        (``client.run``); a short serial batch loads what its tasks need as
        they run. A batch's seconds (:class:`BatchSummary`) count from there,
        so its throughput compares executors on their tasks, not their start.
        On leaving, it is shut down (and a local cluster closed); after an
        exception, without waiting for the tasks still running.

    Raises
    ------
    ValueError
        For more than one of the three, a count below 1, or a scheduler that
        cannot be reached (or has no worker) within ``connect_timeout``.
    ImportError
        For a Dask cluster without the ``distributed`` package, with the
        command that installs it.
    """
    chosen = {"workers": workers, "scheduler": scheduler, "dask_local": dask_local}
    given = [name for name, value in chosen.items() if value is not None]
    if len(given) > 1:
        raise ValueError(f"{given[1]}: give one of workers, scheduler and dask_local, not both")
    if workers is not None:
        # Not told: the NumPy kernels first, as ProcessExecutor's own default.
        count = 0 if tasks is None else tasks
        n = _check_count(workers, "workers")
        executor: Executor = ProcessExecutor(n, tasks=count, executes=executes)
        with _shut_down(executor) as executor:
            try:  # the fork server loaded, a worker forked: the batch starts warm
                executor.submit(os.getpid).result()
            except BrokenProcessPool as exc:
                raise ExecutorBrokenError(_broken(exc)) from None
            yield executor
        return
    if scheduler is None and dask_local is None:
        long = tasks is not None or executes  # (not known: a short batch's kernels' rule)
        if long and worker_preload(tasks, 1, executes) == WORKER_PRELOAD_COMPILED:
            load_compiled()  # a long serial batch: numba from its first task
            load_modules(worker_modules(tasks, 1, executes))  # as the workers' fork server
        executor = SerialExecutor()
    else:
        with _dask_client(scheduler, dask_local, connect_timeout, tasks, executes) as client:
            with _shut_down(DaskExecutor(client)) as executor:
                yield executor
        return
    with _shut_down(executor) as executor:
        yield executor


@contextlib.contextmanager
def _shut_down(executor: Executor) -> Iterator[Executor]:
    """Shut ``executor`` down on leaving: waiting for it, unless an exception ends the batch."""
    try:
        yield executor
    except BaseException:
        executor.shutdown(wait=False, cancel_futures=True)
        raise
    executor.shutdown(wait=True)


@contextlib.contextmanager
def _dask_client(
    scheduler: str | None,
    dask_local: int | None,
    timeout: float,
    tasks: int | None = None,
    executes: bool = False,
) -> Iterator[Any]:
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise ImportError(
            "a Dask cluster needs the optional package distributed: "
            'pip install "lfdkit[dask]" (or pip install "dask[distributed]")'
        ) from None
    import logging

    if dask_local is not None:
        import dask

        n = _check_count(dask_local, "dask_local")
        config, preload = _local_cluster_start(tasks, n, executes)
        with (
            dask.config.set(config),  # the nannies hand it to their workers
            LocalCluster(
                n_workers=n,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
                silence_logs=logging.CRITICAL,  # workers outliving the scheduler log errors
                env=ONE_THREAD_ENV,
                preload=preload,
            ) as cluster,
            Client(cluster) as client,
        ):
            client.wait_for_workers(n, timeout=timeout)
            _warm_workers(client, tasks, executes)  # forked from the fork server: nothing left
            yield client
        return
    if not isinstance(scheduler, str) or not scheduler.strip():
        raise ValueError(f"scheduler: expected an address like tcp://HOST:8786, got {scheduler!r}")
    try:
        client = Client(scheduler, timeout=timeout)
    except (OSError, TimeoutError) as exc:
        raise ValueError(f"scheduler: cannot connect to {scheduler}: {exc}") from None
    with client:
        try:
            client.wait_for_workers(1, timeout=timeout)
        except TimeoutError:
            raise ValueError(
                f"scheduler: {scheduler} has no worker after {timeout:g} s; start some with "
                f"dask worker {scheduler} --nthreads 1"
            ) from None
        _warm_workers(client, tasks, executes)
        yield client


def _warm_workers(client: Any, tasks: int | None, executes: bool) -> None:
    """Load :func:`worker_modules` on every worker of ``client``'s cluster, in parallel.

    A ``dask worker`` started without lfdkit's preload would otherwise load
    them during its first tasks: numba only after a second of the NumPy
    kernels (about ten random sweeping plans at 10x numba's CPU time), and
    the first chunks' times, inflated by that start, would size the chunks
    too small. Workers that loaded them already (forked from the fork
    server, or started with ``--preload lfdkit.app.worker_preload_compiled``)
    return at once. Best effort: a worker without lfdkit fails its tasks,
    which say why.
    """
    n = max(1, sum(client.nthreads().values()))
    with contextlib.suppress(Exception):
        client.run(load_modules, worker_modules(tasks, n, executes))


# ------------------------------------------------------------------ results files
def spec_hash(spec: Mapping[str, Any]) -> str:
    """A short hash of a batch's description (canonical JSON): what its results file is of."""
    text = json.dumps(_jsonable(spec), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def results_header(path: str | os.PathLike[str]) -> dict[str, Any]:
    """The header line of a results file: ``{"lfdkit-batch": 1, "spec": ..., "hash": ...}``.

    Raises
    ------
    ValueError
        If the file does not start with a batch header.
    """
    with open(path, encoding="utf-8") as f:
        first = f.readline()
    try:
        header = json.loads(first)
    except json.JSONDecodeError:
        header = None
    if not isinstance(header, dict) or FORMAT not in header:
        raise ValueError(f"{os.fspath(path)}: not an lfdkit batch results file (no header line)")
    return header


def read_results(path: str | os.PathLike[str]) -> Iterator[dict[str, Any]]:
    """The records of a results file, one dict per finished task, in the tasks' order.

    A last line cut short (the batch was killed while writing it) is skipped.
    Each record has ``task`` and either the work unit's fields or ``error``.
    """
    results_header(path)
    with open(path, encoding="utf-8") as f:
        f.readline()
        for line in f:
            if not line.endswith("\n"):
                return
            yield json.loads(line)


def _jsonable(value: Any) -> Any:
    """``value`` with tuples as lists, NumPy scalars and arrays as numbers, NaN and inf as None."""
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, (str, int, bool)) or value is None:
        return value
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    tolist = getattr(value, "tolist", None)  # NumPy scalars and arrays
    if callable(tolist):
        return _jsonable(tolist())
    raise TypeError(f"cannot write a {type(value).__name__} to a results file")


class ResultsInUseError(RuntimeError):
    """Another batch is writing the same results file (it holds the file's lock)."""


def _lock_path(path: Path) -> Path:
    """The sidecar naming the pid of the batch that holds ``path``'s lock (for the message)."""
    return path.with_name(f".{path.name}.pid")


class _ResultsFile:
    """A results file open for appending: checked, locked, the tasks done known.

    Only a missing path or a regular file is opened (a FIFO would block the
    batch forever, a link would be written through): the path is refused as
    :func:`lfdkit.io.atomic.check_output_path` refuses it, whatever
    ``overwrite`` says, and opened with ``O_NOFOLLOW``. The open file is
    locked (``flock``, exclusive, not waiting) before anything is read or
    truncated, so a second batch on the same file is refused instead of
    interleaving its rows with the first one's.
    """

    def __init__(self, path: Path, spec: Mapping[str, Any], *, overwrite: bool) -> None:
        from lfdkit.io.atomic import check_output_path

        self.path = path
        self.hash = spec_hash(spec)
        self.done: set[Hashable] = set()
        self.failed_before = 0
        self.duplicates = 0
        existing = check_output_path(path, overwrite=True)  # special files and links refused
        self.file = self._open_locked(path)
        try:
            resume = existing is not None and not overwrite and os.fstat(self.file.fileno()).st_size
            if resume:
                self._read_existing()
                self.file.seek(0, os.SEEK_END)
            else:
                self.file.truncate(0)
                header = {FORMAT: FORMAT_VERSION, "hash": self.hash, "spec": _jsonable(spec)}
                self.file.write(json.dumps(header) + "\n")
                self.file.flush()
        except BaseException:
            self.close()
            raise
        self.resumed = bool(resume)

    def _open_locked(self, path: Path) -> Any:
        flags = os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
        fd = os.open(path, flags, 0o666)  # O_NONBLOCK: a FIFO put there meanwhile cannot hang us
        try:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                from lfdkit.io.atomic import NotRegularFileError, file_kind

                raise NotRegularFileError(
                    f"{path}: is {file_kind(os.fstat(fd).st_mode)}, not a regular file; "
                    "give another results file"
                )
            try:
                import fcntl
            except ImportError:  # pragma: no cover - Windows: no lock
                fcntl = None
            if fcntl is not None:
                try:
                    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                except BlockingIOError:
                    holder = _read_pid(_lock_path(path))
                    who = f" (pid {holder})" if holder else ""
                    raise ResultsInUseError(
                        f"{path}: results file is in use by another batch{who}; wait for it to "
                        "finish, or write to another file"
                    ) from None
            self._pid_file = _lock_path(path)
            with contextlib.suppress(OSError):
                self._pid_file.write_text(f"{os.getpid()}\n", encoding="utf-8")
            return os.fdopen(fd, "r+", encoding="utf-8", newline="")
        except BaseException:
            os.close(fd)
            raise

    def _read_existing(self) -> None:
        header = results_header(self.path)
        if header.get("hash") != self.hash:
            raise ValueError(
                f"{self.path}: holds the results of another batch (spec hash "
                f"{header.get('hash')}, this one {self.hash}); pass --force (overwrite=True) to "
                "start over, or write to another file"
            )
        keep: list[bytes] = []
        with open(self.path, "rb") as f:
            head = f.readline()
            size = len(head)
            for raw in f:
                if not raw.endswith(b"\n"):
                    break
                try:
                    record = json.loads(raw)
                    key = _key(record["task"])
                except (json.JSONDecodeError, KeyError, TypeError):
                    break
                size += len(raw)
                if key in self.done:  # written twice (e.g. by an older, unlocked run)
                    self.duplicates += 1
                    continue
                self.done.add(key)
                self.failed_before += "error" in record
                keep.append(raw)
        if self.duplicates:
            # Rewrite the file with one row per task, atomically (under our lock).
            from lfdkit.io.atomic import atomic_write

            def write(f: Any) -> None:
                f.write(head)
                f.writelines(keep)

            os.fsync(self.file.fileno())
            atomic_write(self.path, write, binary=True, overwrite=True)
            # The rename replaced the inode we hold locked: lock the new one.
            old = self.file
            self.file = self._open_locked(self.path)
            old.close()
            warnings.warn(
                f"{self.path}: {self.duplicates} task row{'s' * (self.duplicates > 1)} "
                "appeared twice; kept the first of each (the file now has one row per task)",
                stacklevel=4,
            )
        elif size < self.path.stat().st_size:  # a line cut short by a kill: drop it
            self.file.truncate(size)

    def write(self, record: Mapping[str, Any]) -> None:
        self.file.write(json.dumps(_jsonable(record), allow_nan=False) + "\n")
        self.file.flush()

    def close(self) -> None:
        with contextlib.suppress(OSError):
            self.file.flush()
            os.fsync(self.file.fileno())
        if _read_pid(getattr(self, "_pid_file", None)) == os.getpid():
            with contextlib.suppress(OSError):
                self._pid_file.unlink()
        self.file.close()  # releases the lock


def _read_pid(path: Path | None) -> int | None:
    if path is None:
        return None
    try:
        return int(path.read_text(encoding="utf-8").strip())
    except (OSError, ValueError):
        return None


def _key(task_id: Any) -> Hashable:
    """A task id as a set key (lists read back from JSON as tuples)."""
    return tuple(task_id) if isinstance(task_id, list) else task_id


# ------------------------------------------------------------------ running
class ExecutorBrokenError(RuntimeError):
    """The executor itself failed (a worker process died, the cluster went away)."""


@dataclass
class BatchSummary:
    """What a :func:`run_batch` call did.

    Attributes
    ----------
    path : Path
        The results file.
    total : int
        Tasks of the batch.
    skipped : int
        Tasks already in the file (resumed), not run again.
    done : int
        Tasks run now that succeeded.
    failed : int
        Tasks run now that raised (recorded with their error).
    failed_before : int
        Failed tasks found in the file when resuming.
    seconds : float
        Wall time of this call.
    errors : list of str
        The first few errors of this call, ``"TASK: Type: message"``.
    workers : int
        Tasks the executor ran at once (its ``workers``).
    busy_seconds : float
        Seconds spent inside the tasks' function, summed over the units
        (each unit timed where it ran).
    """

    path: Path
    total: int = 0
    skipped: int = 0
    done: int = 0
    failed: int = 0
    failed_before: int = 0
    seconds: float = 0.0
    errors: list[str] = field(default_factory=list)
    workers: int = 1
    busy_seconds: float = 0.0

    @property
    def throughput(self) -> float:
        """Tasks run per second in this call (nan before any)."""
        ran = self.done + self.failed
        return ran / self.seconds if ran and self.seconds > 0 else float("nan")

    @property
    def overhead_fraction(self) -> float:
        """The share of the workers' time this call spent outside the tasks (nan before any).

        ``1 - busy_seconds / (seconds * workers)``: scheduling, sending and
        collecting, starting workers that were not started, and workers idle
        at the end while the last tasks finish. Issue 30's bar for the
        scheduling part: under 5 % of a batch.
        """
        if not (self.done + self.failed) or self.seconds <= 0:
            return float("nan")
        return 1.0 - self.busy_seconds / (self.seconds * self.workers)


def run_batch(
    executor: Executor,
    fn: Callable[..., Mapping[str, Any]],
    tasks: Iterable[tuple[Any, tuple[Any, ...]]],
    results: str | os.PathLike[str],
    *,
    spec: Mapping[str, Any],
    total: int | None = None,
    overwrite: bool = False,
    window: int | None = None,
    chunk_seconds: float | None = None,
    progress: ProgressLike = None,
    label: str = "batch",
) -> BatchSummary:
    """Run ``fn(*args)`` for every ``(task_id, args)`` and stream the results to a file.

    Parameters
    ----------
    executor : concurrent.futures.Executor
        From :func:`make_executor` (any executor works; its ``workers``
        attribute, 1 if missing, sizes the window).
    fn : callable
        A picklable top-level function returning a JSON-ready mapping.
    tasks : iterable of (task_id, args)
        Read lazily, as tasks are submitted. ``task_id`` is a JSON value
        (int, str, or a list of them) unique in the batch.
    results : path
        JSON-lines results file: a header line, then one record per task
        ``{"task": task_id, **fn(*args)}`` or ``{"task": task_id, "error":
        "Type: message"}``, in the order of ``tasks`` whatever order they
        finish in (a batch that ended early also wrote the results it held
        back: a resumed file's rows may then be out of order).
    spec : mapping
        What the batch is (its inputs and settings), written in the header.
        An existing file with the same spec is resumed: its tasks are not
        run again; one of another spec is refused unless ``overwrite``.
    total : int, optional
        Number of tasks (for the progress bar and its ETA); default
        ``len(tasks)`` when it has one.
    overwrite : bool
        Start the file afresh.
    window : int, optional
        Most units (tasks or chunks) in flight at once (default
        :data:`WINDOW_PER_WORKER` per worker). The caller holds at most this
        many futures and their results.
    chunk_seconds : float, optional
        Seconds of work a chunk of short tasks aims at (default
        :data:`CHUNK_SECONDS`; 0: one task per unit). Tasks are sent one by
        one until the first come back; then as many per unit as take about
        this long by the mean time of the tasks so far, at most
        :data:`MAX_CHUNK` and, where ``total`` is known, at most a half of
        each worker's share of the tasks left. :class:`SerialExecutor` runs
        tasks one by one whatever this says. Chunks change neither the
        results nor the file.
    progress : Progress, callable, bool or None
        A stage with a bar (count, throughput, ETA) over the tasks to run,
        counting each task when it finishes (before its row may be written).
    label : str
        The progress stage's label.

    Returns
    -------
    BatchSummary

    Raises
    ------
    ValueError
        If ``results`` holds another batch's results (and not ``overwrite``),
        or ``window`` or ``chunk_seconds`` is out of range.
    ExecutorBrokenError
        If the executor breaks (a worker process killed); the tasks finished
        so far are in the file, and running the batch again resumes.
    """
    started = time.perf_counter()
    path = Path(results)
    if total is None and hasattr(tasks, "__len__"):
        total = len(tasks)  # type: ignore[arg-type]
    out = _ResultsFile(path, spec, overwrite=overwrite)
    capacity = int(getattr(executor, "workers", 1) or 1)
    summary = BatchSummary(
        path=path, total=total or 0, failed_before=out.failed_before, workers=capacity
    )
    window = WINDOW_PER_WORKER * capacity if window is None else int(window)
    if window < 1:
        raise ValueError(f"window: expected a number of tasks >= 1, got {window}")
    chunk_seconds = CHUNK_SECONDS if chunk_seconds is None else float(chunk_seconds)
    if not (math.isfinite(chunk_seconds) and chunk_seconds >= 0.0):
        raise ValueError(f"chunk_seconds: expected seconds >= 0, got {chunk_seconds!r}")
    serial = isinstance(executor, SerialExecutor)
    chunked = chunk_seconds > 0.0 and not serial
    # Finished tasks held back for a slower earlier one, at most: then no more are sent
    # until it comes back (memory stays bounded whatever one slow task does).
    reorder_limit = max(REORDER_PER_WORKER * capacity, window * MAX_CHUNK)
    # Where each worker warning was raised: its `__warningregistry__` here (once each).
    registries: dict[str, dict[Any, Any]] = {}
    sizer = _ChunkSizer(chunk_seconds, capacity, total)
    todo = None if total is None else max(0, total - len(out.done))
    progress = as_progress(progress)
    # Each unit in flight, the place of its first task among the tasks sent, and its ids.
    pending: dict[Future, tuple[int, list[Any]]] = {}
    counted = 0
    sent = 0  # tasks submitted so far: the next one's place in the file
    # Finished records waiting for an earlier task (by place), and the next place to write.
    waiting: dict[int, dict[str, Any]] = {}
    written = 0
    try:
        with progress.stage(label, total=todo, unit="task") as stage:
            queue = iter(tasks)

            def fill() -> None:
                nonlocal counted, sent
                while len(pending) < window and len(waiting) < reorder_limit:
                    size = sizer.size(counted) if chunked else 1
                    ids: list[Any] = []
                    chunk: list[tuple[Any, ...]] = []
                    while len(ids) < size:
                        item = next(queue, None)
                        if item is None:
                            break
                        task_id, args = item
                        counted += 1
                        if _key(_jsonable(task_id)) in out.done:
                            summary.skipped += 1
                            continue
                        ids.append(task_id)
                        chunk.append(tuple(args))
                    if not ids:
                        return
                    try:
                        if serial:
                            begun = time.perf_counter()
                            future = executor.submit(fn, *chunk[0])
                            summary.busy_seconds += time.perf_counter() - begun
                        else:
                            future = executor.submit(run_unit, fn, chunk)
                    except (BrokenProcessPool, RuntimeError) as exc:
                        raise ExecutorBrokenError(_broken(exc)) from None
                    pending[future] = (sent, ids)
                    sent += len(ids)

            def finish(place: int, record: dict[str, Any]) -> None:
                """Count a finished task; write it and the waiting ones it was holding back."""
                nonlocal written
                waiting[place] = record
                while written in waiting:
                    out.write(waiting.pop(written))
                    written += 1
                if "error" in record:
                    summary.failed += 1
                    if len(summary.errors) < 5:
                        summary.errors.append(f"{record['task']}: {record['error']}")
                else:
                    summary.done += 1
                ran = summary.done + summary.failed
                rate = ran / (time.perf_counter() - started)
                shown = f"{rate:.1f}" if rate >= 1 else f"{rate:.3f}"
                detail = f"{shown} tasks/s" + (
                    f", {summary.failed} failed" if summary.failed else ""
                )
                stage.advance(detail=detail)

            fill()
            while pending:
                finished, _ = wait(pending, return_when=FIRST_COMPLETED)
                # In the order they were sent: a serial run's order where several finished.
                for future in sorted(finished, key=lambda f: pending[f][0]):
                    first, ids = pending.pop(future)
                    if serial:
                        finish(first, _record(ids[0], future))
                        continue
                    _check_unit(future)
                    if future.exception() is not None:  # not an Exception: run_chunk let it by
                        for place, task_id in enumerate(ids, first):
                            finish(place, _record(task_id, future))
                        continue
                    outcomes, seconds, caught = future.result()
                    summary.busy_seconds += seconds
                    _warn_again(caught, registries)
                    if chunked:
                        sizer.timed(len(ids), seconds)
                    for place, (task_id, outcome) in enumerate(
                        zip(ids, outcomes, strict=True), first
                    ):
                        finish(place, {"task": task_id, **outcome})
                fill()
    finally:
        for future in pending:
            future.cancel()
        # Ended early (a broken executor, Ctrl-C): keep the work done, out of order if need be.
        for place in sorted(waiting):
            out.write(waiting.pop(place))
        out.close()
        summary.seconds = time.perf_counter() - started
        if total is None:
            summary.total = counted
    return summary


def _check_unit(future: Future) -> None:
    """Raises :class:`ExecutorBrokenError` for a unit the executor cancelled or lost."""
    if future.cancelled():  # by the executor (a Dask cluster shutting down), not by us
        raise ExecutorBrokenError("the executor cancelled a task; run the batch again to resume")
    exc = future.exception()
    if isinstance(exc, BrokenProcessPool):
        raise ExecutorBrokenError(_broken(exc))


def _record(task_id: Any, future: Future) -> dict[str, Any]:
    """The results-file record of a finished task; a broken executor ends the batch."""
    _check_unit(future)
    exc = future.exception()
    if exc is None:
        return {"task": task_id, **future.result()}
    return {"task": task_id, "error": error_line(exc)}


def error_line(exc: BaseException) -> str:
    """``"Type: first line of the message"``: a failed task's record, a task's ``failure``."""
    text = str(exc).splitlines()[0] if str(exc) else ""
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def run_chunk(
    fn: Callable[..., Mapping[str, Any]], chunk: list[tuple[Any, ...]]
) -> tuple[list[Mapping[str, Any]], float]:
    """Run ``fn(*args)`` for each ``args`` of ``chunk``: :func:`run_batch`'s unit of short tasks.

    Returns each task's result, or ``{"error": "Type: message"}`` for a task
    that raised (the others still run), and the seconds the chunk took.
    """
    started = time.perf_counter()
    outcomes: list[Mapping[str, Any]] = []
    for args in chunk:
        try:
            outcomes.append(fn(*args))
        except Exception as exc:  # recorded as the task's error, as a lone task's would be
            outcomes.append({"error": error_line(exc)})
    return outcomes, time.perf_counter() - started


def run_unit(
    fn: Callable[..., Mapping[str, Any]], chunk: list[tuple[Any, ...]]
) -> tuple[list[Mapping[str, Any]], float, list[tuple[str, type[Warning], str, int]]]:
    """:func:`run_chunk` in a worker, with the warnings its tasks raised.

    Returns :func:`run_chunk`'s outcomes and seconds, and each warning as
    ``(message, category, filename, lineno)``: all of them (the calling
    process's filters decide what is shown, :func:`_warn_again`), so none is
    printed in Python's two-line form on the worker's stderr.
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        outcomes, seconds = run_chunk(fn, chunk)
    raised = [(str(w.message), w.category, w.filename, w.lineno) for w in caught]
    return outcomes, seconds, raised


def _warn_again(
    caught: Iterable[tuple[str, type[Warning], str, int]], registries: dict[str, dict[Any, Any]]
) -> None:
    """Raise a worker's warnings (:func:`run_unit`) in this process, where they were raised.

    ``registries`` (one ``__warningregistry__`` per file, kept over a batch)
    shows a warning raised at one place once under the ``"default"`` filter,
    as in a serial run. The warning is rebuilt without its class's
    ``__init__`` (a class may take other arguments), its message as raised.
    """
    for text, category, filename, lineno in caught:
        message = category.__new__(category)
        Warning.__init__(message, text)
        registry = registries.setdefault(filename, {})
        warnings.warn_explicit(message, category, filename, lineno, registry=registry)


class _ChunkSizer:
    """How many tasks the next unit of :func:`run_batch` holds, from the tasks' times so far."""

    def __init__(self, seconds: float, capacity: int, total: int | None) -> None:
        self.seconds = seconds
        self.capacity = capacity
        self.total = total
        self.tasks = 0
        self.spent = 0.0

    def timed(self, tasks: int, seconds: float) -> None:
        self.tasks += tasks
        self.spent += seconds

    def size(self, submitted: int) -> int:
        if not self.tasks:
            return 1  # nothing timed yet: one at a time
        mean = self.spent / self.tasks
        size = MAX_CHUNK if mean <= 0.0 else int(self.seconds / mean)
        if self.total is not None:  # every worker keeps a share of what is left
            size = min(size, (self.total - submitted) // (2 * self.capacity))
        return max(1, min(size, MAX_CHUNK))


def _broken(exc: BaseException) -> str:
    return (
        f"the executor failed ({type(exc).__name__}: {exc}); the results so far are kept: "
        "run the batch again to resume"
    )


# ------------------------------------------------------------------ evaluate batches
#: What this worker built from the text a batch sends it, by kind and the text's SHA-256.
_BUILT: dict[tuple[str, str], Any] = {}


def worker_cached(kind: str, text: str, build: Callable[[], Any]) -> Any:
    """``build()``, once per worker process for this ``text`` of this ``kind``.

    A batch sends every task the same skill (or arm) as text; the worker
    builds it on the first task and reuses it. One object is kept per kind
    (a new text replaces the old), so a worker serving batch after batch
    holds one skill, not all of them.
    """
    key = (kind, hashlib.sha256(text.encode()).hexdigest())
    if key not in _BUILT:
        for old in [k for k in _BUILT if k[0] == kind]:
            del _BUILT[old]
        _BUILT[key] = build()
    return _BUILT[key]


def skill_from_text(text: str) -> Any:
    """A skill file's JSON text as a :class:`lfdkit.skill.Skill`, parsed once per worker."""
    from lfdkit.skill import Skill

    return worker_cached("skill", text, lambda: Skill.from_dict(json.loads(text), source="skill"))


def check_evaluate_arguments(
    random: int | None,
    scenes: str | os.PathLike[str] | None,
    check: str,
    checks: tuple[str, ...],
    speed_fraction: float,
) -> float:
    """The arguments every ``lfdkit batch evaluate`` takes, checked; the speed fraction as a float.

    Raises
    ------
    ValueError
        Neither or both of ``random`` and ``scenes``, a ``check`` not in
        ``checks``, or a speed fraction outside ``(0, 1]``.
    """
    if (random is None) == (scenes is None):
        raise ValueError("random, scenes: give one of them")
    if check not in checks:
        raise ValueError(f"check: expected one of {', '.join(checks)}, got {check!r}")
    fraction = float(speed_fraction)
    if not 0.0 < fraction <= 1.0:
        raise ValueError(f"speed_fraction: must be in (0, 1], got {speed_fraction!r}")
    return fraction


def check_random_count(random: Any, what: str) -> int:
    """``random``, a number of random ``what`` (scenes, goals) >= 1, or a one-line error."""
    if isinstance(random, bool) or not isinstance(random, int) or random < 1:
        raise ValueError(f"random: expected a number of {what} >= 1, got {random!r}")
    return random


def evaluate_spec(task: str, skill_text: str, **settings: Any) -> dict[str, Any]:
    """The spec of an ``lfdkit batch evaluate`` results file: what makes two batches one.

    ``{"kind": "evaluate", "task": task, "skill": SHA-256 of the skill
    file's text, **settings, "lfdkit": version}``, in that order (the
    header line shows it so); the caller adds how the scenes are drawn
    (``random``) or which file they are (``scenes``).
    """
    from lfdkit import __version__

    return {
        "kind": "evaluate",
        "task": task,
        "skill": hashlib.sha256(skill_text.encode()).hexdigest(),
        **settings,
        "lfdkit": __version__,
    }


def skill_ends(skill: Any, where: Mapping[str, Any]) -> tuple[Any, Any]:
    """A task's ``start`` and ``goal`` (m): ``where``'s, or the skill's path's ends where None."""
    import numpy as np

    start = skill.path_[0] if where.get("start") is None else np.asarray(where["start"], float)
    goal = skill.path_[-1] if where.get("goal") is None else np.asarray(where["goal"], float)
    return start, goal


def evaluate_row(
    identity: Mapping[str, Any], start: Any, goal: Any, obstacles: Any, check: str
) -> dict[str, Any]:
    """The first fields of an evaluated task's row, not ``ok`` yet: the task then fills it in."""
    return {
        "scenario": identity,
        "start": [float(v) for v in start],
        "goal": [float(v) for v in goal],
        "obstacles": obstacles,
        "check": check,
        "ok": False,
        "failure": None,
    }


# ------------------------------------------------------------------ work units
#: Demonstrations and scene files a folder of ``lfdkit batch learn`` may hold, by preference.
DEMOS_NAMES = ("demos.csv", "demos.npz", "demos.json")
SCENES_NAMES = ("scenes.csv", "scenes.json")


def learn_task(
    folder: str, output: str, params: Mapping[str, Any], overwrite: bool = False
) -> dict[str, Any]:
    """Learn one skill from a folder of demonstrations and write it: a work unit.

    Parameters
    ----------
    folder : str
        Holds ``demos.csv`` (or ``.npz``/``.json``) and, optionally,
        ``scenes.csv`` (or ``.json``) naming the obstacles of the
        demonstrations around obstacles (:func:`lfdkit.skill.learn`).
    output : str
        The skill file to write (atomically).
    params : mapping
        :class:`lfdkit.skill.Skill` parameters; ``random_state`` as given
        (the same seed for every folder, so a folder learns the same skill
        as ``lfdkit learn`` with that seed). Without ``units``, as
        ``lfdkit learn`` without ``--units``: metres, and demonstrations
        implausible in metres are refused (:func:`lfdkit.core.units.implausible_units`).
    overwrite : bool
        Replace an existing skill file.

    Returns
    -------
    dict
        ``folder``, ``skill`` (the file written), ``demos`` and ``scenes``
        (the file names read), ``clean_demos``, ``obstacle_demos``,
        ``classes`` (the learned obstacle classes) and ``units``.

    Raises
    ------
    FileNotFoundError
        If the folder has no demonstrations file.
    ValueError
        For malformed files, demonstrations implausible in metres when no
        ``units`` is given, or an obstacle reward fit that did not converge
        (nothing is written then).
    FileExistsError
        If ``output`` exists and not ``overwrite``.
    """
    from lfdkit.core.threads import one_blas_thread
    from lfdkit.core.units import UnitsWarning
    from lfdkit.skill import learn

    where = Path(folder)
    demos = next((where / n for n in DEMOS_NAMES if (where / n).is_file()), None)
    if demos is None:
        raise FileNotFoundError(f"{folder}: no {', '.join(DEMOS_NAMES)}")
    scenes = next((where / n for n in SCENES_NAMES if (where / n).is_file()), None)
    with one_blas_thread(), warnings.catch_warnings():
        if "units" not in params:  # no unit given: implausible metres are refused (issue 31)
            warnings.simplefilter("error", UnitsWarning)
        try:
            skill = learn(demos, scenes, **params)
        except UnitsWarning as exc:
            likely = exc.likely
            raise ValueError(
                f"{demos}: {exc.detail.removeprefix('demos: ')}; no --units was given, so they "
                f"were read as m: pass --units {likely} if that is their unit"
            ) from None
    fit = skill.ioc_info_ or {}
    if not fit.get("converged", True):
        raise ValueError(
            f"the obstacle reward fit did not converge ({fit.get('convergence_message')}); "
            "wrote nothing"
        )
    written = skill.save(output, overwrite=overwrite)
    return {
        "folder": folder,
        "skill": os.fspath(written),
        "demos": os.fspath(demos.name),
        "scenes": None if scenes is None else scenes.name,
        "clean_demos": int(skill.mimic_info_["n_demos"]),
        "obstacle_demos": int(skill.ioc_info_["n_demos"]) if skill.ioc_info_ else 0,
        "classes": list(skill.reward_.classes) if skill.reward_ is not None else [],
        "units": skill.units,
    }


def learn_outputs(
    folders: Iterable[str | os.PathLike[str]], output_dir: str | os.PathLike[str] | None = None
) -> dict[str, Path]:
    """The skill file :func:`learn_batch` writes for each folder, by folder.

    ``FOLDER/skill.json``, or ``OUTPUT_DIR/NAME.json`` (``NAME`` the folder's
    name, which must then be unique).

    Raises
    ------
    ValueError
        If a folder is given twice, or two share a name with ``output_dir``.
    """
    out: dict[str, Path] = {}
    names: dict[str, str] = {}
    for folder in folders:
        key = os.fspath(folder)
        if key in out:
            raise ValueError(f"folders: {key} is given twice")
        if output_dir is None:
            out[key] = Path(folder) / "skill.json"
            continue
        name = Path(folder).resolve().name
        if name in names:
            raise ValueError(
                f"folders: {names[name]} and {key} are both called {name!r}; their skills "
                f"would both be {Path(output_dir) / (name + '.json')}"
            )
        names[name] = key
        out[key] = Path(output_dir) / f"{name}.json"
    return out


def learn_batch(
    folders: Iterable[str | os.PathLike[str]],
    results: str | os.PathLike[str],
    *,
    params: Mapping[str, Any] | None = None,
    output_dir: str | os.PathLike[str] | None = None,
    executor: Executor | None = None,
    overwrite: bool = False,
    progress: ProgressLike = None,
) -> BatchSummary:
    """Learn one skill per folder of demonstrations (:func:`learn_task`), in batch.

    Parameters
    ----------
    folders : iterable of path
        Each with ``demos.csv`` (or ``.npz``/``.json``) and optionally ``scenes.csv``.
    results : path
        The JSON-lines results file, one record per folder (task id: the
        folder as given); resumed when it holds this batch.
    params : mapping, optional
        :class:`lfdkit.skill.Skill` parameters for every folder.
    output_dir : path, optional
        Write ``OUTPUT_DIR/NAME.json`` instead of ``FOLDER/skill.json``
        (:func:`learn_outputs`).
    executor : Executor, optional
        Default :class:`SerialExecutor`.
    overwrite : bool
        Replace the results file and existing skill files. Without it, a
        skill file of a task still to run is replaced only when the batch
        resumes (the file is then its own, from the interrupted run).
    progress : Progress, callable, bool or None

    Returns
    -------
    BatchSummary
    """
    outputs = learn_outputs(folders, output_dir)
    params = dict(params or {})
    spec = {
        "kind": "learn",
        "folders": sorted(outputs),
        "outputs": {k: os.fspath(v) for k, v in sorted(outputs.items())},
        "params": params,
    }
    path = Path(results)
    resuming = path.exists() and not overwrite
    tasks = [
        (folder, (folder, os.fspath(output), params, overwrite or resuming))
        for folder, output in outputs.items()
    ]
    return run_batch(
        executor or SerialExecutor(),
        learn_task,
        tasks,
        path,
        spec=spec,
        overwrite=overwrite,
        progress=progress,
        label=f"learn {len(tasks)} skill{'s' * (len(tasks) != 1)}",
    )
