"""Fuzzing the command line: random argument lists from the real options and junk values.

Whatever the arguments, ``lfdkit`` must end with exit code 0 (it worked), 1 (one
``lfdkit CMD: error:`` line) or 2 (argparse's usage error), never print a
traceback, finish in bounded time and write nothing outside its working folder.
Learning, the full demo, the comparison and the benchmarks are replaced by
cheap stand-ins (or only reached with failing inputs): the property is about
the command line, not about the methods.
"""

from __future__ import annotations

import io
import os
import tempfile
import time
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from lfdkit import skill as skill_module
from lfdkit.app.cli import main
from lfdkit.io.training import read_training_data
from lfdkit.skill import Skill
from lfdkit.tasks.sweeping import demo as sweeping_demo

REPO = Path(__file__).resolve().parents[2]
#: Seconds one command may take here (the stand-ins make every command cheap).
TIME_LIMIT = 30.0

_U = np.linspace(0.0, 1.0, 12)
_DEMOS = [np.c_[_U, 0.1 * np.sin(np.pi * _U) + dy] for dy in (0.0, 0.01, -0.01)]
DEMOS_CSV = "demo,x,y\n" + "".join(
    f"{j},{float(x)!r},{float(y)!r}\n" for j, d in enumerate(_DEMOS) for x, y in d
)
SCENE_CSV = "demo,class,x,y,radius\n0,cup,0.5,0.06,0.03\n"


@pytest.fixture(scope="module")
def skill_text(tmp_path_factory) -> str:
    path = tmp_path_factory.mktemp("fuzz") / "skill.json"
    Skill().fit(_DEMOS).save(path)
    return path.read_text()


def _fake_learn(demos_path, scenes_path=None, *, progress=None, **params):
    """``lfdkit.skill.learn`` without the learning: reads the files, checks the parameters."""
    data = read_training_data(demos_path, scenes_path)
    skill = Skill(**params)
    skill._validate_params()
    return skill.use_path(np.c_[_U, 0.1 * np.sin(np.pi * _U)], source=str(data.free_ids))


def _fake_run_into(out: Path, progress, started) -> dict:
    """The demo's work replaced by writing its files."""
    for path in sweeping_demo.demo_outputs(out):
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("stand-in\n")
    return {
        "emulate": {"test": {"improvement": 99.0}},
        "unseen": [{"planner": "learned reward", "collisions": 0}],
        "execution": {"summary": "stand-in"},
    }


# The real options of each command (those taking a value, then flags), and values.
VALUED = {
    "demo": ["-o", "--output"],
    "learn": ["--scenes", "--mimic", "--n-points", "--seed", "--planner", "--horizon", "--units"],
    "plan": [
        *["--start", "--goal", "--obstacle", "--scene", "--planner", "--horizon"],
        *["--goal-approach", "-o", "--duration", "--speed", "--units"],
    ],
    "plot": [
        "--start",
        "--goal",
        "--obstacle",
        "--scene",
        "--demos",
        "--title",
        "--dpi",
        "--units",
    ],
    "datasets": ["-o", "--scenes", "--seed"],
}
DATASET_WORDS = ["list", "export", "walking", "sweeping", "nosuch", "lasa:Angle", "lasa:x"]
FLAGS = ["-q", "-v", "-f", "--force", "--quiet", "--verbose", "--help"]
INPUTS = ["demos.csv", "skill.json", "scene.csv", "missing.csv", "empty.csv", "garbage.json"]
INPUTS += ["a\x00b", "dém😀.csv", "outdir", "blocker", "blocker/x.csv", ""]
OUTPUTS = ["new.json", "new.csv", "new.png", "out.csv", "outdir", "blocker/x.json"]
OUTPUTS += ["sub/new.json", "demo_out", "dém😀.json", "", "-", "a\x00b"]
VALUES = [
    *["", " ", "-", "--", "0", "-1", "3", "8", "100", "1e309", "nan", "inf", "-inf"],
    *["1e-320", "2147483648", "99999999999999999999", "100000000", "0.5", "a,b"],
    *["0.5,0.1", "0.2,0.05", "-0.4,0.45", "1,2,3", "1,2,3,4", "nan,1", "1e308,1e308"],
    *["1e300,0", "1e7,1e7", "cup:0.5,0.06", "cup:0.5,0.06,r=0.03", "cup:", ":1,2"],
    *["cup:1,2,r=-1", "cup:1,2,r=inf", "x" * 300, "full", "mpc", "gmr", "mean_path"],
    *["m", "cm", "mm", "inch"],
    *INPUTS,
    *OUTPUTS,
]


@st.composite
def argument_lists(draw) -> list[str]:
    command = draw(st.sampled_from([*VALUED, "compare", "bench"]))
    if command == "compare":  # only with a data set name that does not exist
        return ["compare", "--datasets", draw(st.sampled_from(["nosuch", "", "x" * 50]))]
    if command == "bench":
        return ["bench", draw(st.sampled_from(["nosuch", "..", "_common"]))]
    # Mostly well-formed (so the commands run and fail late), sometimes not.
    good_inputs = st.sampled_from(INPUTS[:2] * 6 + INPUTS)
    argv = [command]
    if command == "datasets":
        argv += draw(st.lists(st.sampled_from(DATASET_WORDS), max_size=2))
    if command == "learn":
        argv.append(draw(good_inputs))
    if command in ("plan", "plot"):
        argv.append(draw(st.sampled_from(["skill.json"] * 6 + INPUTS)))
    if command in ("learn", "plot") or draw(st.booleans()):
        argv += ["-o", draw(st.sampled_from(OUTPUTS))]
    options = st.sampled_from(VALUED[command])
    for option, value in draw(st.lists(st.tuples(options, st.sampled_from(VALUES)), max_size=4)):
        argv += [option, value]
    argv += draw(st.lists(st.sampled_from(FLAGS[:-1] * 4 + FLAGS[-1:]), max_size=2))
    if draw(st.integers(0, 9)) == 0:  # a stray token anywhere
        argv.insert(draw(st.integers(1, len(argv))), draw(st.sampled_from(VALUES)))
    return argv


def _snapshot(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")}


@settings(
    max_examples=100,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(argv=argument_lists())
def test_the_cli_never_shows_a_traceback(monkeypatch, skill_text, argv):
    monkeypatch.setattr(skill_module, "learn", _fake_learn)
    monkeypatch.setattr(sweeping_demo, "_run_into", _fake_run_into)
    repo_before = {p.name for p in REPO.iterdir()}
    with tempfile.TemporaryDirectory() as root:
        root = Path(root)
        work = root / "work"
        work.mkdir()
        (work / "demos.csv").write_text(DEMOS_CSV)
        (work / "skill.json").write_text(skill_text)
        (work / "scene.csv").write_text(SCENE_CSV)
        (work / "empty.csv").write_text("")
        (work / "garbage.json").write_text("{not json")
        (work / "out.csv").write_text("precious\n")
        (work / "blocker").write_text("a file, not a folder\n")
        (work / "outdir").mkdir()
        (root / "outside.txt").write_text("outside\n")
        inputs_before = {p: p.read_bytes() for p in work.iterdir() if p.is_file()}
        outside_before = _snapshot(root) - {f"work/{p}" for p in _snapshot(work)} - {"work"}

        monkeypatch.chdir(work)
        out, err = io.StringIO(), io.StringIO()
        started = time.perf_counter()
        with redirect_stdout(out), redirect_stderr(err):
            try:
                code = main(argv)
            except SystemExit as exc:  # argparse: --help (0) or a usage error (2)
                code = exc.code
        elapsed = time.perf_counter() - started
        monkeypatch.chdir(REPO)

        stderr = err.getvalue()
        event(f"exit {code}")
        assert code in (0, 1, 2), (argv, code, stderr)
        assert "Traceback" not in stderr or "-v" in argv or "--verbose" in argv, (argv, stderr)
        if code == 1:
            last = stderr.splitlines()[-1]
            assert last.startswith(f"lfdkit {argv[0]}: "), (argv, stderr)
            assert "error:" in last or "interrupted" in last
        assert elapsed < TIME_LIMIT, (argv, elapsed)
        # Nothing written outside the working folder; an existing file is only
        # replaced with --force.
        outside_after = _snapshot(root) - {f"work/{p}" for p in _snapshot(work)} - {"work"}
        assert outside_after == outside_before, (argv, outside_after ^ outside_before)
        forced = "-f" in argv or "--force" in argv
        for path, content in inputs_before.items():
            if not forced:
                assert path.read_bytes() == content, (argv, path)
    assert {p.name for p in REPO.iterdir()} == repo_before, argv


@pytest.mark.parametrize(
    "argv",
    [
        ["plot", "skill.json", "-o", "x.png", "--dpi", "100000000"],
        ["learn", "demos.csv", "-o", "s.json", "--seed", "-1"],
        ["learn", "demos.csv", "-o", "s.json", "--n-points", "1e3"],
    ],
    ids=["dpi", "seed", "n-points"],
)
def test_absurd_numbers_are_usage_errors(capsys, argv):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert f"argument {argv[-2]}" in err
    assert "Traceback" not in err


def test_write_outside_is_only_where_asked(monkeypatch, tmp_path, skill_text):
    # '-o ../x.csv' is the user's choice: written there, nowhere else.
    work = tmp_path / "work"
    work.mkdir()
    (work / "skill.json").write_text(skill_text)
    monkeypatch.chdir(work)
    with redirect_stdout(io.StringIO()), redirect_stderr(io.StringIO()):
        assert main(["plan", "skill.json", "-o", os.path.join("..", "x.csv")]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["work", "x.csv"]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["--goal", "1_0,0.5"],
            "argument --goal: expected numbers separated by commas, got "
            "'1_0,0.5' ('1_0' is not a number: digit separators ('_') are not allowed)",
        ),
        (["--goal", "0.5,nan"], "'nan' is not finite"),
        (
            ["--obstacle", "cup:0.1,0.45,r=0.03,r=0.05"],
            "argument --obstacle: r= is given twice in 'cup:0.1,0.45,r=0.03,r=0.05'; give it once",
        ),
        (
            ["--obstacle", "cup:0,0.7,r=0.03,vx=0,vx=1,vy=0"],
            "argument --obstacle: vx= is given twice in",
        ),
        (["--obstacle", "cup:0,0.7,r=0_3"], "argument --obstacle: radius in 'cup:0,0.7,r=0_3'"),
        (["--obstacle", "cup:0,0.7,q=3"], "argument --obstacle: unknown key q= in"),
        (["--horizon", "1_0"], "argument --horizon: '1_0' is not a whole number: digit separators"),
        (["--clearance", "1_0"], "argument --clearance: '1_0' is not a number: digit separators"),
    ],
    ids=["separator", "nan", "radius-twice", "vx-twice", "radius-separator", "key", "int", "float"],
)
def test_numbers_are_read_strictly_and_keys_once(capsys, argv, message):
    with pytest.raises(SystemExit) as exc:
        main(["plan", "skill.json", *argv])
    err = capsys.readouterr().err
    assert exc.value.code == 2
    assert message in err and "Traceback" not in err


def test_quiet_silences_progress_not_warnings(capsys):
    import argparse
    import warnings

    from lfdkit.app.cli.entry import _warnings_as_lines

    args = argparse.Namespace(verbosity=0)
    with _warnings_as_lines(args, "lfdkit learn"):
        warnings.warn("obstacle 'cup' is never near any demonstration", UserWarning, stacklevel=1)
    err = capsys.readouterr().err
    assert err == "lfdkit learn: warning: obstacle 'cup' is never near any demonstration\n"
