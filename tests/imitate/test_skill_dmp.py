"""The skill's DMP settings: n_basis="auto" or an integer, in code and in skill files."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lfdkit.datasets import load_dataset
from lfdkit.imitate import BASIS_LADDER, DMP
from lfdkit.skill import Skill


@pytest.fixture(scope="module")
def path() -> np.ndarray:
    u = np.linspace(0.0, 1.0, 100)
    return np.column_stack([0.6 * u, 0.1 * np.sin(2.0 * np.pi * u)])


def test_auto_is_the_default_and_the_dmp_reports_the_count(path) -> None:
    skill = Skill().use_path(path)
    assert skill.n_basis == "auto"
    assert skill.dmp_.n_basis_ in BASIS_LADDER
    assert skill.dmp_.reproduction_error_ <= 0.01
    expected = DMP(n_basis="auto", scaling="spatial").fit(path, timing="minimum_jerk")
    np.testing.assert_array_equal(skill.dmp_.weights_, expected.weights_)
    assert Skill(n_basis=12).use_path(path).dmp_.n_basis_ == 12


@pytest.mark.parametrize("n_basis", ["auto", 12])
def test_the_skill_file_round_trips_auto_and_integer_counts(path, n_basis) -> None:
    skill = Skill(n_basis=n_basis).use_path(path)
    data = json.loads(json.dumps(skill.to_dict()))
    assert data["params"]["n_basis"] == n_basis
    loaded = Skill.from_dict(data)
    assert loaded.n_basis == n_basis
    assert loaded.dmp_.n_basis_ == skill.dmp_.n_basis_
    np.testing.assert_array_equal(loaded.dmp_.weights_, skill.dmp_.weights_)
    np.testing.assert_array_equal(loaded.nominal(goal=[0.7, 0.1]), skill.nominal(goal=[0.7, 0.1]))


@pytest.fixture(scope="module")
def skill_file(path) -> dict:
    """A skill as its file holds it (parsed JSON)."""
    return json.loads(json.dumps(Skill(n_basis=12).use_path(path).to_dict()))


def with_n_basis(data: dict, n_basis: object) -> dict:
    """The file with another ``n_basis``, as a file without the fitted DMP (read by refitting)."""
    refit = {key: value for key, value in data.items() if key != "dmp"}
    return {**refit, "params": {**data["params"], "n_basis": n_basis}}


def test_skill_files_accept_auto_and_counts_up_to_1000(skill_file) -> None:
    assert Skill.from_dict(with_n_basis(skill_file, "auto")).n_basis == "auto"
    assert Skill.from_dict(with_n_basis(skill_file, 200)).dmp_.n_basis_ == 200


def test_a_file_without_the_fitted_dmp_refits_at_most_200(skill_file) -> None:
    with pytest.raises(ValueError, match=r"^f.json: params.n_basis: 201 basis functions, but"):
        Skill.from_dict(with_n_basis(skill_file, 201), source="f.json")


def test_a_stored_dmp_fitted_with_another_count_is_refused(skill_file) -> None:
    edited = {**skill_file, "params": {**skill_file["params"], "n_basis": 13}}
    with pytest.raises(ValueError, match=r"^f.json: dmp.params.n_basis: .* remove the dmp field"):
        Skill.from_dict(edited, source="f.json")


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("automatic", "params.n_basis: expected an integer, got 'automatic'"),
        (0, "params.n_basis: expected 1 to 1000, got 0"),
        (1001, "params.n_basis: expected 1 to 1000, got 1001"),
        (20.0, "params.n_basis: expected an integer"),
        (True, "params.n_basis: expected an integer"),
    ],
)
def test_skill_files_accept_auto_and_bounded_integers_only(skill_file, value, message) -> None:
    with pytest.raises(ValueError, match=f"^f.json: {message}"):
        Skill.from_dict(with_n_basis(skill_file, value), source="f.json")


def test_a_skill_built_in_code_refuses_a_bad_count(path) -> None:
    with pytest.raises(ValueError, match="n_basis: expected an integer or 'auto', got 'many'"):
        Skill(n_basis="many").use_path(path)
    with pytest.raises(ValueError, match="n_basis: expected 1 to 1,000, got 1,001"):
        Skill(n_basis=1001).use_path(path)


def test_the_progress_message_names_the_chosen_count() -> None:
    demos = load_dataset("walking", seed=0).demos
    messages: list[str] = []
    skill = Skill().fit_path(demos, progress=messages.append)
    said = [m for m in messages if m.startswith("imitate:")]
    assert said == [
        f"imitate: DMP with {skill.dmp_.n_basis_} basis functions per dimension "
        f"(n_basis='auto'), reproducing the path within "
        f"{skill.dmp_.reproduction_error_:.2%} of its extent"
    ]
