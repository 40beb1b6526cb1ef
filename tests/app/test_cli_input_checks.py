"""The command line on inputs a new user gets wrong: each said on one line with the fix."""

from __future__ import annotations

import types
import warnings

import numpy as np
import pytest

import lfdkit.skill
from lfdkit.io import save_demos, save_scenes
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill
from tests.app.test_cli import run_cli

_X = np.linspace(-400.0, 400.0, 40)
CLEAN = [np.c_[_X, 450.0 + dy + 30.0 * np.sin(np.linspace(0.0, np.pi, 40))] for dy in (0, 3, -4)]
AROUND = CLEAN[0] + np.c_[np.zeros(40), 60.0 * np.exp(-(_X**2) / (2 * 80.0**2))]


@pytest.fixture(scope="module")
def skill_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("input_checks") / "skill.json"
    Skill(units="mm").fit_path(CLEAN).save(path)
    return path


def test_plan_says_when_the_goal_is_in_another_unit(capsys, skill_file, tmp_path) -> None:
    code, _, err = run_cli(
        capsys, "plan", skill_file, "--goal", "0.4,0.45", "-o", tmp_path / "p.csv"
    )
    assert code == 0, err
    assert "lfdkit plan: warning: goal: (0.4, 0.45) mm lies far" in err
    assert "if that is its unit, pass --units m" in err
    code, _, err = run_cli(
        capsys, "plan", skill_file, "--goal", "400,450", "-o", tmp_path / "q.csv"
    )
    assert code == 0 and "warning" not in err, err


def test_plan_refuses_a_scene_file_of_several_scenes_naming_the_option(
    capsys, skill_file, tmp_path
) -> None:
    scenes = tmp_path / "scenes.csv"
    save_scenes(scenes, {"a": Scene((Obstacle("cup", [0, 440], radius=30),)), "b": Scene(())})
    code, _, err = run_cli(capsys, "plan", skill_file, "--goal", "400,450", "--scene", scenes)
    assert code == 1
    assert err.startswith(f"lfdkit plan: error: --scene {scenes}: holds 2 scenes")
    assert "--scene takes one: keep the rows of one demo, or leave out the demo column" in err


def test_learn_names_the_demonstration_that_starts_inside_its_obstacle(capsys, tmp_path) -> None:
    demos, scenes = tmp_path / "demos.csv", tmp_path / "scenes.csv"
    save_demos(demos, [*CLEAN, AROUND], ids=["free-1", "free-2", "free-3", "cup-1"])
    save_scenes(scenes, {"cup-1": Scene((Obstacle("cup", AROUND[0], radius=30.0),))})
    code, _, err = run_cli(
        capsys, "learn", demos, "--scenes", scenes, "--units", "mm", "-o", tmp_path / "s.json"
    )
    assert code == 1
    assert err.startswith(
        f"lfdkit learn: error: {scenes}: demo 'cup-1': obstacle 0 ('cup'): its demonstration "
        "starts 30 mm inside it"
    ), err
    assert not (tmp_path / "s.json").exists()


def test_learn_refuses_a_fit_that_did_not_converge_on_one_line_saying_what_would_help(
    capsys, tmp_path, monkeypatch
) -> None:
    def learn(*args, **kwargs):  # a fit that warns why, then does not converge
        warnings.warn(
            "not identified: P[cup][x]; show a demonstration with the cup nearer", stacklevel=2
        )
        info = {"converged": False, "convergence_message": "degenerate reward"}
        return types.SimpleNamespace(ioc_info_=info)

    monkeypatch.setattr(lfdkit.skill, "learn", learn)
    demos = tmp_path / "demos.csv"
    save_demos(demos, CLEAN)
    code, _, err = run_cli(capsys, "learn", demos, "--units", "mm", "-o", tmp_path / "s.json")
    assert code == 1
    assert len(err.splitlines()) == 1, err
    assert err.startswith(
        "lfdkit learn: error: the obstacle reward fit did not converge (degenerate reward); "
        "wrote nothing. Not identified: P[cup][x]; show a demonstration with the cup nearer. "
        "Check the units"
    ), err


def test_plot_says_when_the_demonstrations_drawn_are_in_another_unit(
    capsys, skill_file, tmp_path
) -> None:
    metres = tmp_path / "demos_m.csv"
    save_demos(metres, [d / 1000.0 for d in CLEAN])
    code, _, err = run_cli(capsys, "plot", skill_file, "--demos", metres, "-o", tmp_path / "a.png")
    assert code == 0, err
    assert f"lfdkit plot: warning: --demos {metres}: they lie far from the skill's path" in err
    assert "if that is their unit, pass --units m" in err
    millimetres = tmp_path / "demos_mm.csv"
    save_demos(millimetres, CLEAN)
    code, _, err = run_cli(
        capsys, "plot", skill_file, "--demos", millimetres, "-o", tmp_path / "b.png"
    )
    assert code == 0 and "warning" not in err, err


def test_plan_around_obstacles_without_a_reward_names_the_command_that_learns_one(
    capsys, skill_file
) -> None:
    code, _, err = run_cli(
        capsys, "plan", skill_file, "--goal", "400,450", "--obstacle", "cup:0,440,r=30"
    )
    assert code == 1
    assert "learn one with lfdkit learn --scenes (demonstrations around obstacles)" in err
    assert "fit_reward()" not in err
