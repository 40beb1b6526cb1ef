"""``lfdkit learn`` says the learned slow return and a side preference's clearance.

The example skill's file (learned once a session) is edited to known values,
loaded, and handed to the command in place of a fit: the printed lines carry
those numbers in the skill's units; a file from before them prints as before.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from lfdkit.app.cli import main
from lfdkit.app.cli.learn import _fidelity_lines
from lfdkit.skill import Skill

SMALL_DEMOS = "demo,x,y\n1,0,0\n1,0.5,0.1\n1,1,0\n2,0,0\n2,0.5,0.05\n2,1,0\n"
SLOW = "path:window+demonstrated/return"  # asymmetric: planned in the path frame


def _edited(path: Path, *, new: bool) -> dict:
    """The example skill's document: the slow return chosen and a class kept on a side.

    ``new``: with the bound (0.18 of a step bound of slope 1.5, the
    demonstrations returning 0.12 times as steeply) and the side's clearance
    (0.024 m); otherwise as a file from before them.
    """
    document = json.loads(path.read_text())
    selection = document["ioc"]["model_selection"]
    assert SLOW in selection["candidates"]  # the example offers it (it returns slowly)
    document["params"]["max_slope"] = 1.5
    document["ioc"]["demonstrated_return"] = {"out": 1.0, "back": 0.27, "ratio": 0.12, "count": 8}
    side = {"side": "left", "within": 0.09}
    if new:
        selection["chosen"], selection["runner_up"] = SLOW, "window+demonstrated"
        selection["return_fraction"] = 0.18
        document["emulation"]["return_fraction"] = 0.18
        side["clearance"] = 0.024
    else:
        selection.pop("return_fraction", None)
        selection["candidates"].pop(SLOW)
        selection["chosen"], selection["runner_up"] = "window+demonstrated", "window"
    document["emulation"]["sides"] = {"cup": side}
    return document


def _learned(monkeypatch, capsys, tmp_path: Path, skill: Skill) -> list[str]:
    """What ``lfdkit learn`` prints with ``skill`` as its fit's result."""
    demos = tmp_path / "demos.csv"
    demos.write_text(SMALL_DEMOS)
    monkeypatch.setattr("lfdkit.skill.learn", lambda *args, **kwargs: skill)
    code = main(["learn", str(demos), "-o", str(tmp_path / "out.json")])
    err = capsys.readouterr().err
    assert code == 0, err
    return err.splitlines()


@pytest.fixture
def example_file(example_skill_file_once) -> Path:
    return Path(example_skill_file_once)


def test_learn_says_the_slow_return_and_the_sides_clearance(
    monkeypatch, capsys, tmp_path, example_file
) -> None:
    skill = Skill.from_dict(_edited(example_file, new=True), source="edited.json")
    assert skill.return_fraction_ == 0.18
    assert skill.side_preferences_["cup"]["clearance"] == 0.024
    lines = _learned(monkeypatch, capsys, tmp_path, skill)
    chosen = next(line for line in lines if line.startswith("obstacle behaviour planned with"))
    assert chosen.startswith(
        "obstacle behaviour planned with the thesis's MPC (each window's best), keeping the "
        "clearance the demonstrations kept, with a slow return, in the path frame "
        "(cross-validated Pr median"
    )
    assert (
        "; slow return: back at most 0.18 of the step bound (a slope of 0.27 m across per m "
        "along; the demonstrations return 0.12 times as steeply as they swerve); runner-up the "
        "thesis's MPC (each window's best), keeping the clearance the demonstrations kept ("
    ) in chosen
    assert (
        "plans keep the sides the demonstrations kept, the long way round where needed: "
        "every 'cup' on the left (within 0.09 m of the path, at least 0.024 m from it)"
    ) in lines
    # The file it wrote says the same. In millimetres the lengths are in millimetres (the
    # slope is a ratio; the fit's summary, with the demonstrations' ratio, is not carried).
    again = _fidelity_lines(Skill.load(tmp_path / "out.json"))
    assert again == _fidelity_lines(skill)
    mm = _fidelity_lines(skill.to_units("mm"))
    assert (
        "; slow return: back at most 0.18 of the step bound (a slope of 0.27 mm across per mm "
        "along); " in mm[0]
    )
    assert "every 'cup' on the left (within 90 mm of the path, at least 24 mm from it)" in mm[2]


def test_an_older_file_says_neither(monkeypatch, capsys, tmp_path, example_file) -> None:
    skill = Skill.from_dict(_edited(example_file, new=False), source="old.json")
    assert skill.return_fraction_ == 1.0
    assert "clearance" not in skill.side_preferences_["cup"]
    lines = _learned(monkeypatch, capsys, tmp_path, skill)
    text = "\n".join(lines)
    assert "slow return" not in text
    assert (
        "plans keep the sides the demonstrations kept, the long way round where needed: "
        "every 'cup' on the left (within 0.09 m of the path)"
    ) in lines
    # The runner-up may be the slow return, not chosen: named, its bound not said as the plans'.
    document = _edited(example_file, new=True)
    document["ioc"]["model_selection"]["chosen"] = "window+demonstrated"
    document["ioc"]["model_selection"]["runner_up"] = SLOW
    del document["emulation"]["return_fraction"]
    line = _fidelity_lines(Skill.from_dict(document, source="runner.json"))[0]
    assert (
        "; runner-up the thesis's MPC (each window's best), keeping the clearance the "
        "demonstrations kept, with a slow return, in the path frame (cross-validated Pr median"
    ) in line
    assert "slow return:" not in line
