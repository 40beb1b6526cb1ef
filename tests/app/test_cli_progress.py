"""What the ``lfdkit`` command shows while it works (lfdkit.app.cli, lfdkit.core.progress).

On a terminal every stage has a bar (a fake terminal here: a StringIO that
says it is one, so tqdm draws into it), ``--verbose`` adds a line per stage
with the command's clock and the stage's wall time, ``--quiet`` prints
nothing, and in a real pseudo-terminal the screen is never still for 2 s.
"""

from __future__ import annotations

import io
import os
import re
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import pytest

import lfdkit.app.evaluation
import lfdkit.core.progress
from lfdkit.app.cli import main
from lfdkit.tasks.sweeping import example_files

REPO = Path(__file__).resolve().parents[2]
GOAL = "0.36,0.5"
OBSTACLES = ["--obstacle", "cup:-0.02,0.47,r=0.03", "--obstacle", "marker:0.15,0.47"]
#: A ``--verbose`` line: the command's clock, an indent by depth, the stage's record.
LINE = re.compile(r"^\[ *\d+\.\d s\] ( *)(.*)$")
DONE = re.compile(r": done in \d+\.\d+ s$")
ANSI = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")


class FakeTerminal(io.StringIO):
    """Standard error as a terminal: the command draws its bars into it."""

    def isatty(self) -> bool:
        return True


def run_on(stream: io.StringIO, *argv: object) -> tuple[int, str, str]:
    """``main(argv)`` with ``stream`` as stderr: (exit code, stdout, what went to stderr)."""
    out = io.StringIO()
    saved = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = out, stream
    try:
        code = main([str(a) for a in argv])
    finally:
        sys.stdout, sys.stderr = saved
    return code, out.getvalue(), stream.getvalue()


def verbose_lines(text: str) -> list[tuple[int, str]]:
    """(depth, record) of each ``--verbose`` line in ``text`` (bars' redraws left out)."""
    found = []
    # Bars move the cursor (ANSI escapes) around the lines written above them.
    for line in re.split(r"[\r\n]", ANSI.sub("", text)):
        match = LINE.match(line)
        if match:
            found.append((len(match.group(1)) // 2, match.group(2)))
    return found


@pytest.fixture(scope="module")
def learned_on_a_terminal(tmp_path_factory):
    """``lfdkit learn -v`` of the example on a fake terminal, every count drawn and told."""
    files = example_files()
    path = tmp_path_factory.mktemp("skill") / "skill.json"
    with pytest.MonkeyPatch.context() as patch:
        # Draw every count and tell it (instead of 5 draws and a line every 2 s).
        patch.setattr(lfdkit.core.progress, "MIN_INTERVAL", 0.0)
        patch.setattr(lfdkit.core.progress, "HEARTBEAT", 0.0)
        code, out, err = run_on(
            FakeTerminal(),
            *("learn", files["demos"], "--scenes", files["scenes"], "-o", path, "-v"),
        )
    return SimpleNamespace(code=code, stdout=out, stderr=err, path=path)


# ------------------------------------------------------------------ learn
def test_learn_on_a_terminal_shows_a_bar_per_stage_and_the_ioc_iterations(learned_on_a_terminal):
    run = learned_on_a_terminal
    assert run.code == 0, run.stderr[-2000:]
    text = run.stderr
    for label in (
        "lfdkit learn [",  # the command's clock
        "mimic: Mean-Path of 5 demonstrations [",
        "imitate: DMP [",
        "emulate: inverse optimal control on 8 demos (full horizon, … [",  # shortened
        "IOC full horizon: run 3 of 3 (about ",  # the runs so far say how long the rest take
        "IOC MPC H=8: refining: iteration",
    ):
        assert label in text, label
    # The starting search: a bar with a percentage and a count.
    assert re.search(
        r"IOC: scoring (\d+) starting parameters \(plans only\): +100%\|.*\| (\d+)/\1", text
    )
    # L-BFGS iterations counted, with the loss beside them.
    counts = re.findall(
        r"IOC full horizon: run 1 of 3: iteration (\d+) \[[^\]]*loss [0-9.e+-]+",
        text,
    )
    assert counts and max(int(c) for c in counts) >= 5
    assert run.path.is_file()


def test_learn_verbose_lines_carry_the_clock_and_each_stages_wall_time(learned_on_a_terminal):
    lines = verbose_lines(learned_on_a_terminal.stderr)
    records = [record for _, record in lines]
    done = [record for record in records if DONE.search(record)]
    for label in (
        "read the demonstration and scene files",
        "mimic: Mean-Path of 5 demonstrations",
        "emulate: nominal of each obstacle demonstration (DMP)",
        "IOC: scoring 65 starting parameters (plans only)",
        "IOC full horizon: run 2 of 3",
        "IOC MPC H=8: refining",
        "IOC: identifiability (curvature of the loss)",
        "lfdkit learn",
    ):
        # A stage may carry a note after its label (the IOC runs: time left).
        assert any(r.startswith(label) and r.endswith(" ...") for r in records), label
        assert any(d.startswith(label) and ": done in " in d for d in done), label
    assert any(r.startswith("imitate: DMP with ") and DONE.search(r) for r in records)
    # How far the IOC came, within its stage (told every time here).
    assert any(re.match(r"IOC full horizon: run 1 of 3: iteration \d+, loss ", r) for r in records)
    # Nested stages are indented under their stage.
    depth = dict((record, d) for d, record in lines)
    assert depth["lfdkit learn ..."] == 0
    assert depth["emulate: nominal of each obstacle demonstration (DMP) ..."] == 1
    assert depth["IOC: scoring 65 starting parameters (plans only) ..."] == 2
    text = ANSI.sub("", learned_on_a_terminal.stderr)
    clocks = [float(m) for m in re.findall(r"^\[ *(\d+\.\d) s\]", text, re.M)]
    assert clocks == sorted(clocks)


def test_learn_verbose_in_a_log_file_has_lines_and_no_bars(tmp_path, monkeypatch):
    demos = tmp_path / "demos.csv"
    demos.write_text("demo,x,y\n1,0,0\n1,0.5,0.1\n1,1,0\n2,0,0\n2,0.5,0.05\n2,1,0\n")
    code, _, err = run_on(io.StringIO(), "learn", demos, "-o", tmp_path / "s.json", "-v")
    assert code == 0, err
    assert "\r" not in err and "%|" not in err
    records = [record for _, record in verbose_lines(err)]
    assert any(r.startswith("mimic: Mean-Path of 2 demonstrations: done in ") for r in records)
    # Last, or followed by the note on the assumed duration (untimed demonstrations).
    assert any(
        line.startswith("learned from 2 clean demonstrations") for line in err.splitlines()[-2:]
    )


# ------------------------------------------------------------------ plan
def test_plan_on_a_terminal_shows_the_mpc_steps(learned_on_a_terminal, tmp_path, monkeypatch):
    monkeypatch.setattr(lfdkit.core.progress, "MIN_INTERVAL", 0.0)
    skill = learned_on_a_terminal.path
    out = tmp_path / "path.csv"
    code, _, err = run_on(FakeTerminal(), "plan", skill, "--goal", GOAL, *OBSTACLES, "-o", out)
    assert code == 0, err
    assert re.search(r"plan: MPC H=8 over 100 points: +100%\|.*\| 99/99", err)
    assert "plan: the grid's cost-to-go (global route) [" in err
    assert "lfdkit plan [" in err
    # The summary is written above the bars, a whole line; then the bars are cleared.
    wrote = re.escape(f"; wrote {out}")
    assert re.search(rf"[\r\n]planned 100 points around 2 obstacles in [^\r\n]*{wrote}\n", err)
    assert err.endswith("\r")


def test_plan_verbose_lines_carry_times_and_quiet_says_nothing(
    learned_on_a_terminal, tmp_path, monkeypatch
):
    skill = learned_on_a_terminal.path
    code, _, err = run_on(
        io.StringIO(), "plan", skill, "--goal", GOAL, *OBSTACLES, "-o", tmp_path / "a.csv", "-v"
    )
    assert code == 0, err
    records = [record for _, record in verbose_lines(err)]
    assert any(re.match(r"plan: MPC H=8 over 100 points: done in \d+\.\d+ s$", r) for r in records)
    assert any(re.match(r"lfdkit plan: done in \d+\.\d+ s$", r) for r in records)
    for terminal in (io.StringIO(), FakeTerminal()):
        code, stdout, err = run_on(
            terminal,
            "plan",
            skill,
            "--goal",
            GOAL,
            *OBSTACLES,
            "-o",
            tmp_path / "q.csv",
            "-q",
            "-f",
        )
        assert code == 0
        assert (stdout, err) == ("", "")


@pytest.mark.slow
def test_compare_on_a_terminal_shows_a_bar_of_the_fits(tmp_path, monkeypatch):
    monkeypatch.setattr(lfdkit.core.progress, "MIN_INTERVAL", 0.0)  # draw every count
    # The smallest data set (every method fits it in 1.3 s of CPU, noisy_band in 3.3 s):
    # the bar counts the fits, whatever they fit.
    code, _, err = run_on(
        FakeTerminal(), "compare", "--datasets", "quasi_circular", "-o", tmp_path / "cmp", "-v"
    )
    assert code == 0, err
    text = ANSI.sub("", err)
    # One bar over every method's fit, counted, with the last fit's name.
    n_methods = len(lfdkit.app.evaluation.lfdkit_methods())
    label = f"{n_methods} methods on 1 data sets"
    assert re.search(rf"{label}.*{n_methods}/{n_methods}", text)
    records = [record for _, record in verbose_lines(err)]
    assert f"{label} ..." in records
    assert any(r.startswith(f"{label}: done in ") for r in records)


def test_building_the_parser_loads_nothing_heavy():
    # argparse lists an option's choices while adding it unless it has a metavar: the
    # mimic methods' would load scikit-learn (seconds) before any command could speak.
    import subprocess

    code = (
        "import sys, lfdkit.app.cli.entry as c; c._parser(); "
        "print(sorted(m for m in ('numpy', 'sklearn', 'numba', 'scipy') if m in sys.modules))"
    )
    env = {**os.environ, "PYTHONPATH": str(REPO / "src")}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert done.stdout.strip() == "[]", done.stderr


# ------------------------------------------------------------------ a real terminal
@pytest.mark.skipif(not hasattr(os, "openpty") or sys.platform == "win32", reason="needs a pty")
def test_learn_in_a_pseudo_terminal_is_never_still_for_two_seconds(tmp_path):
    import fcntl
    import pty
    import select
    import struct
    import termios

    files = example_files()
    argv = [
        sys.executable,
        "-m",
        "lfdkit.app.cli",
        *("learn", str(files["demos"]), "--scenes", str(files["scenes"])),
        *("-o", str(tmp_path / "skill.json")),
    ]
    env = {**os.environ, "PYTHONPATH": str(REPO / "src")}
    pid, fd = pty.fork()
    if pid == 0:  # pragma: no cover - the child
        os.execvpe(argv[0], argv, env)
    fcntl.ioctl(fd, termios.TIOCSWINSZ, struct.pack("HHHH", 40, 120, 0, 0))
    started = last = time.perf_counter()
    gaps, text = [], b""
    while True:
        ready, _, _ = select.select([fd], [], [], 0.05)
        if not ready:
            if time.perf_counter() - started > 600:
                os.kill(pid, 9)
                break
            continue
        try:
            data = os.read(fd, 65536)
        except OSError:  # the child closed the terminal
            break
        if not data:
            break
        now = time.perf_counter()
        gaps.append((now - last, last - started))
        last, text = now, text + data
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0, text[-2000:]
    final = text.decode(errors="replace")
    assert "learned from 5 clean demonstrations" in final
    # Up to the last line: after it the interpreter only shuts down.
    longest = max(gaps)
    assert longest[0] < 2.0, f"{longest[0]:.2f} s without output at {longest[1]:.1f} s"
    assert len(gaps) > 10


# ------------------------------------------------------------- first run (issue 31)
def test_a_first_run_says_the_kernels_compile_once(learned_on_a_terminal, tmp_path, monkeypatch):
    """With no numba cache the bar (and -v's log) says why it may sit at 'iteration 0'."""
    import lfdkit.app.cli.common

    skill = learned_on_a_terminal.path
    monkeypatch.setattr(lfdkit.app.cli.common, "kernels_compiled", lambda: False)
    monkeypatch.setenv("LFDKIT_KERNELS", "numpy")  # one plan with NumPy's kernels compiles none
    code, _, err = run_on(FakeTerminal(), "plan", skill, "-o", tmp_path / "n.csv")
    assert code == 0 and "compiling" not in err
    monkeypatch.setenv("LFDKIT_KERNELS", "numba")
    code, _, err = run_on(FakeTerminal(), "plan", skill, "-o", tmp_path / "a.csv")
    assert code == 0, err
    note = "compiling kernels once (about 60 s; cached afterwards)"
    assert "lfdkit plan: compiling kernels once" in err  # the command's bar (cut to the width)
    assert f"first run here: {note}" in err
    log = io.StringIO()  # a log file: the line at -v only, no bar
    code, _, err = run_on(log, "plan", skill, "-o", tmp_path / "b.csv", "-v")
    assert code == 0 and f"first run here: {note}" in err
    code, _, err = run_on(io.StringIO(), "plan", skill, "-o", tmp_path / "c.csv")
    assert code == 0 and "compiling" not in err  # default loudness in a log: unchanged
    monkeypatch.setattr(lfdkit.app.cli.common, "kernels_compiled", lambda: True)
    code, _, err = run_on(FakeTerminal(), "plan", skill, "-o", tmp_path / "d.csv")
    assert code == 0 and "compiling" not in err
