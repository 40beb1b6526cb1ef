"""Tests for lfdkit.app.batch: the executor seam, streamed and resumable results, batch learning.

The generic parts run on small pure work units (``dict`` copies its
argument, ``dict(5)`` raises): a failing task is recorded and the batch goes
on; an interrupted batch resumes with only the missing tasks run and ends
with the same file contents as an uninterrupted one; another batch's file is
refused; a cut-short last line is dropped; the window of tasks in flight is
bounded and the client's memory does not grow with the number of tasks.
Batch learning is checked against :func:`lfdkit.skill.learn` on the same
files, serially and on two local processes, through the command line.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
import time
import tracemalloc
import warnings
from concurrent.futures import Executor, Future, ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from lfdkit.app.batch import (
    ExecutorBrokenError,
    SerialExecutor,
    error_line,
    evaluate_spec,
    learn_outputs,
    make_executor,
    read_results,
    results_header,
    run_batch,
    run_chunk,
    run_unit,
    spec_hash,
    worker_cached,
)
from lfdkit.app.cli import main
from lfdkit.datasets import export_dataset
from lfdkit.skill import learn
from tests.app.batch_work import square_late_first
from tests.app.test_cli import run_cli


def tasks(n: int, fail: tuple[int, ...] = ()):
    """``(i, ({"square": i * i},))``; the tasks in ``fail`` get ``(5,)``: ``dict(5)`` raises."""
    for i in range(n):
        yield i, ((5,) if i in fail else ({"square": i * i},))


def records(path: Path) -> list[dict]:
    return sorted(read_results(path), key=lambda r: r["task"])


SPEC = {"kind": "squares"}


# ------------------------------------------------------------------ executors
def test_serial_executor_returns_finished_futures():
    executor = SerialExecutor()
    assert executor.submit(divmod, 7, 2).result() == (3, 1)
    failed = executor.submit(divmod, 1, 0)
    assert failed.done()
    assert isinstance(failed.exception(), ZeroDivisionError)


def test_serial_executor_lets_an_interrupt_through():
    def interrupt():
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        SerialExecutor().submit(interrupt)


def test_make_executor_defaults_to_serial_and_refuses_two_choices():
    with make_executor() as executor:
        assert isinstance(executor, SerialExecutor)
        assert executor.workers == 1
    with pytest.raises(ValueError, match="scheduler: give one of"):
        with make_executor(workers=2, scheduler="tcp://localhost:1"):
            pass
    with pytest.raises(ValueError, match="workers: expected a whole number"):
        with make_executor(workers=0):
            pass


def test_an_unreachable_scheduler_is_one_clear_error():
    with pytest.raises(ValueError, match=r"scheduler: cannot connect to tcp://127\.0\.0\.1:9"):
        with make_executor(scheduler="tcp://127.0.0.1:9", connect_timeout=2):
            pass


def test_local_processes_write_the_serial_file_byte_for_byte(tmp_path):
    """Rows go in the tasks' order, though task 0 finishes after the others (issue 30)."""
    squares = [(i, (i,)) for i in range(30)]
    run_batch(SerialExecutor(), square_late_first, squares, tmp_path / "a.jsonl", spec=SPEC)
    with make_executor(workers=2) as executor:
        assert executor.workers == 2
        summary = run_batch(executor, square_late_first, squares, tmp_path / "b.jsonl", spec=SPEC)
    assert (summary.done, summary.failed) == (29, 1)
    assert [r["task"] for r in read_results(tmp_path / "b.jsonl")] == list(range(30))
    assert (tmp_path / "b.jsonl").read_bytes() == (tmp_path / "a.jsonl").read_bytes()
    assert summary.workers == 2 and 0.0 < summary.busy_seconds <= 2 * summary.seconds


def _nap(seconds: float) -> dict:
    time.sleep(seconds)
    return {"slept": seconds}


def test_the_overhead_fraction_is_the_share_of_time_outside_the_tasks(tmp_path):
    """Five 20 ms naps in this process: busy 0.1 s or more, and next to nothing outside them."""
    summary = run_batch(
        SerialExecutor(), _nap, [(i, (0.02,)) for i in range(5)], tmp_path / "n.jsonl", spec=SPEC
    )
    assert summary.busy_seconds >= 0.1
    assert summary.busy_seconds <= summary.seconds
    assert summary.overhead_fraction == pytest.approx(1 - summary.busy_seconds / summary.seconds)
    assert 0.0 <= summary.overhead_fraction < 0.5
    assert np.isnan(
        run_batch(SerialExecutor(), _nap, [], tmp_path / "e.jsonl", spec=SPEC).overhead_fraction
    )


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="a forkserver on Linux only")
def test_local_workers_start_with_the_skill_loaded_and_nothing_heavy():
    """Issue 30: workers fork from a server that loaded them once (lfdkit.app.worker_preload).

    numba is not among them (each worker loads it by the kernels' rule), and the
    kernels' CPU clock starts afresh in each worker. The probe is ``eval`` of a
    string, so the worker imports no test module to run it.
    """
    wanted = ("numpy", "numba", "lfdkit.skill", "lfdkit.emulate.planner", "scipy", "mujoco")
    wanted += ("matplotlib", "lfdkit.emulate._planner_numpy")
    modules = "__import__('sys').modules"
    probe = (
        f"([m for m in {wanted!r} if m in {modules}], __import__('os').getpid(),"
        f" {modules}['lfdkit.core.kernels']._clock['cpu_start'])"
    )
    with make_executor(workers=2) as executor:
        got = [executor.submit(eval, probe).result() for _ in range(2)]
    for loaded, pid, clock in got:
        assert pid != os.getpid()
        planner = ["lfdkit.emulate.planner", "lfdkit.emulate._planner_numpy"]
        assert loaded == ["numpy", "lfdkit.skill", *planner]
        assert clock is None  # restarted after the fork server's warm-up


def test_the_fork_server_loads_numba_once_for_a_long_batch_only(monkeypatch):
    """Issue 30: numba in the fork server pays off from COMPILED_TASKS_PER_WORKER tasks a worker."""
    from lfdkit.app.batch import (
        COMPILED_TASKS_PER_WORKER,
        WORKER_PRELOAD,
        WORKER_PRELOAD_COMPILED,
        worker_preload,
    )

    monkeypatch.delenv("LFDKIT_KERNELS", raising=False)
    enough = COMPILED_TASKS_PER_WORKER * 2
    assert worker_preload(enough, 2) == WORKER_PRELOAD_COMPILED
    assert worker_preload(enough - 1, 2) == WORKER_PRELOAD
    assert worker_preload(None, 16) == WORKER_PRELOAD_COMPILED  # a scene file, a learn batch
    monkeypatch.setenv("LFDKIT_KERNELS", "numpy")
    assert worker_preload(None, 2) == WORKER_PRELOAD


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="a forkserver on Linux only")
def test_local_workers_are_started_before_the_batch_s_clock():
    """Issue 30: make_executor yields once the fork server has loaded and a worker is forked.

    So a batch's seconds (its tasks/s) count its tasks, as a serial batch's
    do, not the fork server's loading. The worker is the fork server's
    child, this process's grandchild.
    """
    psutil = pytest.importorskip("psutil")
    me = os.getpid()
    with make_executor(workers=2) as executor:
        workers = [p for p in psutil.Process(me).children(recursive=True) if p.ppid() != me]
        assert workers, "no worker forked yet"
        assert executor.submit(os.getpid).result() in {p.pid for p in workers}


def test_workers_that_execute_plans_preload_numba_and_the_pipeline(monkeypatch):
    """Issue 30: a batch that carries plans onto a robot loads numba and the pipeline once.

    Whatever its length (its rows must equal the serial run's, which the
    NumPy form of the timing law would not, to round-off), and the pipeline
    with SciPy, but not MuJoCo, is in the execution preload (a fresh
    interpreter imports it).
    """
    from lfdkit.app.batch import (
        WORKER_PRELOAD,
        WORKER_PRELOAD_COMPILED,
        WORKER_PRELOAD_EXECUTION,
        worker_modules,
        worker_preload,
    )

    monkeypatch.delenv("LFDKIT_KERNELS", raising=False)
    assert worker_preload(2, 2) == WORKER_PRELOAD
    assert worker_preload(2, 2, executes=True) == WORKER_PRELOAD_COMPILED
    assert worker_modules(2, 2) == [WORKER_PRELOAD]
    assert worker_modules(2, 2, True) == [WORKER_PRELOAD_COMPILED, WORKER_PRELOAD_EXECUTION]
    probe = (
        f"import sys, {WORKER_PRELOAD_EXECUTION}\n"
        "print([m in sys.modules for m in ('lfdkit.execute.pipeline', 'scipy.interpolate',"
        " 'mujoco')])\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=60, check=True
    )
    assert done.stdout.split() == ["[True,", "True,", "False]"]


@pytest.mark.slow  # a fresh interpreter whose fork server loads numba: ~3 s quiet
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="a forkserver on Linux only")
def test_workers_of_a_long_batch_start_on_numba_s_kernels():
    """The fork server started early with the compiled preload: workers plan on numba at once.

    In a fresh interpreter: a process has one fork server, and this test
    process's may already run the other preload.
    """
    code = (
        "from lfdkit.app.batch import ProcessExecutor, start_worker_server\n"
        "assert start_worker_server(64, 2)\n"
        "probe = \"('numba' in __import__('sys').modules,"
        " __import__('lfdkit.core.kernels').core.kernels.use_compiled())\"\n"
        "with ProcessExecutor(2) as pool:\n"
        "    print(pool.submit(eval, probe).result())\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "LFDKIT_KERNELS"}
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120
    )
    assert done.returncode == 0, done.stderr[-500:]
    loaded, compiled = eval(done.stdout.strip().splitlines()[-1])
    assert loaded and compiled


class _ForkServerStarted(Exception):
    """Raised by a stand-in for ``start_worker_server``: the command reached it."""


@pytest.mark.parametrize(
    "argv",
    [
        ["--task", "sweep", "--rate", "100"],  # a path-task option for the sweep
        ["--task", "path", "--rate", "fast"],
        ["--task", "sweep", "--start", "0.1,0.2"],  # --start with random scenes
        ["--task", "path", "--check", "kinematics"],
        ["--task", "path", "--spread", "-1"],
        ["--start", "0.1,0.2"],  # the default task: refused by the sweep once it is known
    ],
)
def test_a_usage_error_starts_no_fork_server(
    monkeypatch, capsys, tmp_path, example_skill_file_once, argv
):
    """Issue 30: the workers' fork server starts once the options are checked, not before.

    Before, it started at the command's first line, and a usage error left it
    loading (about 1.7 s of CPU) in the background. A valid command reaches it
    before the skill loads (the control: the stand-in's exception ends it).
    """

    def started(*args, **kwargs):
        raise _ForkServerStarted

    monkeypatch.setattr("lfdkit.app.batch.start_worker_server", started)
    out = tmp_path / "r.jsonl"
    skill = example_skill_file_once
    base = ["batch", "evaluate", skill, "--random", "4", "--workers", "2", "-o", out]
    code, _, err = run_cli(capsys, *base, *argv)
    assert code == 2 and "error: " in err and "_ForkServerStarted" not in err
    code, _, err = run_cli(capsys, *base)
    assert code == 1 and "_ForkServerStarted" in err
    code, _, err = run_cli(
        capsys, "batch", "learn", tmp_path / "missing", "--workers", "2", "-o", out
    )
    assert code == 2 and "no such folder" in err


@pytest.mark.slow  # two fresh interpreters that load numba: ~2 s each quiet
def test_a_long_batch_loads_numba_before_its_first_task_serial_or_on_workers():
    """A serial batch of 64 tasks, and a long batch's workers forked from a fork server
    an earlier short batch started without numba (a process has one), load numba
    before their first task instead of running the NumPy kernels for a second first;
    a short serial batch does not.
    """
    serial = (
        "import sys\n"
        "from lfdkit.app.batch import make_executor\n"
        "with make_executor(tasks=4):\n"
        "    short = 'numba' in sys.modules\n"
        "with make_executor(tasks=64):\n"
        "    print(short, 'numba' in sys.modules)\n"
    )
    workers = (
        "from lfdkit.app.batch import ProcessExecutor, start_worker_server\n"
        "start_worker_server(2, 2)\n"  # a short batch's: no numba in the fork server
        "probe = \"'numba' in __import__('sys').modules\"\n"
        "with ProcessExecutor(2, tasks=2) as pool:\n"
        "    short = pool.submit(eval, probe).result()\n"
        "with ProcessExecutor(2, tasks=64) as pool:\n"
        "    print(short, pool.submit(eval, probe).result())\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "LFDKIT_KERNELS"}
    codes = [serial, workers] if sys.platform.startswith("linux") else [serial]
    for code in codes:
        done = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120
        )
        assert done.returncode == 0, done.stderr[-500:]
        assert done.stdout.split() == ["False", "True"]


# ------------------------------------------------------------------ results files
def test_results_stream_to_the_file_and_a_failure_does_not_stop_the_batch(tmp_path):
    path = tmp_path / "r.jsonl"
    summary = run_batch(SerialExecutor(), dict, tasks(6, fail=(2, 4)), path, spec=SPEC)
    assert (summary.total, summary.done, summary.failed, summary.skipped) == (6, 4, 2, 0)
    assert summary.errors[0].startswith("2: TypeError: ")
    header = results_header(path)
    assert header["hash"] == spec_hash(SPEC)
    assert header["spec"] == SPEC
    got = records(path)
    assert [r["task"] for r in got] == list(range(6))
    assert got[3] == {"task": 3, "square": 9}
    assert got[2]["error"].startswith("TypeError: ")
    assert "square" not in got[4]


def test_an_interrupted_batch_resumes_where_it_stopped(tmp_path):
    whole, part = tmp_path / "whole.jsonl", tmp_path / "part.jsonl"
    run_batch(SerialExecutor(), dict, tasks(20, fail=(7,)), whole, spec=SPEC)

    def interrupted():
        for k, task in enumerate(tasks(20, fail=(7,))):
            if k == 12:
                raise KeyboardInterrupt
            yield task

    with pytest.raises(KeyboardInterrupt):
        run_batch(SerialExecutor(), dict, interrupted(), part, spec=SPEC)
    assert len(records(part)) == 12

    ran = []

    class Counting(SerialExecutor):
        def submit(self, fn, /, *args, **kwargs):
            ran.append(args)
            return super().submit(fn, *args, **kwargs)

    summary = run_batch(Counting(), dict, tasks(20, fail=(7,)), part, spec=SPEC)
    assert len(ran) == 8
    assert (summary.skipped, summary.done, summary.failed, summary.failed_before) == (12, 8, 0, 1)
    assert records(part) == records(whole)
    # The same batch again: nothing left to run.
    again = run_batch(Counting(), dict, tasks(20, fail=(7,)), part, spec=SPEC)
    assert (again.skipped, again.done, len(ran)) == (20, 0, 8)


def test_a_line_cut_short_is_dropped_and_its_task_run_again(tmp_path):
    path = tmp_path / "r.jsonl"
    run_batch(SerialExecutor(), dict, tasks(5), path, spec=SPEC)
    text = path.read_text()
    path.write_text(text[: text.rindex('{"task"') + 9])  # killed while writing the last record
    assert len(list(read_results(path))) == 4
    summary = run_batch(SerialExecutor(), dict, tasks(5), path, spec=SPEC)
    assert (summary.skipped, summary.done) == (4, 1)
    assert records(path) == [{"task": i, "square": i * i} for i in range(5)]


def test_another_batchs_file_is_refused_unless_overwritten(tmp_path):
    path = tmp_path / "r.jsonl"
    run_batch(SerialExecutor(), dict, tasks(3), path, spec=SPEC)
    with pytest.raises(ValueError, match="holds the results of another batch"):
        run_batch(SerialExecutor(), dict, tasks(3), path, spec={"kind": "cubes"})
    summary = run_batch(
        SerialExecutor(), dict, tasks(2), path, spec={"kind": "cubes"}, overwrite=True
    )
    assert summary.done == 2
    assert results_header(path)["spec"] == {"kind": "cubes"}
    not_ours = tmp_path / "other.jsonl"
    not_ours.write_text('{"a": 1}\n')
    with pytest.raises(ValueError, match="not an lfdkit batch results file"):
        run_batch(SerialExecutor(), dict, tasks(3), not_ours, spec=SPEC)


def test_a_dead_worker_process_ends_the_batch_with_its_results_kept(tmp_path):
    import os

    path = tmp_path / "r.jsonl"
    work = [(0, ({"a": 1},)), (1, (0,))]
    with pytest.raises(ExecutorBrokenError, match="run the batch again to resume"):
        with make_executor(workers=1) as executor:
            run_batch(executor, dict, work[:1], path, spec=SPEC)
            run_batch(executor, os._exit, work[1:], path, spec=SPEC)
    assert records(path) == [{"task": 0, "a": 1}]


# ------------------------------------------------------------------ bounded work in flight
class _Watching(Executor):
    """Threads that finish tasks one by one, counting how many are in flight at once."""

    def __init__(self) -> None:
        self._pool = ThreadPoolExecutor(2)
        self._lock = threading.Lock()
        self.in_flight = self.most = 0
        self.workers = 2

    def submit(self, fn, /, *args, **kwargs) -> Future:
        with self._lock:
            self.in_flight += 1
            self.most = max(self.most, self.in_flight)
        future = self._pool.submit(fn, *args, **kwargs)
        future.add_done_callback(self._finished)
        return future

    def _finished(self, future: Future) -> None:
        with self._lock:
            self.in_flight -= 1

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        self._pool.shutdown(wait=wait, cancel_futures=cancel_futures)


def test_tasks_in_flight_stay_within_the_window(tmp_path):
    executor = _Watching()
    consumed = []

    def lazy():
        for task in tasks(500):
            consumed.append(task[0])
            yield task

    summary = run_batch(executor, dict, lazy(), tmp_path / "r.jsonl", spec=SPEC, window=5)
    executor.shutdown()
    assert summary.done == 500
    assert 1 < executor.most <= 5
    default = _Watching()
    run_batch(default, dict, tasks(200), tmp_path / "d.jsonl", spec=SPEC)
    default.shutdown()
    assert default.most <= 8  # 4 per worker


# ------------------------------------------------------------------ a worker's warnings
class _Elsewhere(Executor):
    """Runs each unit at once as a pool's worker would: what it shows itself, nobody sees."""

    workers = 2

    def submit(self, fn, /, *args, **kwargs) -> Future:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a worker's own stderr
            return SerialExecutor().submit(fn, *args, **kwargs)


class _Poor(UserWarning):
    def __init__(self, value: float, where: str) -> None:  # not (message,): rebuilt without it
        super().__init__(f"task: {value} is poor at {where}")


def _warning_square(i: int) -> dict:
    if i % 2:
        warnings.warn(f"task: odd {i % 3}", UserWarning, stacklevel=1)  # 2 distinct texts
    if i == 4:
        warnings.warn(_Poor(0.5, "four"), stacklevel=1)
    return {"square": i * i}


def test_a_worker_s_warnings_are_raised_again_where_the_serial_run_raises_them(tmp_path):
    """Issue 30: the caller shows a worker's warnings as its own (same text, place, once)."""
    work = [(i, (i,)) for i in range(9)]
    shown = {}
    for name, executor in (("serial", SerialExecutor()), ("units", _Elsewhere())):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("default")
            run_batch(executor, _warning_square, work, tmp_path / f"{name}.jsonl", spec=SPEC)
        shown[name] = sorted((str(w.message), w.category.__name__, w.lineno) for w in caught)
        squares = [{"task": i, "square": i * i} for i in range(9)]
        assert records(tmp_path / f"{name}.jsonl") == squares
    assert shown["units"] == shown["serial"]
    assert [text for text, _, _ in shown["serial"]] == [
        "task: 0.5 is poor at four",
        "task: odd 0",
        "task: odd 1",
        "task: odd 2",
    ]


def test_a_unit_records_its_warnings_and_prints_none(capsys):
    outcomes, _, raised = run_unit(_warning_square, [(3,), (4,), (13,)])
    assert outcomes == [{"square": 9}, {"square": 16}, {"square": 169}]
    assert [(text, category) for text, category, _, _ in raised] == [
        ("task: odd 0", UserWarning),
        ("task: 0.5 is poor at four", _Poor),
        ("task: odd 1", UserWarning),
    ]
    assert capsys.readouterr().err == ""


# ------------------------------------------------------------------ chunks of short tasks
class _Counting(_Watching):
    """:class:`_Watching` that keeps what each unit submitted was: a lone task or a chunk."""

    def __init__(self) -> None:
        super().__init__()
        self.units: list[int] = []

    def submit(self, fn, /, *args, **kwargs) -> Future:
        self.units.append(len(args[1]) if fn is run_unit else 1)
        return super().submit(fn, *args, **kwargs)


def _slow_square(i: int, seconds: float) -> dict:
    time.sleep(seconds)
    if i == 13:
        raise ValueError(f"task {i}: no square\nsecond line")
    return {"square": i * i}


def test_short_tasks_travel_in_chunks_long_ones_alone_and_the_records_are_the_same(tmp_path):
    """Issue 30: ~5 ms tasks go tens to a chunk of 0.25 s, fewer as the batch ends."""
    work = [(i, (i, 0.005)) for i in range(120)]
    run_batch(SerialExecutor(), _slow_square, work, tmp_path / "serial.jsonl", spec=SPEC)
    short = _Counting()
    summary = run_batch(short, _slow_square, work, tmp_path / "short.jsonl", spec=SPEC)
    short.shutdown()
    assert (summary.done, summary.failed) == (119, 1)
    assert summary.errors == ["13: ValueError: task 13: no square"]
    assert records(tmp_path / "short.jsonl") == records(tmp_path / "serial.jsonl")
    units = short.units
    assert sum(units) == 120
    assert units[:8] == [1] * 8  # nothing timed yet: one at a time, a window of 8
    assert max(units) >= 10 and len(units) < 40  # sleep overshoots on a shared machine
    # Every worker keeps a share at the end: no chunk holds over a quarter of what is left.
    left = 120 - np.cumsum([0, *units[:-1]])
    assert all(size <= max(1, rest // 4) for size, rest in zip(units, left, strict=True))
    # Tasks longer than the chunk's seconds, or chunks off: one task per unit.
    long = _Counting()
    run_batch(long, _slow_square, work[:30], tmp_path / "long.jsonl", spec=SPEC, chunk_seconds=1e-4)
    off = _Counting()
    run_batch(off, _slow_square, work[:30], tmp_path / "off.jsonl", spec=SPEC, chunk_seconds=0)
    long.shutdown()
    off.shutdown()
    assert long.units == [1] * 30 and off.units == [1] * 30
    assert records(tmp_path / "long.jsonl") == records(tmp_path / "serial.jsonl")[:30]


def test_a_chunk_records_each_failure_and_goes_on():
    outcomes, seconds = run_chunk(dict, [({"a": 1},), (5,), ({"b": 2},)])
    assert outcomes[0] == {"a": 1} and outcomes[2] == {"b": 2}
    assert outcomes[1]["error"].startswith("TypeError: ")
    assert seconds >= 0.0


@pytest.mark.parametrize("bad", [-1.0, float("nan"), float("inf")])
def test_chunk_seconds_out_of_range_is_refused(tmp_path, bad):
    with pytest.raises(ValueError, match="chunk_seconds: expected seconds >= 0, got"):
        run_batch(
            SerialExecutor(), dict, tasks(2), tmp_path / "r.jsonl", spec=SPEC, chunk_seconds=bad
        )


def _peak_bytes(n: int, path: Path) -> int:
    tracemalloc.start()
    try:
        run_batch(SerialExecutor(), dict, tasks(n), path, spec=SPEC, total=n)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_the_clients_memory_does_not_grow_with_the_number_of_tasks(tmp_path):
    small = _peak_bytes(500, tmp_path / "small.jsonl")
    large = _peak_bytes(5_000, tmp_path / "large.jsonl")
    assert len(list(read_results(tmp_path / "large.jsonl"))) == 5_000
    # Accumulating the 5,000 results would take a megabyte; streaming them takes nothing more.
    assert large < small + 64 * 1024, (small, large)


def test_progress_reports_throughput(tmp_path):
    from lfdkit.core.progress import Progress

    heard: list[str] = []
    progress = Progress(bars=False, log=False, callback=heard.append, heartbeat=0)
    path = tmp_path / "r.jsonl"
    run_batch(SerialExecutor(), dict, tasks(4), path, spec=SPEC, total=4, progress=progress)
    assert heard[0] == "batch"
    assert heard[-1].startswith("batch: 4/4, ") and "tasks/s" in heard[-1]


# ------------------------------------------------------------------ learning in batch
@pytest.fixture(scope="module")
def folders(tmp_path_factory) -> list[Path]:
    root = tmp_path_factory.mktemp("learn")
    made = []
    for name in ("noisy_band", "different_extents"):
        folder = root / name
        folder.mkdir()
        export_dataset(name, folder / "demos.csv", seed=1)
        made.append(folder)
    (root / "empty").mkdir()
    return [*made, root / "empty"]


@pytest.fixture(scope="module")
def expected_skills(folders) -> dict[Path, dict]:
    """Each data folder's skill as the Python API learns it (seed 3), as its file reads back:
    learned once for both batch-learn tests."""
    return {
        folder: json.loads(json.dumps(learn(folder / "demos.csv", random_state=3).to_dict()))
        for folder in folders[:2]
    }


def test_batch_learn_writes_each_skill_and_records_the_failing_folder(
    folders, expected_skills, capsys, tmp_path
):
    results = tmp_path / "learn.jsonl"
    code, _, err = run_cli(capsys, "batch", "learn", *folders, "--seed", 3, "-o", results)
    assert code == 1
    assert "1 of 3 tasks failed" in err and "no demos.csv" in err
    got = {r["task"]: r for r in read_results(results)}
    assert got[str(folders[2])]["error"].startswith("FileNotFoundError: ")
    for folder in folders[:2]:
        row = got[str(folder)]
        assert row["skill"] == str(folder / "skill.json")
        assert row["clean_demos"] == 10
        assert json.loads((folder / "skill.json").read_text()) == expected_skills[folder]
    # Run again: resumed, nothing rerun, the failure still reported.
    code, _, err = run_cli(capsys, "batch", "learn", *folders, "--seed", 3, "-o", results)
    assert code == 1 and "1 of 3 tasks failed" in err
    assert len(list(read_results(results))) == 3
    # Another batch into the same file is refused; a new file refuses to overwrite the skills.
    code, _, err = run_cli(capsys, "batch", "learn", *folders[:2], "-o", results)
    assert code == 1 and "another batch" in err
    code, _, err = run_cli(capsys, "batch", "learn", *folders[:2], "-o", tmp_path / "new.jsonl")
    assert code == 1 and "skill.json: exists; pass --force" in err


@pytest.mark.slow  # two fresh processes import scikit-learn and numba: ~20 s on 2 cores
def test_batch_learn_on_two_processes_learns_the_same_skills(
    folders, expected_skills, capsys, tmp_path
):
    out = tmp_path / "skills"
    out.mkdir()
    argv = ["batch", "learn", *folders[:2], "--seed", 3, "--output-dir", out]
    code, _, err = run_cli(capsys, *argv, "--workers", 2, "-o", tmp_path / "p.jsonl")
    assert code == 0, err
    for folder in folders[:2]:
        written = json.loads((out / f"{folder.name}.json").read_text())
        assert written == expected_skills[folder]


def test_learn_outputs_refuses_clashing_names(tmp_path):
    with pytest.raises(ValueError, match="both called 'x'"):
        learn_outputs([tmp_path / "a" / "x", tmp_path / "b" / "x"], tmp_path)
    with pytest.raises(ValueError, match="given twice"):
        learn_outputs(["a", "a"])
    assert learn_outputs(["a"]) == {"a": Path("a") / "skill.json"}


def test_batch_usage_errors(capsys, tmp_path):
    code, _, err = run_cli(capsys, "batch", "learn", tmp_path / "nope", "-o", tmp_path / "r.jsonl")
    assert code == 2 and "no such folder" in err
    with pytest.raises(SystemExit) as exc:
        main(["batch", "learn", str(tmp_path), "--workers", "2", "--dask-local", "2", "-o", "r"])
    assert exc.value.code == 2
    assert "not allowed with argument" in capsys.readouterr().err


# ------------------------------------------------------------------ hostile results files
def test_a_special_file_or_link_as_results_is_refused_never_written_through(tmp_path):
    import os

    fifo = tmp_path / "fifo.jsonl"
    os.mkfifo(fifo)
    for overwrite in (False, True):  # would block forever if opened
        with pytest.raises(OSError, match="named pipe"):
            run_batch(SerialExecutor(), dict, tasks(2), fifo, spec=SPEC, overwrite=overwrite)
    target = tmp_path / "precious.txt"
    target.write_text("keep me\n")
    link = tmp_path / "link.jsonl"
    link.symlink_to(target)
    for overwrite in (False, True):
        with pytest.raises(OSError, match="symbolic link"):
            run_batch(SerialExecutor(), dict, tasks(2), link, spec=SPEC, overwrite=overwrite)
    assert target.read_text() == "keep me\n" and link.is_symlink()


def test_the_command_refuses_a_fifo_or_link_output_with_and_without_force(capsys, tmp_path):
    import os

    fifo = tmp_path / "fifo.jsonl"
    os.mkfifo(fifo)
    target = tmp_path / "precious.txt"
    target.write_text("keep me\n")
    link = tmp_path / "link.jsonl"
    link.symlink_to(target)
    for out, what in ((fifo, "named pipe"), (link, "symbolic link")):
        for force in ((), ("--force",)):
            code, _, err = run_cli(capsys, "batch", "learn", tmp_path, "-o", out, *force)
            assert code == 2, err
            assert f"error: --output {out}: is a {what}" in err and err.count("\n") == 1
    assert target.read_text() == "keep me\n"


def test_a_second_writer_of_one_results_file_is_refused(tmp_path):
    path = tmp_path / "r.jsonl"
    inner = []

    def second(item):  # runs while the first batch holds the file
        if not inner:
            inner.append(True)
            with pytest.raises(RuntimeError, match=r"in use by another batch \(pid \d+\)"):
                run_batch(SerialExecutor(), dict, tasks(4), path, spec=SPEC)
            with pytest.raises(RuntimeError, match="in use by another batch"):
                run_batch(SerialExecutor(), dict, tasks(4), path, spec=SPEC, overwrite=True)
        return item

    summary = run_batch(SerialExecutor(), second, tasks(4), path, spec=SPEC)
    assert inner and summary.done == 4
    assert records(path) == [{"task": i, "square": i * i} for i in range(4)]
    assert not (tmp_path / ".r.jsonl.pid").exists()  # the pid note goes with the lock
    # Released: a later run resumes the file.
    assert run_batch(SerialExecutor(), dict, tasks(4), path, spec=SPEC).skipped == 4


def test_a_task_written_twice_is_kept_once_on_resume(tmp_path):
    path = tmp_path / "r.jsonl"
    run_batch(SerialExecutor(), dict, tasks(16), path, spec=SPEC)
    lines = path.read_text().splitlines(keepends=True)
    path.write_text("".join([*lines, lines[5]]))  # task 4 twice: 17 rows for 16 tasks
    with pytest.warns(UserWarning, match="1 task row appeared twice; kept the first"):
        summary = run_batch(SerialExecutor(), dict, tasks(16), path, spec=SPEC)
    assert (summary.skipped, summary.done) == (16, 0)
    got = list(read_results(path))
    assert len(got) == 16 and sorted(r["task"] for r in got) == list(range(16))


def test_batch_learn_refuses_millimetres_read_as_metres(capsys, tmp_path):
    """As ``lfdkit learn``: without --units, a folder implausible in metres fails, saying why."""
    from lfdkit.io import load_demos, save_demos
    from lfdkit.tasks.sweeping import example_files

    sweeps = load_demos(example_files()["demos"])[:4]
    folders = []
    for name, factor in (("in_mm", 1e3), ("in_m", 1.0)):
        folder = tmp_path / name
        folder.mkdir()
        save_demos(folder / "demos.csv", [factor * d for d in sweeps])
        folders.append(folder)
    results = tmp_path / "learn.jsonl"
    code, _, err = run_cli(capsys, "batch", "learn", *folders, "-o", results)
    assert code == 1 and "1 of 2 tasks failed" in err
    got = {r["task"]: r for r in read_results(results)}
    error = got[str(folders[0])]["error"]
    assert error.startswith("ValueError: ") and "more than a demonstration can (over 20 m)" in error
    assert "in mm they would span 0.8 m" in error and "pass --units mm" in error
    assert not (folders[0] / "skill.json").exists()
    assert got[str(folders[1])]["units"] == "m"
    code, _, err = run_cli(
        capsys, "batch", "learn", folders[0], "--units", "mm", "-o", tmp_path / "mm.jsonl"
    )
    assert code == 0, err
    assert json.loads((folders[0] / "skill.json").read_text())["units"] == "mm"


def test_a_worker_builds_each_text_once_and_keeps_one_per_kind():
    built = []

    def build(name):
        return lambda: built.append(name) or name

    assert worker_cached("test-skill", "a", build("a")) == "a"
    assert worker_cached("test-skill", "a", build("a again")) == "a"  # not rebuilt
    assert worker_cached("test-arm", "a", build("arm a")) == "arm a"  # kinds apart
    assert worker_cached("test-skill", "b", build("b")) == "b"
    assert worker_cached("test-skill", "a", build("a, rebuilt")) == "a, rebuilt"  # b replaced a
    assert worker_cached("test-arm", "a", build("arm a again")) == "arm a"  # the arm kept
    assert built == ["a", "arm a", "b", "a, rebuilt"]


def test_the_evaluate_spec_and_failure_line_both_tasks_share():
    spec = evaluate_spec("path", "{}", arm="ur5", check="plan")
    assert list(spec) == ["kind", "task", "skill", "arm", "check", "lfdkit"]  # the header's order
    assert spec["skill"] == "44136fa355b3678a1146ad16f7e8649e94fb4fc21fe77e8310c060f61caaff8a"
    assert error_line(ValueError("first\nsecond")) == "ValueError: first"
    assert error_line(RuntimeError()) == "RuntimeError"  # an empty message is still one line
