"""Skill files store the fitted DMPs: loading restores them (no refit), plans equal to the bit.

Issue 30: loading a skill used to refit its DMP (2.9 s for the sweeping
skill, 18 s at 1000 basis functions). The file now holds the DMP as fitted;
these tests check that a loaded skill plans exactly as the saved one over
several settings (hypothesis), that loading never fits, that a file written
before the state existed still loads (by refitting, to the same plans), and
that a corrupt or mismatched state is refused on one line naming the field.
"""

from __future__ import annotations

import base64
import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from lfdkit.core.options import SCALINGS
from lfdkit.emulate import Reward
from lfdkit.imitate import DMP, QuaternionDMP, SpeedProfile
from lfdkit.imitate.dmp import STATE_VERSION
from lfdkit.io.skill_file import pack_arrays
from lfdkit.model.scene import Scene
from lfdkit.skill import Skill


def wavy_path(n_dims: int, seed: int, n_points: int = 60) -> np.ndarray:
    """A smooth open path with random wiggles (units arbitrary)."""
    rng = np.random.default_rng(seed)
    u = np.linspace(0.0, 1.0, n_points)
    path = np.outer(u, rng.uniform(0.3, 2.0, n_dims))
    for k in range(1, 3):
        path += np.outer(np.sin(np.pi * k * u), rng.normal(0.0, 0.1, n_dims))
    return path


def reloaded(skill: Skill) -> Skill:
    return Skill.from_dict(json.loads(json.dumps(skill.to_dict())))


def assert_same_plan(a, b) -> None:
    assert np.array_equal(a.points, b.points)
    assert np.array_equal(a.times, b.times)
    assert np.array_equal(a.velocities, b.velocities)


@pytest.mark.filterwarnings("ignore:n_basis='auto'")  # uniform timing lags from rest
@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    n_dims=st.sampled_from([2, 3]),
    n_basis=st.sampled_from(["auto", 6, 37]),
    scaling=st.sampled_from(SCALINGS),
    timing=st.sampled_from(["minimum_jerk", "uniform", "learned"]),
    units=st.sampled_from(["m", "mm"]),
    seed=st.integers(0, 10_000),
)
def test_a_loaded_skill_plans_to_the_bit_as_the_saved_one(
    n_dims, n_basis, scaling, timing, units, seed
) -> None:
    scale = 1000.0 if units == "mm" else 1.0
    path = scale * wavy_path(n_dims, seed)
    law = None
    if timing == "learned":
        law = SpeedProfile(2.5, np.array([0.0, 0.0, 1.0, 3.0, 2.0, 0.5, 0.0, 0.0]), "given")
    skill = Skill(
        n_basis=n_basis,
        scaling=scaling,
        timing="uniform" if timing == "uniform" else "minimum_jerk",
        units=units,
    ).use_path(path, timing=law)
    loaded = reloaded(skill)
    rng = np.random.default_rng(seed)
    for _ in range(2):
        goal = path[-1] + rng.normal(0.0, 0.05 * scale, n_dims)
        start = path[0] + rng.normal(0.0, 0.05 * scale, n_dims)
        assert_same_plan(loaded.plan(start, goal), skill.plan(start, goal))
    assert loaded.dmp_.n_basis_ == skill.dmp_.n_basis_
    assert loaded.dmp_.reproduction_error_ == skill.dmp_.reproduction_error_
    # The loaded skill writes the same document again.
    assert loaded.to_dict() == json.loads(json.dumps(skill.to_dict()))


def test_plans_around_obstacles_and_steps_are_equal_too() -> None:
    path = wavy_path(2, seed=3)
    skill = Skill(n_basis=15).use_path(path).adopt(Reward(1.0, {"cup": 400.0 * np.eye(2)}))
    loaded = reloaded(skill)
    scene = Scene.from_arrays(["cup"], [path[30] + [0.01, -0.02]], [0.05])
    goal = path[-1] + [0.05, 0.02]
    assert_same_plan(loaded.plan(goal=goal, scene=scene), skill.plan(goal=goal, scene=scene))
    state = (0.3, path[10] + 0.01, np.array([0.2, -0.1]), 0.01)
    steps = skill.dmp_.step(*state, goal=goal), loaded.dmp_.step(*state, goal=goal)
    for a, b in zip(*steps, strict=True):
        assert np.array_equal(a, b)


def test_loading_restores_without_fitting(tmp_path: Path, monkeypatch) -> None:
    path = wavy_path(2, seed=1)
    saved = Skill().use_path(path).save(tmp_path / "skill.json")

    def refuse(*args, **kwargs):
        raise AssertionError("loading refitted the DMP")

    monkeypatch.setattr(DMP, "fit", refuse)
    monkeypatch.setattr(QuaternionDMP, "fit", refuse)
    loaded = Skill.load(saved)
    assert loaded.dmp_.forcing_target_ is None  # a fit diagnostic, not stored
    assert loaded.nominal(goal=path[-1] + 0.1).shape[1] == 2


def test_orientation_dmp_round_trips_without_refit(monkeypatch) -> None:
    path = wavy_path(3, seed=5)
    angle = np.linspace(0.0, 1.0, len(path))
    orientations = np.column_stack(
        [np.zeros_like(angle), np.zeros_like(angle), np.sin(angle / 2), np.cos(angle / 2)]
    )
    skill = Skill(n_basis=20).use_path(path, orientations=orientations)
    data = json.loads(json.dumps(skill.to_dict()))
    monkeypatch.setattr(QuaternionDMP, "fit", lambda *a, **k: pytest.fail("refitted"))
    loaded = Skill.from_dict(data)
    goal_q = [0.0, 0.0, np.sin(0.7), np.cos(0.7)]
    a = skill.plan(goal=path[-1] + 0.1, goal_orientation=goal_q)
    b = loaded.plan(goal=path[-1] + 0.1, goal_orientation=goal_q)
    assert_same_plan(a, b)
    assert np.array_equal(a.orientations, b.orientations)


def test_a_file_without_the_state_still_loads_by_refitting() -> None:
    skill = Skill(n_basis=12).use_path(wavy_path(2, seed=2))
    data = json.loads(json.dumps(skill.to_dict()))
    old = {key: value for key, value in data.items() if key != "dmp"}  # before issue 30
    loaded = Skill.from_dict(old)
    assert loaded.dmp_.forcing_target_ is not None  # refitted
    goal = [2.0, 1.0]
    assert_same_plan(loaded.plan(goal=goal), skill.plan(goal=goal))
    # And it is written back with the state.
    assert loaded.to_dict() == data


def test_the_dmp_state_round_trips_alone() -> None:
    path = wavy_path(2, seed=4)
    for scaling in SCALINGS:
        for end in ("rest", "free"):
            dmp = DMP(n_basis=25, scaling=scaling, end=end).fit(path, duration=3.0)
            again = DMP.from_state(_unpacked(dmp.to_state()))
            first, second = dmp.rollout(goal=[2.5, 1.0]), again.rollout(goal=[2.5, 1.0])
            for field in ("times", "positions", "velocities", "accelerations"):
                assert np.array_equal(getattr(first, field), getattr(second, field))


def _unpacked(state: dict) -> dict:
    from lfdkit.io.skill_file import unpack_arrays

    return unpack_arrays(json.loads(json.dumps(pack_arrays(state))), "dmp")


# ------------------------------------------------------------------ refusals
@pytest.fixture(scope="module")
def document() -> dict:
    return json.loads(json.dumps(Skill(n_basis=12).use_path(wavy_path(2, seed=7)).to_dict()))


def _edit_weights(doc: dict) -> None:
    packed = doc["dmp"]["weights"]
    values = np.frombuffer(base64.b64decode(packed["float64le"]), "<f8").copy()
    values[3] += 1e-12
    packed["float64le"] = base64.b64encode(values.tobytes()).decode()


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (_edit_weights, r"dmp: the stored DMP does not match its checksum"),
        (lambda d: d["path"][5].__setitem__(0, 0.123), r"dmp: the stored DMP does not match"),
        (lambda d: d["dmp"]["knots"].update(float64le="*"), r"knots.float64le: expected base64"),
        (lambda d: d["dmp"]["times"].update(shape=[3]), r"dmp.times.float64le: holds 60 numbers"),
        (lambda d: d["dmp"].update(version=STATE_VERSION + 1), r"dmp.version: .* newer"),
        (lambda d: d["dmp"].pop("weights"), r"dmp.weights: missing field"),
        (lambda d: d.update(dmp=[1, 2]), r"dmp: expected an object"),
        (lambda d: d["params"].update(scaling="spatial"), r"dmp.params.scaling: .* refit"),
        (lambda d: d["params"].update(timing="uniform"), r"dmp.timing: .*another speed profile"),
        (lambda d: d["params"].update(duration=2.0), r"dmp.duration: .* refit"),
    ],
)
def test_a_corrupt_or_mismatched_state_is_refused_on_one_line(document, edit, message) -> None:
    doc = json.loads(json.dumps(document))
    edit(doc)
    with pytest.raises(ValueError, match=f"^f.json: .*{message}") as info:
        Skill.from_dict(doc, source="f.json")
    assert "\n" not in str(info.value)
