"""A skill's units: learning is scale-invariant, and the unit is kept in the skill file.

The sweeping example (metres) is learned as given and multiplied by 1000 with
``units="mm"``: the path must come out 1000 times larger, the reward's nominal
weight and precisions (1/units²) 1e6 times smaller, and every plan 1000 times
larger. The two fits see the same numbers to round-off; the reward fit's
L-BFGS path through a flat loss amplifies that to a few 1e-6 in the
parameters and about 1e-7 of the extent in the plans.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from lfdkit.io import load_demos, load_scenes
from lfdkit.io.training import read_training_data
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill
from lfdkit.tasks.sweeping import example_files
from tests.conftest import example_skill_copy

FILES = example_files()
SCENE = Scene((Obstacle("cup", [-0.05, 0.47], radius=0.03), Obstacle("marker", [0.1, 0.44])))
GOAL = np.array([0.36, 0.5])


def _fit(factor: float, units: str, **params) -> Skill:
    data = read_training_data(FILES["demos"], FILES["scenes"])
    return Skill(units=units, **params).fit(
        [factor * d for d in data.free_demos],
        [factor * d for d in data.obstacle_demos],
        [scene.scaled(factor) for scene in data.scenes],
    )


@pytest.fixture(scope="module")
def metres(example_skill_once) -> Skill:
    # The session's example skill: learn() fits these very arrays (its fit record also
    # names the demonstrations), so _fit(1.0, "m") would learn it a second time.
    return example_skill_copy(example_skill_once)


@pytest.fixture(scope="module")
def millimetres() -> Skill:
    return _fit(1000.0, "mm")


def _extent(path: np.ndarray) -> float:
    return float(np.ptp(path, axis=0).max())


def test_the_default_unit_is_the_metre(metres) -> None:
    assert Skill().units == "m"
    assert metres.to_dict()["units"] == "m"


def test_the_same_demonstrations_in_millimetres_learn_the_same_skill(metres, millimetres):
    extent = _extent(metres.path_)
    np.testing.assert_allclose(
        millimetres.path_ / 1000.0, metres.path_, rtol=0.0, atol=1e-12 * extent
    )
    # Q and the precisions are in 1/units²: divided by 1000².
    assert millimetres.reward_.nominal_weight * 1e6 == pytest.approx(
        metres.reward_.nominal_weight, rel=1e-4
    )
    assert set(millimetres.reward_.classes) == set(metres.reward_.classes) == {"cup", "marker"}
    for label in metres.reward_.classes:
        np.testing.assert_allclose(
            millimetres.reward_.precisions[label] * 1e6,
            metres.reward_.precisions[label],
            rtol=1e-4,
        )
    assert millimetres.ioc_info_["loss"] == pytest.approx(1e6 * metres.ioc_info_["loss"], rel=1e-4)


def test_the_same_demonstrations_in_millimetres_choose_the_same_model(metres, millimetres):
    # Every decision of the model choice is a ratio or a count: the same choice, its
    # cross-validated replanning errors (units²) 1e6 times larger.
    in_m, in_mm = metres.model_selection_, millimetres.model_selection_
    for key in ("chosen", "runner_up", "default", "folds", "gaps_shown"):
        assert in_mm[key] == in_m[key], key
    assert in_mm["clearance_consistency"] == pytest.approx(in_m["clearance_consistency"], rel=1e-4)
    assert in_mm["candidates"].keys() == in_m["candidates"].keys()
    for name, scores in in_m["candidates"].items():
        scaled = in_mm["candidates"][name]
        assert scaled["mse"] == pytest.approx(1e6 * scores["mse"], rel=1e-4), name
        assert scaled["error"] == pytest.approx(1e6 * scores["error"], rel=1e-4), name
        for key in ("refused", "clearance_relaxed", "route", "floor"):
            assert scaled[key] == scores[key], (name, key)
    assert (millimetres.route_, millimetres.gaps_) == (metres.route_, metres.gaps_)
    assert millimetres.clearances_.keys() == metres.clearances_.keys()
    for label, clearance in metres.clearances_.items():
        assert millimetres.clearances_[label] == pytest.approx(1000.0 * clearance, rel=1e-9)


@pytest.mark.parametrize("planner", ["mpc", "full"])
def test_plans_in_millimetres_are_the_plans_in_metres_times_1000(metres, millimetres, planner):
    extent = _extent(metres.path_)
    options = {"planner": planner}
    in_m = metres.plan(None, GOAL, SCENE, **options)
    in_mm = millimetres.plan(None, 1000.0 * GOAL, SCENE.scaled(1000.0), **options)
    np.testing.assert_allclose(in_mm / 1000.0, in_m, rtol=0.0, atol=1e-6 * extent)
    # Lengths given to the planner are in the skill's units too.
    details_m = metres.plan_details(None, GOAL, SCENE, goal_approach=0.1, clearance=0.01, **options)
    details_mm = millimetres.plan_details(
        None, 1000.0 * GOAL, SCENE.scaled(1000.0), goal_approach=100.0, clearance=10.0, **options
    )
    np.testing.assert_allclose(
        details_mm.points / 1000.0, details_m.points, rtol=0.0, atol=1e-6 * extent
    )
    np.testing.assert_allclose(
        details_mm.clearance / 1000.0, details_m.clearance, rtol=0.0, atol=1e-6 * extent
    )


def test_held_out_scores_transform_with_the_units(metres, millimetres) -> None:
    demos, ids = load_demos(FILES["test_demos"], return_ids=True)
    by_id = load_scenes(FILES["test_scenes"])
    scenes = [by_id[key] for key in ids]
    in_m = metres.evaluate(demos, scenes)
    in_mm = millimetres.evaluate([1000.0 * d for d in demos], [s.scaled(1000.0) for s in scenes])
    assert in_mm["mse"] == pytest.approx(1e6 * in_m["mse"], rel=1e-4)  # units²
    assert in_mm["mse_replay"] == pytest.approx(1e6 * in_m["mse_replay"], rel=1e-9)
    assert in_mm["improvement"] == pytest.approx(in_m["improvement"], abs=1e-3)  # percent


@pytest.mark.parametrize(("mimic", "units", "factor"), [("gmr", "mm", 1e3), ("gmr", "cm", 1e2)])
def test_gmr_paths_do_not_depend_on_the_units(mimic, units, factor) -> None:
    # GMR's mixture of phase and position is not scale-invariant by itself; the skill
    # fits it in metres.
    data = read_training_data(FILES["demos"])
    params = {"mimic": mimic, "random_state": 0}
    in_m = Skill(**params).fit_path(data.free_demos[:5])
    scaled = Skill(units=units, **params).fit_path([factor * d for d in data.free_demos[:5]])
    extent = _extent(in_m.path_)
    np.testing.assert_allclose(scaled.path_ / factor, in_m.path_, rtol=0.0, atol=1e-9 * extent)
    assert scaled.mimic_info_["converged"] == in_m.mimic_info_["converged"]


def test_to_units_converts_a_fitted_skill(metres, millimetres) -> None:
    assert metres.to_units("m") is metres
    converted = metres.to_units("mm")
    assert converted.units == "mm" and metres.units == "m"
    assert converted.get_params() == {**metres.get_params(), "units": "mm"}
    np.testing.assert_array_equal(converted.path_, 1000.0 * metres.path_)
    assert converted.reward_.nominal_weight == metres.reward_.nominal_weight / 1e6
    for label in metres.reward_.classes:
        np.testing.assert_array_equal(
            converted.reward_.precisions[label], metres.reward_.precisions[label] / 1e6
        )
    assert converted.ioc_info_ is None and converted.mimic_info_["method"] == "given"
    extent = _extent(metres.path_)
    plan = converted.plan(None, 1000.0 * GOAL, SCENE.scaled(1000.0))
    np.testing.assert_allclose(plan / 1000.0, metres.plan(None, GOAL, SCENE), atol=1e-6 * extent)
    back = millimetres.to_units("cm").to_units("m")
    np.testing.assert_allclose(back.path_, millimetres.path_ / 1000.0, rtol=1e-15)
    with pytest.raises(ValueError, match=r"^units: expected one of 'm', 'cm', 'mm', got 'in'"):
        metres.to_units("in")


def test_to_units_converts_the_model_choice_s_lengths_and_areas(metres) -> None:
    # Clearances, allowances and reaches are lengths (x 1000 in mm), replanning errors and
    # the noise floor areas (x 1e6); ratios, shares, counts and names stay as they are.
    chosen, converted = metres.model_selection_, metres.to_units("mm").model_selection_
    for key in ("gap_clearances", "gap_allowance"):
        for label, value in (chosen.get(key) or {}).items():
            assert converted[key][label] == pytest.approx(1e3 * value, rel=1e-12), key
    if chosen.get("swerve_reach") is not None:
        np.testing.assert_allclose(
            converted["swerve_reach"], 1e3 * np.asarray(chosen["swerve_reach"])
        )
    for key in ("noise_mse", "no_floor_mse"):
        if chosen.get(key) is not None:
            assert converted[key] == pytest.approx(1e6 * chosen[key], rel=1e-12), key
    for name, scores in chosen["candidates"].items():
        assert converted["candidates"][name]["mse"] == pytest.approx(1e6 * scores["mse"]), name
        assert converted["candidates"][name]["route"] == scores["route"], name
    for key in ("chosen", "runner_up", "clearance_consistency", "threads_gaps", "gaps_shown"):
        assert converted[key] == chosen[key], key
    assert chosen.get("no_floor_mse") is not None  # the areas are checked, not skipped


def test_an_unknown_unit_is_refused() -> None:
    with pytest.raises(ValueError, match=r"^units: expected one of 'm', 'cm', 'mm', got 'km'"):
        Skill(units="km").fit_path([np.eye(3)[:, :2], np.eye(3)[:, :2] + 0.1])


def _saved(skill: Skill, tmp_path: Path, edit=None) -> Path:
    doc = skill.to_dict()
    if edit is not None:
        edit(doc)
    path = tmp_path / "skill.json"
    path.write_text(json.dumps(doc))
    return path


def test_the_unit_is_kept_in_the_skill_file(millimetres, tmp_path) -> None:
    path = tmp_path / "mm.json"
    millimetres.save(path)
    doc = json.loads(path.read_text())
    assert doc["units"] == "mm" and doc["params"]["units"] == "mm"
    loaded = Skill.load(path)
    assert loaded.units == "mm"
    plan = millimetres.plan(None, 1000.0 * GOAL, SCENE.scaled(1000.0))
    np.testing.assert_array_equal(loaded.plan(None, 1000.0 * GOAL, SCENE.scaled(1000.0)), plan)


def test_an_old_skill_file_without_units_is_in_metres(metres, tmp_path) -> None:
    def drop(doc):
        doc.pop("units")
        doc["params"].pop("units")

    loaded = Skill.load(_saved(metres, tmp_path, drop))
    assert loaded.units == "m"
    np.testing.assert_array_equal(loaded.plan(None, GOAL, SCENE), metres.plan(None, GOAL, SCENE))
    # One of the two places is enough.
    loaded = Skill.load(_saved(metres, tmp_path, lambda d: d["params"].pop("units")))
    assert loaded.units == "m"
    loaded = Skill.load(_saved(metres, tmp_path, lambda d: d.pop("units")))
    assert loaded.units == "m"


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d.update(units="mm"), r"units: 'mm' does not match params.units 'm'"),
        (lambda d: d.update(units=3), r"units: expected str, got int"),
        (
            lambda d: (d.update(units="inch"), d["params"].update(units="inch")),
            r"params: units: expected one of 'm', 'cm', 'mm', got 'inch'",
        ),
        (
            lambda d: (d.pop("units"), d["params"].update(units="")),
            r"params: units: expected one of 'm', 'cm', 'mm', got ''",
        ),
    ],
    ids=["mismatch", "not-text", "unknown", "empty"],
)
def test_a_broken_unit_in_a_skill_file_names_the_field(metres, tmp_path, edit, message):
    path = _saved(metres, tmp_path, edit)
    with pytest.raises(ValueError, match=message) as info:
        Skill.load(path)
    assert str(info.value).startswith(str(path))
