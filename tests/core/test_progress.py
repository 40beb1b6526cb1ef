"""Tests for lfdkit.core.progress: silent by default, callbacks, log records with times, bars.

Bars are drawn into a StringIO (no terminal needed: ``bars=True`` forces
them); the clock of an open bar is checked to keep running without any
progress being reported.
"""

from __future__ import annotations

import io
import logging
import pickle
import re
import time

import numpy as np
import pytest

import lfdkit.core.progress as progress_module
from lfdkit.core.progress import LOGGER, Progress, as_progress
from lfdkit.skill import Skill

RECORDS = "lfdkit.core.progress"  # the logger's name (lfdkit.core.progress.LOGGER)


def run_stages(progress: Progress) -> None:
    """An outer stage with three counted items and a nested stage that describes itself."""
    with progress.stage("outer", total=3) as outer:
        for _ in range(3):
            outer.advance(detail="ok")
        with progress.stage("inner", announce=False) as inner:
            inner.describe("inner: did its work")


# ------------------------------------------------------------------ as_progress
@pytest.mark.parametrize("value", [None, False])
def test_none_and_false_are_silent(value, caplog, capsys):
    caplog.set_level(logging.INFO, logger=RECORDS)
    progress = as_progress(value)
    assert progress.silent
    with progress.stage("work", total=2) as stage:
        stage.advance()
        stage.advance()
    assert stage.done == 2
    assert stage.seconds >= 0
    assert caplog.records == []
    assert capsys.readouterr() == ("", "")


def test_a_callable_hears_each_stage_as_it_starts():
    heard: list[str] = []
    run_stages(as_progress(heard.append))
    # "inner" was not announced at its start: it said what it did instead.
    assert heard == ["outer", "inner: did its work"]


def test_a_callable_hears_how_far_a_long_stage_has_come():
    heard: list[str] = []
    progress = Progress(bars=False, log=False, callback=heard.append, heartbeat=0.0)
    with progress.stage("fit", unit="iteration") as stage:
        stage.advance(detail="loss 0.5")
        stage.advance(detail="loss 0.25")
    assert heard[0] == "fit"
    assert re.fullmatch(r"fit: iteration 1, loss 0\.5, \d+\.\d s", heard[1])
    assert re.fullmatch(r"fit: iteration 2, loss 0\.25, \d+\.\d s", heard[2])


def test_true_is_a_progress_with_records_and_a_progress_is_itself():
    made = as_progress(True)
    assert isinstance(made, Progress) and made.log
    assert as_progress(made) is made


@pytest.mark.parametrize("value", ["yes", 1, 0.5, object()])
def test_anything_else_is_refused_naming_the_argument(value):
    with pytest.raises(TypeError, match=r"^progress: expected True, False, None, a callable"):
        as_progress(value)


def test_bad_settings_are_refused_naming_them():
    with pytest.raises(TypeError, match=r"^callback: expected a callable"):
        Progress(callback="print")
    with pytest.raises(ValueError, match=r"^heartbeat: expected a number of seconds >= 0"):
        Progress(heartbeat=-1.0)
    with pytest.raises(ValueError, match=r"^total: expected a count >= 0"):
        Progress(bars=False).stage("x", total=-1)


# ------------------------------------------------------------------ records
def test_records_say_each_stage_start_and_wall_time_with_its_depth(caplog):
    caplog.set_level(logging.INFO, logger=RECORDS)
    run_stages(Progress(bars=False, log=True, heartbeat=60.0))
    lines = [(r.depth, r.getMessage()) for r in caplog.records]
    assert lines[0] == (0, "outer ...")
    assert lines[1] == (1, "inner ...")
    assert lines[2][0] == 1
    assert re.fullmatch(r"inner: did its work: done in \d+\.\d\d s", lines[2][1])
    assert re.fullmatch(r"outer: done in \d+\.\d\d s", lines[3][1])
    elapsed = [r.elapsed for r in caplog.records]
    assert elapsed == sorted(elapsed) and elapsed[0] >= 0


def test_a_failed_stage_says_so_and_closes_what_it_held(caplog):
    caplog.set_level(logging.INFO, logger=RECORDS)
    out = io.StringIO()
    progress = Progress(bars=True, log=True, file=out)
    with pytest.raises(RuntimeError, match="boom"):
        with progress.stage("outer"), progress.stage("inner"):
            raise RuntimeError("boom")
    messages = [r.getMessage() for r in caplog.records]
    assert re.fullmatch(r"inner: stopped after \d+\.\d\d s", messages[-2])
    assert re.fullmatch(r"outer: stopped after \d+\.\d\d s", messages[-1])
    assert progress._stack == []
    assert progress._redraw_stop is None


def test_stage_seconds_stop_when_the_stage_ends():
    with Progress(bars=False, log=False).stage("x") as stage:
        time.sleep(0.01)
    ended = stage.seconds
    time.sleep(0.02)
    assert stage.seconds == ended >= 0.01


# ------------------------------------------------------------------ bars
def test_bars_show_the_label_the_count_and_clear_themselves(monkeypatch):
    monkeypatch.setattr(progress_module, "MIN_INTERVAL", 0.0)
    out = io.StringIO()
    progress = Progress(bars=True, log=False, file=out)
    with progress.stage("plan: MPC over 4 points", total=3) as stage:
        for _ in range(3):
            stage.advance()
    with progress.stage("fit", unit="iteration") as stage:
        stage.advance(detail="loss 0.5")
    text = out.getvalue()
    assert "plan: MPC over 4 points:" in text
    assert "3/3" in text and "100%" in text
    assert "fit: iteration 1 [" in text and "loss 0.5" in text
    # leave=False: the last thing drawn is the cleared line.
    assert text.endswith("\r")
    assert progress._stack == []


def test_an_open_bar_keeps_its_clock_running_without_progress():
    out = io.StringIO()
    progress = Progress(bars=True, log=False, file=out)
    with progress.stage("a long item"):
        drawn = out.getvalue().count("\r")
        time.sleep(4 * progress_module.REDRAW)
        redrawn = out.getvalue().count("\r")
    assert redrawn > drawn, "the bar was not redrawn while nothing advanced"
    assert "[00:01" in out.getvalue()


def test_write_goes_above_the_bars():
    out = io.StringIO()
    progress = Progress(bars=True, log=False, file=out)
    with progress.stage("work"):
        progress.write("a line")
    assert "a line\n" in out.getvalue()
    plain = io.StringIO()
    Progress(bars=False, log=False, file=plain).write("a line")
    assert plain.getvalue() == "a line\n"


def test_a_progress_comes_back_silent_from_pickling():
    heard: list[str] = []
    copy = pickle.loads(pickle.dumps(Progress(callback=heard.append)))
    assert copy.silent
    with copy.stage("x"):
        pass
    assert heard == []


def test_auto_bars_follow_the_file_being_a_terminal():
    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    assert Progress(file=Terminal()).bars
    assert not Progress(file=io.StringIO()).bars


# ------------------------------------------------------------------ the library
def test_the_library_is_quiet_unless_asked(caplog, capsys):
    caplog.set_level(logging.INFO, logger=RECORDS)
    u = np.linspace(0.0, 1.0, 30)
    demos = [np.c_[u, 0.1 * np.sin(np.pi * u) + s] for s in (0.0, 0.01, -0.01)]
    skill = Skill().fit(demos)
    skill.plan(goal=[1.0, 0.05])
    assert capsys.readouterr() == ("", "")
    assert caplog.records == []
    Skill().fit(demos, progress=True)
    messages = [r.getMessage() for r in caplog.records]
    assert messages[0] == "mimic: Mean-Path of 3 demonstrations ..."
    assert any(m.startswith("imitate: DMP with") and " s" in m for m in messages)
    assert LOGGER.name == RECORDS


def test_kernels_compiled_reads_numbas_cache_index(tmp_path, monkeypatch) -> None:
    """False while no kernel module has a numba index file (a fresh install); True after."""
    from lfdkit.core.progress import KERNEL_MODULES, kernels_compiled

    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    for module in KERNEL_MODULES:
        source = tmp_path / module
        source.parent.mkdir(parents=True, exist_ok=True)
        source.write_text("")
        (source.parent / "__pycache__").mkdir(exist_ok=True)
        (source.parent / "__pycache__" / f"{source.stem}.py").write_text("")  # not an index
    assert not kernels_compiled(tmp_path)
    planner = tmp_path / "emulate/_planner_kernels.py"
    (planner.parent / "__pycache__" / f"{planner.stem}.grid_walk-164.py311.nbi").write_text("")
    assert kernels_compiled(tmp_path)
    elsewhere = tmp_path / "numba-cache"  # NUMBA_CACHE_DIR moves the cache
    elsewhere.mkdir()
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(elsewhere))
    assert not kernels_compiled(tmp_path)
    (elsewhere / "deep" / "emulate").mkdir(parents=True)
    (elsewhere / "deep" / "emulate" / f"{planner.stem}.k-1.py311.nbi").write_text("")
    assert kernels_compiled(tmp_path)
