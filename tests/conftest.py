"""What tests in several folders share: the sweeping example skill, learned once a
session, and the ``lfdkit demo`` runs.

Learning it takes ~3 s on the CI's 2-core machine and eight test modules plan
with it, so it is learned once (the example files, default parameters) and each
module takes its own copy (:func:`copy.deepcopy` of the skill, or of its file in
the module's own folder): no module sees another's changes. The tests of
learning itself (tests/skill/) still learn their own.

The demo (~15 s a run) runs twice for the whole session: ``-v`` into ``out``
(the command's test in tests/app/test_cli.py and the report's in
tests/tasks/sweeping/test_demo_report.py read it; neither writes there) and
``--quiet --force`` over a stale ``quiet/results.json``. When the collected
tests use them, both start in the background as soon as collection ends, one
after the other: they run on the core the (single-process) test run leaves idle
and are done by the time the command's test asks for them, instead of holding
the run ~26 s there (the same two runs, the same checks).

BLAS and OpenMP run one thread in the test process and the processes it starts
(``OPENBLAS_NUM_THREADS`` etc., unless set; :mod:`threadpoolctl` for the
libraries already loaded). The suite's arrays are small: SciPy's L-BFGS-B
(the reference planner of tests/emulate/test_planner_safety.py, the IOC fits)
spent ~95 % of its time in OpenBLAS's threads waiting on each other when the
cores are busy (3 reference costs 20.8 s -> 1.4 s of CPU at load 20). Results
do not change: no assertion depends on the number of threads.
"""

# ruff: noqa: E402 (the thread settings come before the imports that load BLAS)
from __future__ import annotations

import os

for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")  # before SciPy's own OpenBLAS loads

import copy
import shutil
import subprocess
import tempfile
import threading
from pathlib import Path
from types import SimpleNamespace

import pytest

from lfdkit.skill import Skill, learn
from lfdkit.tasks.sweeping import example_files

try:  # the libraries loaded before this file (NumPy's OpenBLAS): one thread too
    from threadpoolctl import threadpool_limits
except ImportError:  # pragma: no cover - scikit-learn brings it
    pass
else:
    threadpool_limits(1)


@pytest.fixture(scope="session")
def example_skill_once() -> Skill:
    """The example skill as :func:`~lfdkit.skill.learn` returns it (share: do not change it)."""
    files = example_files()
    return learn(files["demos"], files["scenes"])


@pytest.fixture(scope="session")
def example_skill_file_once(example_skill_once, tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("example_skill") / "skill.json"
    example_skill_once.save(path)
    return path


def example_skill_copy(shared: Skill) -> Skill:
    """A module's own copy of the shared example skill."""
    return copy.deepcopy(shared)


def example_skill_file_copy(shared: Path, folder: Path) -> Path:
    """A module's own copy of the shared example skill's file, in ``folder``."""
    path = folder / "skill.json"
    shutil.copyfile(shared, path)
    return path


class _DemoRuns:
    """The two demo runs, in a background thread started once for the session."""

    def __init__(self) -> None:
        self.folder = Path(tempfile.mkdtemp(prefix="lfdkit-demo-runs-"))
        self.out, self.quiet = self.folder / "out", self.folder / "quiet"
        self.quiet.mkdir()
        (self.quiet / "results.json").write_text("stale")
        self.verbose_command = ["lfdkit", "demo", "--output", str(self.out), "-v"]
        self.quiet_command = ["lfdkit", "demo", "--output", str(self.quiet), "--quiet", "--force"]
        self.runs: dict[str, subprocess.CompletedProcess | BaseException] = {}
        self.running: subprocess.Popen | None = None
        self.stopped = False
        self.thread = threading.Thread(target=self._run_both, name="demo-runs", daemon=True)
        self.thread.start()

    def _run(self, name: str, command: list[str]) -> None:
        try:
            if self.stopped:
                raise RuntimeError("the test session ended first")
            self.running = subprocess.Popen(
                command,
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
                cwd=self.folder,
            )
            stdout, stderr = self.running.communicate(timeout=300)
            self.runs[name] = subprocess.CompletedProcess(
                command, self.running.returncode, stdout, stderr
            )
        except BaseException as exc:  # kept for the test that reads the run
            if self.running is not None and self.running.poll() is None:
                self.running.kill()
                self.running.communicate()
            self.runs[name] = exc

    def _run_both(self) -> None:
        self._run("verbose", self.verbose_command)
        self._run("quiet", self.quiet_command)

    def result(self) -> SimpleNamespace:
        self.thread.join(timeout=700)
        if self.thread.is_alive():
            raise TimeoutError("the two demo runs took over 700 s")
        for name in ("verbose", "quiet"):
            if isinstance(self.runs[name], BaseException):
                raise self.runs[name]
        return SimpleNamespace(
            folder=self.folder,
            out=self.out,
            verbose=self.runs["verbose"],
            quiet=self.quiet,
            quiet_run=self.runs["quiet"],
        )

    def stop(self) -> None:
        self.stopped = True
        if self.running is not None and self.running.poll() is None:
            self.running.kill()
        self.thread.join(timeout=30)
        shutil.rmtree(self.folder, ignore_errors=True)


_demo_runs: _DemoRuns | None = None


def pytest_collection_finish(session: pytest.Session) -> None:
    """Start the demo runs in the background if a collected test reads them."""
    global _demo_runs
    wanted = any("demo_runs" in getattr(item, "fixturenames", ()) for item in session.items)
    # Not in pytest-xdist's workers: each collects every test, and would start its own.
    worker = hasattr(session.config, "workerinput")
    if wanted and _demo_runs is None and not worker and not session.config.option.collectonly:
        _demo_runs = _DemoRuns()


def pytest_sessionfinish(session: pytest.Session) -> None:
    if _demo_runs is not None:
        _demo_runs.stop()


@pytest.fixture(scope="session")
def demo_runs() -> SimpleNamespace:
    """``lfdkit demo -v`` and ``lfdkit demo --quiet --force`` (read only), run in the
    background from the end of collection (see the module's docstring).

    Returns ``folder`` (their working folder), ``out`` and ``verbose`` (the ``-v``
    run's folder and its :class:`subprocess.CompletedProcess`), ``quiet`` and
    ``quiet_run`` (the same for the quiet run).
    """
    global _demo_runs
    if _demo_runs is None:  # collected without the hook (e.g. another rootdir's conftest)
        _demo_runs = _DemoRuns()
    return _demo_runs.result()
