"""What tests in several folders share: the sweeping example skill, learned once a
session, and the ``lfdkit demo`` runs.

Learning it takes ~3 s on the CI's 2-core machine and eight test modules plan
with it, so it is learned once (the example files, default parameters) and each
module takes its own copy (:func:`copy.deepcopy` of the skill, or of its file in
the module's own folder): no module sees another's changes. The tests of
learning itself (tests/skill/) still learn their own.

The demo (~15 s a run) runs twice at once, one run per core, for the whole
session: ``-v`` into ``out`` (the command's test in tests/app/test_cli.py and
the report's in tests/tasks/sweeping/test_demo_report.py read it; neither
writes there) and ``--quiet --force`` over a stale ``quiet/results.json``.
"""

from __future__ import annotations

import copy
import shutil
import subprocess
from pathlib import Path
from types import SimpleNamespace

import pytest

from lfdkit.skill import Skill, learn
from lfdkit.tasks.sweeping import example_files


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


@pytest.fixture(scope="session")
def demo_runs(tmp_path_factory) -> SimpleNamespace:
    """``lfdkit demo -v`` and ``lfdkit demo --quiet --force``, run at once (read only).

    Returns ``folder`` (their working folder), ``out`` and ``verbose`` (the ``-v``
    run's folder and its :class:`subprocess.CompletedProcess`), ``quiet`` and
    ``quiet_run`` (the same for the quiet run).
    """
    folder = tmp_path_factory.mktemp("demo")
    out, quiet = folder / "out", folder / "quiet"
    quiet.mkdir()
    (quiet / "results.json").write_text("stale")
    quiet_command = ["lfdkit", "demo", "--output", str(quiet), "--quiet", "--force"]
    run = subprocess.Popen(
        quiet_command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=folder
    )
    try:
        verbose = subprocess.run(
            ["lfdkit", "demo", "--output", str(out), "-v"],
            capture_output=True,
            text=True,
            timeout=300,
            cwd=folder,
        )
        stdout, stderr = run.communicate(timeout=300)
    finally:
        if run.poll() is None:
            run.kill()
            run.communicate()
    quiet_run = subprocess.CompletedProcess(quiet_command, run.returncode, stdout, stderr)
    return SimpleNamespace(
        folder=folder, out=out, verbose=verbose, quiet=quiet, quiet_run=quiet_run
    )
