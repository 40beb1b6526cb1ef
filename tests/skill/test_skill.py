"""The layered skill: learning from files, planning, composition, and the skill file."""

from __future__ import annotations

import json
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from lfdkit.core.geometry import arc_length, path_length, resample
from lfdkit.core.rotations import exp
from lfdkit.datasets import load_emulation_dataset
from lfdkit.emulate import Reward, metrics, plan_path
from lfdkit.imitate import SpeedProfile
from lfdkit.io import SKILL_VERSION, load_demos, save_demos
from lfdkit.io.scenes import load_scenes, save_scenes
from lfdkit.io.training import read_training_data
from lfdkit.mimic import DemoOrientationWarning
from lfdkit.model.demos import Demo
from lfdkit.model.motion import ConstantVelocity
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.model.timed_path import TimedPlan
from lfdkit.skill import Skill, learn
from lfdkit.tasks.sweeping import example_dataset, example_files

FILES = example_files()


@pytest.fixture(scope="module")
def skill() -> Skill:
    return learn(FILES["demos"], FILES["scenes"])


@pytest.fixture(scope="module")
def test_set() -> tuple[list[np.ndarray], list[Scene]]:
    demos, ids = load_demos(FILES["test_demos"], return_ids=True)
    scenes = load_scenes(FILES["test_scenes"])
    return demos, [scenes[key] for key in ids]


@pytest.fixture(scope="module")
def sweeping():
    return load_emulation_dataset("sweeping", seed=0)


# ------------------------------------------------------------------ learning
def test_training_data_splits_clean_and_obstacle_demonstrations() -> None:
    data = read_training_data(FILES["demos"], FILES["scenes"])
    assert data.free_ids == [f"free-{j}" for j in range(1, 6)]
    assert sorted(data.obstacle_ids) == sorted(
        [f"cup-{j}" for j in range(1, 5)] + [f"marker-{j}" for j in range(1, 5)]
    )
    assert [s.labels[0] for s in data.scenes] == [k.split("-")[0] for k in data.obstacle_ids]
    only_free = read_training_data(FILES["demos"])
    assert len(only_free.free_demos) == 13 and not only_free.obstacle_demos


def test_learned_skill_matches_the_demonstrator_on_held_out_sweeps(skill, test_set, sweeping):
    demos, scenes = test_set
    # The demonstrator follows the thesis's model (no goal term: a late swerve ends beside the
    # goal): scored with that model the plans match it; the executed plans, which return to
    # the goal over the last tenth of the path, lose a little at the end.
    scores = skill.evaluate(demos, scenes, goal_approach=None)
    truth = [
        plan_path(sweeping.true_reward, skill.nominal(d[0]), s, horizon=8, goal_approach=None)
        for d, s in zip(demos, scenes, strict=True)
    ]
    assert scores["improvement"] > 99.0
    assert scores["mse"] < 1.5 * metrics.mse_paths([t.points for t in truth], demos)
    assert skill.evaluate(demos, scenes)["improvement"] > 93.0
    assert set(skill.reward_.classes) == {"cup", "marker"}
    # The generalized path is the clean sweeps' Mean-Path: on average within 1 mm of the truth.
    assert metrics.e2(skill.path_, sweeping.nominal, n_points=100) / 100 < 1e-3


def test_the_file_path_and_the_in_memory_path_learn_the_same_skill(skill) -> None:
    data = example_dataset()
    direct = Skill().fit(
        data.free_demos,
        [data.demos[j] for j in data.train],
        [data.scenes[j] for j in data.train],
    )
    np.testing.assert_array_equal(direct.path_, skill.path_)
    assert direct.reward_.nominal_weight == skill.reward_.nominal_weight
    for label in ("cup", "marker"):
        np.testing.assert_array_equal(
            direct.reward_.precisions[label], skill.reward_.precisions[label]
        )


# ------------------------------------------------------------------ planning
def test_without_obstacles_the_plan_is_the_dmp_nominal(skill) -> None:
    goal = np.array([0.35, 0.5])
    plan = skill.plan(goal=goal)
    expected = resample(skill.nominal(goal=goal), skill.n_points)
    np.testing.assert_allclose(plan, expected, atol=1e-9)
    np.testing.assert_allclose(plan[-1], goal, atol=1e-9)
    np.testing.assert_allclose(plan[0], skill.path_[0], atol=1e-9)


def test_plan_avoids_both_classes_in_an_unseen_scene(skill) -> None:
    start, goal = np.array([-0.4, 0.45]), np.array([0.36, 0.5])
    scene = Scene.from_arrays(["cup", "marker"], [[-0.1, 0.47], [0.12, 0.46]], [0.03, 0.01])
    nominal = skill.nominal(start, goal)
    assert metrics.collisions(nominal, scene) > 0  # the DMP alone hits the cup
    for planner in ("mpc", "full"):
        plan = skill.plan(start, goal, scene, planner=planner)
        assert plan.shape == (100, 2)
        assert metrics.collisions(plan, scene) == 0
        np.testing.assert_allclose(plan[0], start, atol=1e-9)


def test_plan_is_deterministic(skill) -> None:
    scene = Scene.from_arrays(["cup"], [[0.0, 0.47]], [0.03])
    np.testing.assert_array_equal(skill.plan(scene=scene), skill.plan(scene=scene))


def test_gmr_mimic_gives_a_path_close_to_mean_path(skill) -> None:
    data = read_training_data(FILES["demos"])
    clean = data.free_demos[:5]
    gmr = Skill(mimic="gmr", n_components=6, random_state=0).fit_path(clean)
    assert gmr.path_.shape == (100, 2)
    assert metrics.e2(gmr.path_, skill.path_, n_points=100) / 100 < 2e-3
    assert gmr.mimic_info_["method"] == "gmr"


def test_a_class_learned_in_another_skill_is_reused(sweeping) -> None:
    train = list(sweeping.train)
    cup = [j for j in train if sweeping.scenes[j].labels[0] == "cup"]
    marker = [j for j in train if sweeping.scenes[j].labels[0] == "marker"]
    base = Skill(planner="full").fit_path(sweeping.free_demos)
    cup_skill = Skill(planner="full").fit_path(sweeping.free_demos)
    cup_skill.fit_reward([sweeping.demos[j] for j in cup], [sweeping.scenes[j] for j in cup])
    marker_skill = Skill(planner="full").fit_path(sweeping.free_demos)
    marker_skill.fit_reward(
        [sweeping.demos[j] for j in marker], [sweeping.scenes[j] for j in marker]
    )
    combined = base.adopt(cup_skill).adopt(marker_skill, ["marker"])
    assert combined.reward_.classes == ("cup", "marker")
    assert combined.reward_.nominal_weight == cup_skill.reward_.nominal_weight
    np.testing.assert_array_equal(
        combined.reward_.precisions["marker"], marker_skill.reward_.precisions["marker"]
    )
    mixed = sweeping.held_out_scenes[0]
    plan = combined.plan(scene=mixed)
    assert metrics.collisions(plan, mixed) == 0
    with pytest.raises(ValueError, match="'marker' was never learned"):
        cup_skill.plan(scene=mixed)
    with pytest.raises(ValueError, match="classes: 'bottle' is not learned"):
        base.adopt(cup_skill, ["bottle"])


# ------------------------------------------------------------------ files
@pytest.mark.parametrize("planner", ["mpc", "full"])
def test_skill_file_round_trip_plans_identically(skill, tmp_path: Path, planner: str) -> None:
    path = skill.save(tmp_path / "skill.json")
    loaded = Skill.load(path)
    assert loaded.get_params() == skill.get_params()
    np.testing.assert_array_equal(loaded.path_, skill.path_)
    assert loaded.reward_.nominal_weight == skill.reward_.nominal_weight
    scene = Scene.from_arrays(["cup", "marker"], [[-0.05, 0.47], [0.1, 0.44]], [0.03, 0.01])
    goal = [0.3, 0.52]
    np.testing.assert_array_equal(
        loaded.plan(goal=goal, scene=scene, planner=planner),
        skill.plan(goal=goal, scene=scene, planner=planner),
    )
    # Saving the loaded skill writes the same bytes (the file holds no time stamp).
    assert loaded.save(tmp_path / "again.json").read_bytes() == path.read_bytes()


def test_learning_twice_writes_byte_identical_skill_files(skill, tmp_path: Path) -> None:
    # the issue: skill.json recorded the wall-clock time and run times, so no two runs matched
    again = learn(FILES["demos"], FILES["scenes"])
    first = skill.save(tmp_path / "first.json").read_bytes()
    assert again.save(tmp_path / "second.json").read_bytes() == first
    assert b'"created"' not in first and b'"seconds"' not in first
    # the run times stay on the object, for reports
    assert skill.mimic_info_["seconds"] >= 0 and skill.ioc_info_["seconds"] > 0
    assert "seconds" in skill.ioc_info_["stages"][0]


def test_skill_without_reward_round_trips(tmp_path: Path) -> None:
    data = read_training_data(FILES["demos"])
    plain = Skill(planner="full").fit_path(data.free_demos[:5])
    loaded = Skill.load(plain.save(tmp_path / "plain.json"))
    assert loaded.reward_ is None
    np.testing.assert_array_equal(loaded.plan(goal=[0.3, 0.5]), plain.plan(goal=[0.3, 0.5]))


def test_save_refuses_to_overwrite_and_directories(skill, tmp_path: Path) -> None:
    target = tmp_path / "skill.json"
    target.write_text("keep")
    with pytest.raises(FileExistsError):
        skill.save(target)
    assert target.read_text() == "keep"
    skill.save(target, overwrite=True)
    assert Skill.load(target).n_dims_ == 2
    with pytest.raises(IsADirectoryError, match="is a directory"):
        skill.save(tmp_path)


def _edited(skill: Skill, tmp_path: Path, edit) -> Path:
    doc = skill.to_dict()
    edit(doc)
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(doc))
    return path


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d.update(version=SKILL_VERSION + 1), "newer lfdkit.*Upgrade"),
        (lambda d: d.update(format="something"), "not an lfdkit skill"),
        (lambda d: d.pop("path"), "path: missing field"),
        (lambda d: d.update(path=[[0.0, 1.0, 2.0]] * 5), r"path: expected shape n x 2"),
        (lambda d: d.update(n_dims="2"), "n_dims: expected int"),
        (lambda d: d["params"].update(horizon=40), "params: horizon"),
        (lambda d: d["params"].update(colour="red"), "params.colour: unknown parameter"),
        (lambda d: d["reward"].pop("nominal_weight"), "reward.nominal_weight: missing field"),
        (
            lambda d: d["reward"]["precisions"].update(cup=[[1.0, 0.0], [0.0, -1.0]]),
            "positive definite",
        ),
        (lambda d: d["reward"]["precisions"].update(cup=[[1.0, 0.0]]), r"precisions.cup"),
        (lambda d: d["params"].update(duration=1e300), r"params.duration: expected a value in "),
        (lambda d: d["params"].update(duration=0.0), r"params.duration: expected a value in "),
        (lambda d: d["params"].update(duration="1.0"), r"params.duration: expected a number"),
        (lambda d: d["params"].update(duration=True), r"params.duration: expected a number"),
        (lambda d: d["params"].update(n_basis=10_000), r"params.n_basis: expected 1 to 1000"),
        (lambda d: d["params"].update(n_basis=20.0), r"params.n_basis: expected an integer"),
        (lambda d: d["params"].update(n_points=10**6), r"params.n_points: expected 3 to 100000"),
        (lambda d: d["params"].update(n_components="10"), "params.n_components: expected an"),
        (lambda d: d["params"].update(max_slope=1e9), r"params.max_slope: expected a value"),
        (lambda d: d["params"].update(horizon=8.0), r"params.horizon: expected an integer"),
        (lambda d: d["params"].update(random_state="0"), "params.random_state: expected an"),
        (lambda d: d.update(n_dims=4), r"n_dims: expected 2 or 3, got 4"),
        (
            lambda d: d.update(path=[[0.0, 0.0]] * 100_001),
            r"path: has 100001 points; a skill file holds at most 100000",
        ),
        (
            lambda d: d["path"][3].__setitem__(1, "0.5"),
            r"path\[3\]\[1\]: expected a number, got a string",
        ),
        (lambda d: d["path"][0].__setitem__(0, False), r"path\[0\]\[0\]: expected a number"),
        (
            lambda d: d["params"].update(classes=["bowl"]),
            r"params.classes: \['bowl'\] contradicts the classes the reward learned",
        ),
        (
            lambda d: d["reward"]["precisions"].update(cup=[[1.0, "0"], [0.0, 1.0]]),
            r"reward.precisions.cup\[0\]\[1\]: expected a number",
        ),
    ],
)
def test_broken_skill_files_name_the_field(skill, tmp_path: Path, edit, message: str) -> None:
    path = _edited(skill, tmp_path, edit)
    with pytest.raises(ValueError, match=message) as info:
        Skill.load(path)
    assert str(info.value).startswith(str(path))


def test_non_json_and_non_finite_skill_files(skill, tmp_path: Path) -> None:
    path = tmp_path / "bad.json"
    path.write_text('{"format": "lfdkit-skill",\n "version": ')
    with pytest.raises(ValueError, match=r"bad.json: line 2: not valid JSON"):
        Skill.load(path)
    text = json.dumps(skill.to_dict()).replace('"nominal_weight": ', '"nominal_weight": NaN, "x": ')
    path.write_text(text)
    with pytest.raises(ValueError, match=r"bad.json: line 1, column \d+: NaN is not a JSON number"):
        Skill.load(path)
    with pytest.raises(FileNotFoundError):
        Skill.load(tmp_path / "missing.json")


def test_pickle_given_as_a_skill_file_names_the_file(skill, tmp_path: Path) -> None:
    import pickle

    path = tmp_path / "skill.json"
    path.write_bytes(pickle.dumps({"format": "lfdkit-skill"}))
    with pytest.raises(ValueError) as info:
        Skill.load(path)
    assert str(info.value) == (
        f"{path}: binary data, not text (a pickle, NumPy or other binary file?); this file "
        "type is read as UTF-8 text"
    )


def test_repeated_key_in_a_skill_file(skill, tmp_path: Path) -> None:
    text = skill.save(tmp_path / "skill.json").read_text()
    path = tmp_path / "dup.json"
    path.write_text(text.replace('"params": {', '"params": {\n  "n_basis": 5,', 1))
    with pytest.raises(ValueError) as info:
        Skill.load(path)
    assert str(info.value) == (
        f"{path}: params: key 'n_basis' appears more than once in one object; each key may "
        "be given once"
    )


@pytest.mark.parametrize("depth", [65, 100_000])
def test_deeply_nested_skill_file(tmp_path: Path, depth: int) -> None:
    path = tmp_path / "deep.json"
    path.write_text('{"format": "lfdkit-skill", "ioc": ' + "[" * depth + "]" * depth + "}")
    with pytest.raises(ValueError, match=r"deep.json: JSON nested too deep \(more than 64"):
        Skill.load(path)


def test_skill_file_over_the_size_cap(skill, tmp_path: Path, monkeypatch) -> None:
    import lfdkit.io.skill_file

    path = skill.save(tmp_path / "skill.json")
    monkeypatch.setattr(lfdkit.io.skill_file, "MAX_SKILL_FILE_BYTES", 1000)
    with pytest.raises(ValueError) as info:
        Skill.load(path)
    assert str(info.value) == (
        f"{path}: file too large ({path.stat().st_size} bytes); lfdkit reads files of at most "
        "1000 bytes (0.000953674 MiB)"
    )


# ------------------------------------------------------------------ errors
def test_plan_errors(skill) -> None:
    with pytest.raises(ValueError, match="'bottle' was never learned"):
        skill.plan(scene=Scene.from_arrays(["bottle"], [[0.0, 0.45]]))
    with pytest.raises(ValueError, match="horizon"):
        skill.plan(scene=Scene.from_arrays(["cup"], [[0.0, 0.47]]), horizon=20)
    with pytest.raises(ValueError, match="goal: expected a 2-D point"):
        skill.plan(goal=[1.0, 2.0, 3.0])
    for goal in (["0.36", "0.5"], [True, False], np.array([1, 0], dtype=bool)):
        with pytest.raises(ValueError, match="goal: expected 2 numbers, got strings or booleans"):
            skill.plan(goal=goal)
    with pytest.raises(ValueError, match="start: contains NaN"):
        skill.plan(start=[np.nan, 0.0])
    with pytest.raises(ValueError, match="goal: coincides with start"):
        skill.plan(start=[0.0, 0.0], goal=[0.0, 0.0])
    # A negative tool clearance, with obstacles or without (it was taken without any).
    for scene in (None, Scene.from_arrays(["cup"], [[0.0, 0.47]])):
        with pytest.raises(ValueError, match=r"^clearance: must be >= 0, got -0.01"):
            skill.plan(scene=scene, clearance=-0.01)
    with pytest.raises(ValueError, match="inside"):
        skill.plan(scene=Scene.from_arrays(["cup"], [[-0.39, 0.45]], [0.03]))
    with pytest.raises(ValueError, match="not fitted"):
        Skill().plan()
    plain = Skill().fit_path(read_training_data(FILES["demos"]).free_demos[:5])
    with pytest.raises(ValueError, match="no obstacle reward"):
        plain.plan(scene=Scene.from_arrays(["cup"], [[0.0, 0.47]]))


@pytest.mark.parametrize("units", ["m", "mm"])
def test_an_unlearned_class_is_planned_around_only_when_asked(skill, units) -> None:
    scale = {"m": 1.0, "mm": 1000.0}[units]
    learned = skill if units == "m" else skill.to_units(units)
    start, goal = scale * np.array([-0.4, 0.45]), scale * np.array([0.36, 0.5])
    bottle = Scene.from_arrays(["bottle"], [scale * np.array([-0.05, 0.47])], [0.03 * scale])
    # Without the opt-in: refused, the error naming it.
    with pytest.raises(ValueError, match=r"'bottle' was never learned.*unknown_class=MARGIN"):
        learned.plan(start, goal, bottle)
    nominal = learned.nominal(start, goal)
    for margin in (0.0, 0.02 * scale, 0.05 * scale):
        # The plan must swerve: the nominal passes inside radius plus margin.
        assert bottle.distances(nominal).min() < margin
        with pytest.warns(UserWarning) as caught:
            plan = learned.plan(start, goal, bottle, unknown_class=margin)
        text = str(caught[0].message)
        assert "class 'bottle' never learned: planned around it (1 obstacle)" in text
        assert f"margin {margin:g} {units}" in text and "no learned response" in text
        assert bottle.distances(plan.points).min() >= margin - 1e-9 * scale
        assert plan.details.clearance[0] >= 0.0
        np.testing.assert_allclose(plan.points[[0, -1]], [start, goal], atol=1e-9 * scale)
    # A learned class beside it keeps its learned response: the plan still clears both.
    mixed = Scene.from_arrays(
        ["bottle", "cup", "bottle"],
        scale * np.array([[-0.1, 0.47], [0.15, 0.46], [0.25, 0.6]]),
        scale * np.array([0.02, 0.03, 0.01]),
    )
    with pytest.warns(UserWarning, match=r"'bottle' never learned: planned around them \(2 obst"):
        plan = learned.plan(start, goal, mixed, unknown_class=0.01 * scale)
    gaps = mixed.distances(plan.points)  # to each obstacle's surface
    assert gaps[1] >= 0.0
    assert gaps[[0, 2]].min() >= 0.01 * scale - 1e-9 * scale
    with pytest.raises(ValueError, match="unknown_class: must be >= 0"):
        learned.plan(scene=bottle, unknown_class=-1.0)
    point = Scene.from_arrays(["bottle"], [scale * np.array([0.0, 0.47])])
    with pytest.raises(ValueError, match=r"unknown_class: obstacle 0 .* give a positive margin"):
        learned.plan(scene=point, unknown_class=0.0)


def test_an_unlearned_class_takes_the_response_of_the_learned_class_nearest_in_size(
    skill, tmp_path
) -> None:
    # The example's training scenes hold 3 cm cups and 1 cm markers.
    assert skill.class_radii_ == pytest.approx({"cup": 0.03, "marker": 0.01})
    skill.save(tmp_path / "skill.json")
    assert Skill.load(tmp_path / "skill.json").class_radii_ == skill.class_radii_
    assert skill.to_units("mm").class_radii_ == pytest.approx({"cup": 30.0, "marker": 10.0})
    document = skill.to_dict()
    document["emulation"]["radii"] = {"cup": "big"}
    with pytest.raises(ValueError, match=r"f.json: emulation.radii.cup: expected a number"):
        Skill.from_dict(document, source="f.json")
    del document["emulation"]["radii"]  # a file from before them: no sizes, plans as before
    assert Skill.from_dict(document).class_radii_ == {}
    start, goal = np.array([-0.4, 0.45]), np.array([0.36, 0.5])
    pen = Scene.from_arrays(["pen"], [[-0.05, 0.47]], [0.008])  # nearest a marker in size
    plans = {}
    for response in (None, "nearest", "marker"):
        with pytest.warns(UserWarning) as caught:
            plans[response] = skill.plan(
                start, goal, pen, unknown_class=0.01, unknown_response=response
            )
        text = str(caught[0].message)
        if response is None:
            assert "no learned response" in text
        else:
            assert "'pen' takes the learned response of 'marker' (radius 0.008 m" in text
    np.testing.assert_array_equal(plans["nearest"].points, plans["marker"].points)
    # The marker's learned response swerves wider than the bare hard radius.
    gaps = {key: pen.distances(plan.points)[0] for key, plan in plans.items()}
    assert gaps[None] >= 0.01 - 1e-9
    assert gaps["marker"] > gaps[None] + 0.01
    bottle = Scene.from_arrays(["bottle"], [[-0.05, 0.47]], [0.03])
    with pytest.warns(UserWarning, match="'bottle' takes the learned response of 'cup'"):
        skill.plan(start, goal, bottle, unknown_class=0.01, unknown_response="nearest")
    with pytest.raises(ValueError, match=r"unknown_response: 'bowl' is not a learned class"):
        skill.plan(start, goal, bottle, unknown_class=0.01, unknown_response="bowl")
    # Without the sizes (a reward adopted), "nearest" cannot choose: it says so.
    adopted = Skill().fit_path(read_training_data(FILES["demos"]).free_demos[:5])
    adopted.adopt(skill.reward_)
    with pytest.raises(ValueError, match=r"'nearest' needs the sizes.*\(cup, marker\)"):
        adopted.plan(scene=bottle, unknown_class=0.01, unknown_response="nearest")


def test_a_moving_unlearned_obstacle_is_kept_out_of_at_the_plans_own_times(skill) -> None:
    from lfdkit.emulate.planner import moving_clearance

    start, goal = np.array([-0.4, 0.45]), np.array([0.36, 0.5])
    crossing = Obstacle("bottle", [0.0, 0.3], 0.02, motion=ConstantVelocity([0.0, 0.1]))
    scene = Scene((crossing,))
    with pytest.raises(ValueError, match="'bottle' was never learned"):
        skill.plan(start, goal, scene, duration=4.0)
    with pytest.warns(UserWarning, match="'bottle' never learned"):
        plan = skill.plan(start, goal, scene, duration=4.0, clearance=0.005, unknown_class=0.02)
    gaps = moving_clearance(plan.points, plan.times, scene, 0.025, 0.0)
    assert gaps.min() >= -1e-9
    # Unplanned for, the nominal at the same times passes inside radius + 25 mm.
    nominal = resample(skill.nominal(start, goal), skill.n_points)
    assert moving_clearance(nominal, skill.point_times(4.0), scene, 0.025, 0.0).min() < 0.0


def test_a_skill_without_reward_plans_around_obstacles_only_when_asked() -> None:
    plain = Skill().fit_path(read_training_data(FILES["demos"]).free_demos[:5])
    cup = Scene.from_arrays(["cup"], [[0.0, 0.47]], [0.02])
    with pytest.raises(ValueError, match=r"no obstacle reward.*unknown_class=MARGIN"):
        plain.plan(scene=cup)
    assert cup.distances(plain.plan().points).min() < 0.01  # the nominal passes through it
    with pytest.warns(UserWarning, match="'cup' never learned"):
        plan = plain.plan(scene=cup, unknown_class=0.01)
    assert cup.distances(plan.points).min() >= 0.01 - 1e-12


def test_fit_errors(sweeping) -> None:
    free = sweeping.free_demos
    with pytest.raises(ValueError, match="scenes: give obstacle_demos and scenes together"):
        Skill().fit(free, sweeping.demos[:2])
    with pytest.raises(ValueError, match="scenes: 1 scenes for 2 obstacle demonstrations"):
        Skill(planner="full").fit(free, sweeping.demos[:2], sweeping.scenes[:1])
    with pytest.raises(ValueError, match="demos: "):
        Skill().fit(free[:1])
    with pytest.raises(ValueError, match="mimic: expected one of"):
        Skill(mimic="dtw").fit(free)
    with pytest.raises(ValueError, match="horizon: expected 4 <= H <= 12"):
        Skill(horizon=3).fit(free)
    with pytest.raises(ValueError, match="contains NaN"):
        Skill().fit([free[0], np.full_like(free[1], np.nan)])
    with pytest.raises(ValueError, match="not fitted"):
        Skill().fit_reward(sweeping.demos[:1], sweeping.scenes[:1])
    with pytest.raises(ValueError, match="2-D obstacles for 3-D"):
        three_d = [np.column_stack([d, np.zeros(len(d))]) for d in free]
        Skill().fit_path(three_d).fit_reward(
            [np.column_stack([sweeping.demos[0], np.zeros(len(sweeping.demos[0]))])],
            sweeping.scenes[:1],
        )
    with pytest.raises(ValueError, match="no learned obstacle reward"):
        Skill().adopt(Skill())


def test_training_file_errors(tmp_path: Path) -> None:
    demos, ids = load_demos(FILES["demos"], return_ids=True)
    scenes = load_scenes(FILES["scenes"])
    stray = tmp_path / "stray.csv"
    save_scenes(stray, {**scenes, "cup-99": scenes["cup-1"]})
    with pytest.raises(ValueError, match=r"stray.csv: demo 'cup-99' is not in .*demos.csv"):
        read_training_data(FILES["demos"], stray)
    few = tmp_path / "few.csv"
    save_demos(few, demos[:1] + demos[5:7], ids=ids[:1] + ids[5:7])
    few_scenes = tmp_path / "few_scenes.csv"
    save_scenes(few_scenes, {key: scenes[key] for key in ids[5:7]})
    with pytest.raises(ValueError, match=r"few\.csv: needs at least 2 demonstrations without"):
        read_training_data(few, few_scenes)


def test_learning_with_a_moving_obstacle_is_refused_at_the_edge(sweeping, tmp_path) -> None:
    """Issue 27: it failed inside the planner, about ``times``; the IOC has no time model."""
    moving = [
        Scene(tuple(replace(o, motion=ConstantVelocity([0.02, 0.0])) for o in scene))
        for scene in sweeping.scenes[:2]
    ]
    with pytest.raises(ValueError, match=r"^scenes\[0\]: obstacle 0 \('cup'\) moves; the rew"):
        Skill().fit(sweeping.free_demos, sweeping.demos[:2], moving)
    scenes = load_scenes(FILES["scenes"])
    first = next(iter(scenes))
    scenes[first] = Scene(
        tuple(replace(o, motion=ConstantVelocity([0.0, 0.05])) for o in scenes[first])
    )
    save_scenes(tmp_path / "moving.json", scenes)
    message = rf"moving\.json: demo {first!r}: obstacle 0 \('cup'\) moves; the reward is lear"
    with pytest.raises(ValueError, match=message):
        learn(FILES["demos"], tmp_path / "moving.json")


def test_obstacles_far_from_every_demonstration_are_said_and_learning_goes_on(sweeping) -> None:
    """Issue 27: obstacles 10 m away: the fit failed replanning scenes of classes not learned."""
    far = [Scene(tuple(o.translated([10.0, 10.0]) for o in s)) for s in sweeping.scenes]
    with pytest.warns(UserWarning) as caught:
        skill = Skill().fit(sweeping.free_demos, sweeping.demos, far)
    said = [str(w.message) for w in caught]
    for label in ("cup", "marker"):
        assert any(
            m.startswith(f"obstacle {label!r} is never near any demonstration (the nearest")
            and "its class cannot be learned" in m
            for m in said
        ), said
    assert skill.reward_.classes == ()
    assert skill.ioc_info_["not_learned"] == ["cup", "marker"]
    with pytest.raises(ValueError, match="'cup' was never learned"):
        skill.plan(scene=Scene((Obstacle("cup", [0.0, 0.45], 0.03),)))


def test_reward_from_another_dimension_is_refused() -> None:
    free = read_training_data(FILES["demos"]).free_demos[:5]
    reward3 = Reward(10.0, {"cup": [1.0, 2.0, 3.0]})
    with pytest.raises(ValueError, match="3-D reward for a 2-D skill"):
        Skill().fit_path(free).adopt(reward3)


def test_skill_records_how_the_reward_fit_went(skill, tmp_path: Path) -> None:
    info = skill.ioc_info_
    assert info["converged"] is True
    assert info["convergence_message"] == "converged"
    assert info["not_learned"] == []
    names = {"Q", "P[cup][x]", "P[cup][y]", "P[marker][x]", "P[marker][y]"}
    assert set(info["identifiability"]) == names
    for entry in info["identifiability"].values():
        assert set(entry) == {"curvature", "relative_error", "identified"}
    loaded = Skill.load(skill.save(tmp_path / "skill.json"))
    assert loaded.ioc_info_["identifiability"] == json.loads(json.dumps(info["identifiability"]))


@pytest.mark.parametrize(
    ("params", "message"),
    [
        ({"n_basis": 10**4}, "n_basis: expected 1 to 1,000, got 10,000"),
        ({"duration": 1e300}, "duration: expected 0 < duration <= 1e+06, got 1e+300"),
        ({"n_points": 10**6}, "n_points: expected 3 to 100,000"),
        ({"n_components": 5000}, "n_components: expected 1 to 1,000"),
        ({"max_slope": 1e9}, "max_slope: expected 0 < max_slope <= 1e+06"),
        ({"duration": "soon"}, "duration: expected a number or 'auto', got 'soon'"),
        ({"classes": "cup"}, "classes: expected a list of class names, got 'cup'"),
    ],
)
def test_a_skill_built_in_code_is_bounded_as_a_skill_file_is(params, message) -> None:
    # What the constructor accepts, a skill file can hold (and load back).
    with pytest.raises(ValueError, match=re.escape(message)):
        Skill(**params)._validate_params()


def test_a_mimic_warning_is_passed_on_and_kept_in_the_skill_file(tmp_path, monkeypatch) -> None:
    from lfdkit.mimic import PathLengthWarning, orientation

    # Any path is "too short" against a band of 1.5-2 times the median.
    monkeypatch.setattr(orientation, "LENGTH_WARNING_RANGE", (1.5, 2.0))
    x = np.linspace(0.0, 1.0, 40)
    demos = [np.column_stack((x, 0.2 * np.sin(3 * x) + dy)) for dy in (-0.01, 0.0, 0.01)]
    with pytest.warns(PathLengthWarning, match="times the median demonstration length"):
        skill = Skill().fit_path(demos)
    assert skill.mimic_info_["length_ratio"] == pytest.approx(1.0, abs=0.02)
    [text] = skill.mimic_info_["warnings"]
    assert "stops short" in text
    saved = skill.save(tmp_path / "skill.json")
    assert Skill.load(saved).mimic_info_["warnings"] == [text]


@pytest.mark.parametrize("scaling", ["translate", "spatial"])
def test_a_closed_skill_plans_from_a_point_back_to_it(scaling) -> None:
    # An open skill asked to go nowhere is refused (test_plan_errors); a closed one is not.
    t = np.linspace(0.0, 2.0 * np.pi, 100)
    circle = np.column_stack((np.cos(t), np.sin(t)))
    circle[-1] = circle[0]
    skill = Skill(scaling=scaling).use_path(circle)
    here = np.array([1.1, 0.1])
    plan = skill.plan(start=here, goal=here)
    np.testing.assert_allclose(plan[[0, -1]], [here, here], atol=1e-9)
    # The loop is carried there whole, not collapsed.
    assert np.ptp(plan, axis=0).min() == pytest.approx(2.0, abs=0.02)


# ------------------------------------------------------------------ timing
def timed_free_demos(
    seed: int = 0, jitter: float = 0.002
) -> tuple[list[np.ndarray], list[np.ndarray], list[float]]:
    """The example's clean sweeps with times: minimum jerk over 4.0 to 5.2 s, 2 ms jitter."""
    rng = np.random.default_rng(seed)
    demos = read_training_data(FILES["demos"], FILES["scenes"]).free_demos
    law = SpeedProfile.minimum_jerk()
    durations = [4.0 + 0.3 * j for j in range(len(demos))]
    times = []
    for demo, duration in zip(demos, durations, strict=True):
        fraction = arc_length(demo) / path_length(demo)
        t = duration * law.phase(fraction) + rng.normal(0.0, jitter, len(demo))
        t[0], t[-1] = 0.0, duration
        times.append(np.maximum.accumulate(t) + 1e-7 * np.arange(len(t)))
    return demos, times, durations


@pytest.fixture(scope="module")
def timed(skill) -> Skill:
    """The example skill with times: its timing learned, the reward adopted from ``skill``."""
    demos, times, _ = timed_free_demos()
    return Skill().fit_path(demos, times=times).adopt(skill)


def speeds_between(times: np.ndarray, points: np.ndarray) -> np.ndarray:
    return np.linalg.norm(np.diff(points, axis=0), axis=1) / np.diff(times)


def test_the_timing_is_learned_from_the_demonstrations_times(timed) -> None:
    _, _, durations = timed_free_demos()
    timing = timed.timing_
    assert timing.source == "demonstrations"
    assert timing.duration == pytest.approx(np.median(durations), abs=1e-5)
    u = np.linspace(0.0, 1.0, 501)
    truth = SpeedProfile.minimum_jerk()
    assert np.max(np.abs(timing.speed(u) - truth.speed(u))) < 0.05 * truth.peak_speed
    # The DMP runs over the learned duration, and so does a plan.
    assert timed.dmp_.duration_ == pytest.approx(timing.duration)
    plan = timed.plan()
    assert plan.times[0] == 0.0 and plan.duration == pytest.approx(timing.duration)
    np.testing.assert_allclose(plan.velocities[[0, -1]], 0.0, atol=1e-12)
    # Without obstacles the plan's speed is the learned profile over the nominal's length.
    expected = path_length(plan.points) * timing.speed(plan.times / plan.duration) / plan.duration
    np.testing.assert_allclose(plan.speeds, expected, rtol=1e-9, atol=1e-12)
    # Without times: the skill's law (minimum jerk) over its duration parameter.
    plain = Skill(duration=2.0).fit_path(timed_free_demos()[0])
    assert plain.timing_ == SpeedProfile.minimum_jerk(2.0)
    assert plain.plan().duration == 2.0


def test_a_timed_plan_stands_for_its_points(timed) -> None:
    plan = timed.plan(goal=[0.35, 0.5])
    points = plan.points
    assert isinstance(plan, TimedPlan)
    assert plan.times.shape == (100,) and plan.velocities.shape == points.shape == (100, 2)
    assert plan.positions is points
    # What code written for the ndarray plan did still works.
    assert np.asarray(plan) is points
    assert plan.shape == (100, 2) and plan.ndim == 2 and len(plan) == 100
    np.testing.assert_array_equal(plan[-1], points[-1])
    np.testing.assert_array_equal(plan[:, 0], points[:, 0])
    assert (plan == timed.plan(goal=[0.35, 0.5])).all()
    np.testing.assert_array_equal(plan - points[0], points - points[0])
    np.testing.assert_array_equal(2.0 * plan, 2.0 * points)
    assert [tuple(p) for p in plan] == [tuple(p) for p in points]
    assert np.array(plan) is not points and np.array_equal(np.array(plan), points)
    with pytest.raises(TypeError):
        plan += 1.0  # immutable
    assert "100 points in 2-D" in repr(plan)
    # The planner's details come along.
    assert plan.details.goal_error < 1e-6 and np.shares_memory(plan.details.points, points)
    assert not points.flags.writeable  # a read-only view of the planner's, not a copy


def test_duration_and_speed_rescale_the_plan(timed) -> None:
    scene = Scene.from_arrays(["cup"], [[0.0, 0.47]], [0.03])
    plan = timed.plan(scene=scene)
    slow = timed.plan(scene=scene, duration=2 * plan.duration)
    fast = timed.plan(scene=scene, speed=4.0)
    np.testing.assert_array_equal(slow.points, plan.points)
    np.testing.assert_allclose(slow.times, 2.0 * plan.times, rtol=1e-12)
    np.testing.assert_allclose(slow.velocities, 0.5 * plan.velocities, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(fast.times, 0.25 * plan.times, rtol=1e-12)
    assert fast.duration == pytest.approx(timed.timing_.duration / 4.0)
    for bad, message in (
        ({"duration": -1.0}, "duration: must be > 0"),
        ({"duration": np.nan}, "duration: must be finite"),
        ({"speed": 0.0}, "speed: must be > 0"),
        ({"speed": 1e-12}, "speed: the plan would last"),
        ({"duration": 1.0, "speed": 2.0}, "speed: give duration or speed, not both"),
    ):
        with pytest.raises(ValueError, match=message):
            timed.plan(scene=scene, **bad)


def test_a_swerving_plan_is_retimed_without_speed_spikes(timed) -> None:
    # A large cup in the middle of the sweep, where it is fastest: the plan swerves
    # and is longer than the nominal. Timed along its own length it runs a little
    # faster everywhere; keeping the nominal's time for each point (the naive timing)
    # crosses the swerve's long steps in the nominal's short time steps.
    demos, times, _ = timed_free_demos(jitter=0.0)  # their true speeds
    duration = timed.timing_.duration
    # The demonstrations' peak speed, each rescaled to the plan's duration.
    peaks = [
        np.max(speeds_between(t, d)) * (t[-1] - t[0]) / duration
        for d, t in zip(demos, times, strict=True)
    ]
    reference = float(np.median(peaks))
    plan = timed.plan(scene=Scene.from_arrays(["cup"], [[0.0, 0.455]], [0.08]))
    length_ratio = path_length(plan.points) / path_length(timed.plan().points)
    assert length_ratio > 1.05  # it swerves
    ratio = float(np.max(speeds_between(plan.times, plan.points))) / reference
    assert np.max(plan.speeds) / reference < 1.15
    assert ratio < 1.15
    assert ratio == pytest.approx(length_ratio, abs=0.03)
    naive = duration * timed.timing_.phase(np.linspace(0.0, 1.0, len(plan)))
    assert np.max(speeds_between(naive, plan.points)) / reference > 1.2


def test_learned_timing_round_trips_through_the_skill_file(timed, skill, tmp_path) -> None:
    path = timed.save(tmp_path / "timed.json")
    document = json.loads(path.read_text())
    assert document["timing"]["source"] == "demonstrations"
    assert len(document["timing"]["demo_durations"]) == 5
    loaded = Skill.load(path)
    assert loaded.timing_ == timed.timing_
    scene = Scene.from_arrays(["cup"], [[0.0, 0.47]], [0.03])
    again, before = loaded.plan(scene=scene), timed.plan(scene=scene)
    for name in ("times", "points", "velocities"):
        np.testing.assert_array_equal(getattr(again, name), getattr(before, name))
    assert loaded.save(tmp_path / "again.json").read_bytes() == path.read_bytes()
    # A skill without times writes no timing field: its files are as before.
    assert "timing" not in json.loads(skill.save(tmp_path / "plain.json").read_text())
    # A broken timing field is refused, naming the file and the field.
    document["timing"]["duration"] = -2.0
    broken = tmp_path / "broken.json"
    broken.write_text(json.dumps(document))
    with pytest.raises(ValueError, match=r"broken\.json: timing\.duration: must be > 0"):
        Skill.load(broken)


def test_times_of_a_reversed_demonstration_are_turned_round_too() -> None:
    demos, times, durations = timed_free_demos()
    demos = [demos[0][::-1], *demos[1:]]
    times = [durations[0] - times[0][::-1], *times[1:]]
    with pytest.warns(DemoOrientationWarning, match="reversed demonstration"):
        skill = Skill().fit_path(demos, times=times)
    assert skill.mimic_info_["reversed"] == [0]
    assert skill.timing_.demo_durations == pytest.approx(durations, abs=1e-5)
    u = np.linspace(0.0, 1.0, 501)
    assert np.max(np.abs(skill.timing_.speed(u) - SpeedProfile.minimum_jerk().speed(u))) < 0.06


def test_bad_times_are_refused_naming_them() -> None:
    demos, times, _ = timed_free_demos()
    nan = [t.copy() for t in times]
    nan[2][7] = np.nan
    with pytest.raises(ValueError, match=r"times\[2\]: contains NaN or infinite values"):
        Skill().fit_path(demos, times=nan)
    with pytest.raises(ValueError, match=r"times\[1\]: must increase strictly"):
        Skill().fit_path(demos, times=[times[0], times[1][::-1], *times[2:]])
    with pytest.raises(ValueError, match="times: got 2 entries for 5 demonstrations"):
        Skill().fit(demos, times=times[:2])
    # Some demonstrations without times: the timing comes from the others.
    partial = Skill().fit_path(demos, times=[None, *times[1:]])
    assert len(partial.timing_.demo_durations) == 4


def test_learn_reads_the_times_of_a_demonstrations_file(tmp_path) -> None:
    demos, times, durations = timed_free_demos()
    path = save_demos(tmp_path / "timed.csv", demos, times=times)
    skill = learn(path)
    assert skill.timing_.duration == pytest.approx(np.median(durations), abs=1e-5)
    assert read_training_data(path).free_times[0] is not None
    assert read_training_data(FILES["demos"]).free_times == [None] * 13
    bad = tmp_path / "nan.csv"
    bad.write_text(path.read_text().replace("\n0,0.0,", "\n0,nan,", 1))
    with pytest.raises(ValueError, match=r"nan\.csv.*(time|t)"):
        learn(bad)


# ------------------------------------------------------------------ moving obstacles
def test_plan_avoids_a_moving_obstacle_where_it_is_when_the_tool_passes(skill) -> None:
    from lfdkit.model.motion import ConstantVelocity
    from lfdkit.model.scene import Obstacle

    duration = 8.0
    times = skill.point_times(duration)
    assert times[0] == 0.0 and times[-1] == pytest.approx(duration)
    assert np.all(np.diff(times) > 0)
    nominal = np.asarray(skill.plan(duration=duration).points)
    k = len(nominal) // 2  # a cup crossing the sweep at its middle when the tool is there
    velocity = np.array([0.0, 0.05])
    cup = Obstacle("cup", nominal[k] - velocity * times[k], 0.03, motion=ConstantVelocity(velocity))
    plan = skill.plan(scene=Scene((cup,)), duration=duration, clearance=0.025)
    centres = cup.predict(plan.times)[0]
    assert np.linalg.norm(plan.points - centres, axis=1).min() >= 0.03 + 0.025 - 1e-3
    # the assumption: the swerving plan reaches each point at nearly the nominal's time
    assert np.abs(plan.times - times).max() < 0.05 * duration
    # planned for where the cup is now, the sweep runs into it later
    static = skill.plan(scene=Scene((cup.at(0.0),)), duration=duration, clearance=0.025)
    assert np.linalg.norm(static.points - cup.predict(static.times)[0], axis=1).min() < 0.03


#: Issue 27: a standing 10 cm cup forces a detour; a marker crosses it at 4 m/s. Planned
#: at the nominal's point times, the plan re-timed by its own arc length ran into it.
DETOUR_CUP = ([0.0, 0.46], 0.1)
FAST_MARKER = ([-0.327, -0.893], 0.01, [0.283, 3.99])


def _detour_scene() -> Scene:
    from lfdkit.model.motion import ConstantVelocity
    from lfdkit.model.scene import Obstacle

    (at, radius), (start, r, velocity) = DETOUR_CUP, FAST_MARKER
    marker = Obstacle("marker", start, r, motion=ConstantVelocity(velocity))
    return Scene((Obstacle("cup", at, radius), marker))


def test_moving_plans_are_checked_at_the_times_they_are_run(skill) -> None:
    from lfdkit.emulate.planner import moving_clearance

    goal, scene = [0.36, 0.5], _detour_scene()
    # The old way: the planner's plan (safe at the nominal's times), timed by its length.
    details = skill.plan_details(goal=goal, scene=scene, duration=1.0)
    own, _ = skill.timing_.time_path(details.points, 1.0)
    assert moving_clearance(details.points, skill.point_times(1.0), scene, 0.0, 2.0)[1] > 0.0
    assert moving_clearance(details.points, own, scene, 0.0, 2.0)[1] < -1e-3  # inside
    # Skill.plan checks at its own times and re-plans at them.
    plan = skill.plan(goal=goal, scene=scene, duration=1.0)
    assert np.all(moving_clearance(plan.points, plan.times, scene, 0.0, 2.0) >= 0.0)
    assert plan.details.clearance.min() >= 0.0
    assert plan.times[-1] == pytest.approx(1.0) and plan.details.goal_error < 1e-3


# ------------------------------------------------------------------ demonstration records
def test_demo_records_learn_what_the_parallel_lists_learn(tmp_path) -> None:
    demos, times, _ = timed_free_demos()
    demos, times = demos[:3], times[:3]  # three are enough to tell the two forms apart
    turns = [exp(np.c_[np.zeros((len(d), 2)), np.linspace(0.0, 0.5, len(d))]) for d in demos]
    fields = enumerate(zip(demos, times, turns, strict=True))
    records = [Demo(d, t, o, f"sweep-{j}") for j, (d, t, o) in fields]
    from_records = Skill().fit_path(records)
    from_lists = Skill().fit_path(demos, times=times, orientations=turns)
    np.testing.assert_array_equal(from_records.path_, from_lists.path_)
    np.testing.assert_array_equal(from_records.orientations_, from_lists.orientations_)
    assert from_records.timing_.demo_durations == from_lists.timing_.demo_durations
    # A file read as records is the same set.
    path = save_demos(tmp_path / "timed.csv", records)
    back = load_demos(path, as_records=True)
    assert [r.id for r in back] == [r.id for r in records]
    for got, sent in zip(back, records, strict=True):
        np.testing.assert_array_equal(got.points, sent.points)
        np.testing.assert_array_equal(got.times, sent.times)
        np.testing.assert_allclose(got.orientations, sent.orientations, atol=1e-15)


def test_task_frames_a_skill_does_not_use_are_said(sweeping) -> None:
    framed = [Demo(d, frames={"pan": [0.4, 0.5, 1.0]}) for d in sweeping.free_demos[:3]]
    with pytest.warns(UserWarning, match=r"^demos: the demonstrations carry task frames \(pan\)"):
        skill = Skill().fit_path(framed)
    plain = Skill().fit_path(sweeping.free_demos[:3])
    np.testing.assert_array_equal(skill.path_, plain.path_)


def test_demo_records_refuse_what_they_already_carry(sweeping) -> None:
    clean = [Demo(d) for d in sweeping.free_demos]
    pairs = zip(sweeping.demos[:2], sweeping.scenes[:2], strict=True)
    around = [Demo(d, scene=s) for d, s in pairs]
    with pytest.raises(ValueError, match=r"^times: the Demo records carry their own times"):
        Skill().fit(clean, times=[None] * len(clean))
    with pytest.raises(
        ValueError, match=r"^demos\[1\]: recorded around obstacles \(1 in its scene"
    ):
        Skill().fit([clean[0], around[0], *clean[1:]])
    with pytest.raises(ValueError, match=r"^scenes: the Demo records carry their own scenes"):
        Skill().fit(clean, around, sweeping.scenes[:2])
    with pytest.raises(ValueError, match=r"^obstacle_demos\[0\]: the record .* has no scene"):
        Skill().fit(clean, [Demo(sweeping.demos[0])])
    with pytest.raises(TypeError, match=r"^demos\[2\]: expected a Demo record like the others"):
        Skill().fit([*clean[:2], sweeping.free_demos[2]])


def test_held_out_records_are_scored_as_their_lists(skill, test_set) -> None:
    demos, scenes = test_set
    records = [Demo(d, scene=s) for d, s in zip(demos[:2], scenes[:2], strict=True)]
    assert skill.evaluate(records) == skill.evaluate(demos[:2], scenes[:2])
    with pytest.raises(ValueError, match=r"^scenes: give one scene per demonstration"):
        skill.evaluate(demos[:2])
    with pytest.raises(ValueError, match=r"^demos\[0\]: the record .* has no scene"):
        skill.evaluate([Demo(demos[0])])


@pytest.mark.slow
def test_a_demonstration_passed_on_a_side_no_reward_takes_is_left_out_of_the_fit(
    sweeping, tmp_path
):
    """One cup 2 mm beside the path passed 12 cm away on its own side (a coin flip).

    The fit warm-starts each plan on its demonstration's side, so with it the whole
    reward bent to explain that swerve (main: Q 107 against the truth's 20, held-out
    improvement 96.2 %); replanned on the other side, it is left out and said.
    """
    data = example_dataset()
    demos = [data.demos[j] for j in data.train]
    scenes = [data.scenes[j] for j in data.train]
    nominal = resample(Skill().fit(data.free_demos).nominal(demos[0][0]), 200)
    left = np.column_stack((-np.gradient(nominal[:, 1]), np.gradient(nominal[:, 0])))
    left /= np.linalg.norm(left, axis=1, keepdims=True)
    u = np.linspace(0.0, 1.0, 200)
    bump = np.where(np.abs(u - 0.5) < 0.25, 0.5 + 0.5 * np.cos(np.pi * (u - 0.5) / 0.25), 0.0)
    cup = next(s.obstacles[0] for s in scenes if s.labels[0] == "cup")
    near = Scene((replace(cup, position=nominal[100] + 0.002 * left[100]),))
    outlier = nominal + 0.12 * bump[:, None] * left
    with pytest.warns(UserWarning, match=r"obstacle demonstration\(s\) 8 pass an obstacle"):
        skill = Skill().fit(data.free_demos, [*demos, outlier], [*scenes, near])
    assert skill.ioc_info_["left_out"] == [8]
    assert 0.5 < skill.reward_.nominal_weight / sweeping.true_reward.nominal_weight < 2.0
    # Reported with the others, as the skill plans its scene: on the other side.
    rows = {row["demo"]: row for row in skill.training_fidelity_}
    assert sorted(rows) == list(range(9)) and rows[8]["left_out"]
    assert not rows[8]["sides_agree"] and not any(rows[j].get("left_out") for j in range(8))
    loaded = Skill.load(skill.save(tmp_path / "skill.json"))
    assert loaded.ioc_info_["left_out"] == [8] and loaded.training_fidelity_[8]["left_out"]
    test_demos, ids = load_demos(FILES["test_demos"], return_ids=True)
    test_scenes = load_scenes(FILES["test_scenes"])
    assert skill.evaluate(test_demos, [test_scenes[k] for k in ids])["improvement"] > 98.0
