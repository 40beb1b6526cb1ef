"""A skill learned with the tool's orientation: mean orientation, orientation DMP, plans, files.

Synthetic demonstrations in centimetres (3-D) and metres (2-D) carry a known
orientation profile (a yaw turning smoothly along the path, a pitch that
rises and falls), each demonstration with its own smooth deviation, small
per-sample noise and random quaternion sign flips. The truth is built with
pytransform3d (a second library, scalar-first quaternions), so the
``[x, y, z, w]`` convention is checked too.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import pytransform3d.rotations as pr

from lfdkit.core.rotations import angle_between, exp, multiply
from lfdkit.execute.poses import path_yaw, yaw_from_quaternions
from lfdkit.skill import Skill

#: The truth's yaw and pitch along the movement's fraction u (rad).
YAW0, YAW_TURN, PITCH = 0.2, 1.2, 0.3


def truth(u: np.ndarray, *, pitch: float = PITCH) -> np.ndarray:
    """Rz(yaw(u)) Ry(pitch(u)) as unit quaternions [x, y, z, w], through pytransform3d."""
    out = []
    for v in np.atleast_1d(u):
        R = pr.active_matrix_from_angle(2, YAW0 + YAW_TURN * v) @ pr.active_matrix_from_angle(
            1, pitch * np.sin(np.pi * v)
        )
        w, x, y, z = pr.quaternion_from_matrix(R)
        out.append([x, y, z, w])
    return np.array(out)


def demonstrations(n_dims: int, scale: float, seed: int, pitch: float = PITCH):
    """Five demonstrations of a curve (``scale`` units long) with their orientations."""
    rng = np.random.default_rng(seed)
    demos, quats = [], []
    for j in range(5):
        n = 80 + 7 * j
        u = np.linspace(0.0, 1.0, n)
        curve = np.stack([u, 0.3 * np.sin(np.pi * u), 0.2 * u**2], axis=-1)[:, :n_dims]
        points = scale * (curve + rng.normal(0, 0.005, (1, n_dims)))
        points += scale * rng.normal(0, 0.001, (n, n_dims))
        # A smooth deviation of a few degrees per demonstration, and sensor noise.
        axis = rng.normal(0, 0.03, 3) if n_dims == 3 else np.array([0, 0, rng.normal(0, 0.03)])
        drift = exp(np.outer(np.sin(np.pi * u * (1 + j % 3)), axis))
        noise = exp(rng.normal(0, 0.002, (n, 3)) * ([1, 1, 1] if n_dims == 3 else [0, 0, 1]))
        q = multiply(multiply(truth(u, pitch=pitch), drift), noise)
        q[rng.random(n) < 0.3] *= -1.0  # q and -q: the same orientation
        demos.append(points)
        quats.append(q)
    return demos, quats


@pytest.fixture(scope="module")
def skill3() -> Skill:
    demos, quats = demonstrations(3, 100.0, seed=1)
    return Skill(units="cm").fit(demos, orientations=quats)


@pytest.fixture(scope="module")
def skill2() -> Skill:
    """A 2-D skill in metres whose brush is held along a yaw that is not the tangent."""
    demos, quats = demonstrations(2, 0.4, seed=2, pitch=0.0)
    return Skill().fit(demos, orientations=quats)


def _truth_at(skill: Skill, points: np.ndarray, scale: float) -> np.ndarray:
    return truth(np.clip(points[:, 0] / scale, 0.0, 1.0), pitch=PITCH if skill.n_dims_ == 3 else 0)


# ------------------------------------------------------------------ learning
def test_the_mean_orientation_is_close_to_the_truth(skill3: Skill) -> None:
    assert skill3.orientations_.shape == (skill3.n_points, 4)
    assert skill3.orientations_[0, 3] >= 0.0  # the sign that starts with w >= 0
    error = np.degrees(angle_between(skill3.orientations_, _truth_at(skill3, skill3.path_, 100)))
    assert np.median(error) < 2.0 and error.max() < 3.5, error
    assert np.allclose(np.linalg.norm(skill3.orientations_, axis=1), 1.0, atol=1e-12)
    assert skill3.orientation_dmp_ is not None
    assert 0.0 < skill3.mimic_info_["orientation_spread_deg"] < 10.0


def test_a_skill_without_orientation_plans_as_before(skill3: Skill) -> None:
    demos, _ = demonstrations(3, 100.0, seed=1)
    plain = Skill(units="cm").fit(demos)
    assert plain.orientations_ is None and plain.orientation_dmp_ is None
    plan, oriented = plain.plan(), skill3.plan()
    assert plan.orientations is None
    np.testing.assert_array_equal(plan.points, oriented.points)
    np.testing.assert_array_equal(plan.times, oriented.times)
    assert "orientation" not in plain.to_dict()
    with pytest.raises(ValueError, match=r"^start_orientation: this skill has no orientation"):
        plain.plan(start_orientation=[0, 0, 0, 1])


# ------------------------------------------------------------------ plans
def test_the_plan_starts_at_the_start_and_ends_exactly_at_the_goal_orientation(skill3) -> None:
    plan = skill3.plan()
    q = plan.orientations
    assert q.shape == (len(plan), 4)
    assert np.abs(np.linalg.norm(q, axis=1) - 1.0).max() < 1e-12
    assert angle_between(q[0], skill3.orientations_[0]) < 1e-9
    assert angle_between(q[-1], skill3.orientations_[-1]) < 1e-9
    assert np.all(np.sum(q[1:] * q[:-1], axis=1) > 0.0)  # signs continuous
    # Along the way: the mean orientation of the path point as far along (the plan with
    # the default ends is the path's), within a degree, so as close to the truth as it.
    assert np.degrees(angle_between(q, skill3.orientations_)).max() < 1.0
    assert np.degrees(angle_between(q, _truth_at(skill3, plan.points, 100))).max() < 3.5
    assert "turning" in repr(plan)

    rng = np.random.default_rng(7)
    for _ in range(3):
        start_q, goal_q = exp(rng.normal(0, 0.6, (2, 3)))
        moved = skill3.plan(
            [5.0, -3.0, 2.0],
            [90.0, 10.0, 30.0],
            start_orientation=start_q,
            goal_orientation=-goal_q,  # either sign
        )
        assert angle_between(moved.orientations[0], start_q) < 1e-9
        assert angle_between(moved.orientations[-1], goal_q) < 1e-9
        assert np.abs(np.linalg.norm(moved.orientations, axis=1) - 1.0).max() < 1e-12


def test_orientations_follow_the_plans_normalised_time(skill3) -> None:
    """The orientation at a plan's point is the orientation DMP's at that point's t / T."""
    slow = skill3.plan(duration=7.0)
    fast = skill3.plan(speed=3.0)
    np.testing.assert_allclose(slow.orientations, fast.orientations, atol=1e-12)
    u = np.array([0.0, 0.25, 0.5, 1.0])
    rollout = skill3.orientation_dmp_.rollout(n_steps=5).orientations
    at = skill3.orientations_at(u)
    assert angle_between(at, rollout[[0, 1, 2, 4]]).max() < 1e-6


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"start_orientation": [0, 0, 0, 2]}, "^start_orientation: row 0 has norm 2"),
        ({"goal_orientation": [0, 0, 1]}, "^goal_orientation: expected shape"),
        ({"goal_orientation": [np.nan, 0, 0, 1]}, "^goal_orientation: row 0 is not finite"),
    ],
)
def test_bad_orientations_name_the_argument(skill3, kwargs, message) -> None:
    with pytest.raises(ValueError, match=message):
        skill3.plan(**kwargs)


def test_bad_training_orientations_name_the_argument() -> None:
    demos, quats = demonstrations(3, 100.0, seed=3)
    with pytest.raises(ValueError, match=r"^orientations: 4 arrays for 5 demonstrations"):
        Skill().fit(demos, orientations=quats[:4])
    with pytest.raises(ValueError, match=r"^orientations: orientations\[2\] is None"):
        Skill().fit(demos, orientations=[*quats[:2], None, *quats[3:]])
    with pytest.raises(ValueError, match=r"^orientations\[1\]: expected 87 quaternions"):
        Skill().fit(demos, orientations=[quats[0], quats[1][:-1], *quats[2:]])
    with pytest.raises(ValueError, match=r"^orientations\[0\]: row 0 has norm"):
        Skill().fit(demos, orientations=[2 * quats[0], *quats[1:]])
    # None for all is no orientation at all.
    assert Skill().fit(demos, orientations=[None] * 5).orientation_dmp_ is None


def test_a_constant_orientation_is_carried_to_a_new_goal_orientation() -> None:
    demos, _ = demonstrations(3, 100.0, seed=4)
    held = np.array([0.0, 0.0, np.sin(0.3), np.cos(0.3)])
    skill = Skill(units="cm").fit(demos, orientations=[np.tile(held, (len(d), 1)) for d in demos])
    assert angle_between(skill.plan().orientations, held).max() < 1e-9
    goal_q = exp(np.array([0.2, -0.1, 0.4]))
    plan = skill.plan(goal_orientation=goal_q)
    assert angle_between(plan.orientations[0], held) < 1e-9
    assert angle_between(plan.orientations[-1], goal_q) < 1e-9


# ------------------------------------------------------------------ files
def test_skill_file_round_trip_keeps_orientations_and_plans(skill3, tmp_path: Path) -> None:
    path = skill3.save(tmp_path / "skill.json")
    loaded = Skill.load(path)
    np.testing.assert_array_equal(loaded.orientations_, skill3.orientations_)
    goal_q = exp(np.array([0.1, 0.2, -0.3]))
    for kwargs in ({}, {"goal": [80.0, 5.0, 25.0], "goal_orientation": goal_q}):
        a, b = skill3.plan(**kwargs), loaded.plan(**kwargs)
        np.testing.assert_array_equal(a.points, b.points)
        np.testing.assert_array_equal(a.orientations, b.orientations)
    # Saving the loaded skill writes the same bytes.
    again = loaded.save(tmp_path / "again.json")
    assert again.read_bytes() == path.read_bytes()
    # Units: the orientation does not change with them.
    in_mm = loaded.to_units("mm")
    np.testing.assert_array_equal(in_mm.orientations_, skill3.orientations_)
    assert angle_between(in_mm.plan().orientations, skill3.plan().orientations).max() < 1e-6


def test_a_file_without_the_orientation_field_loads_without_orientation(skill3) -> None:
    document = skill3.to_dict()
    assert len(document["orientation"]["mean"]) == skill3.n_points
    del document["orientation"]
    skill = Skill.from_dict(json.loads(json.dumps(document)))
    assert skill.orientation_dmp_ is None and skill.plan().orientations is None


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d["orientation"].update(mean=d["orientation"]["mean"][:-1]), "orientation.mean"),
        (lambda d: d.update(orientation=[1, 2]), "orientation: expected an object"),
        (lambda d: d["orientation"]["mean"][3].__setitem__(0, 5.0), "orientations: row 3 has norm"),
        (lambda d: d["orientation"].pop("mean"), "orientation.mean: missing field"),
    ],
)
def test_broken_orientation_fields_are_named(skill3, edit, message) -> None:
    document = json.loads(json.dumps(skill3.to_dict()))
    edit(document)
    with pytest.raises(ValueError, match=f"^f.json: .*{message}"):
        Skill.from_dict(document, source="f.json")


# ------------------------------------------------------------------ 2-D, yaw
def test_a_2d_skill_learns_a_yaw_that_is_not_the_tangent(skill2) -> None:
    plan = skill2.plan()
    yaw = yaw_from_quaternions(plan.orientations)
    want = YAW0 + YAW_TURN * np.clip(plan.points[:, 0] / 0.4, 0, 1)
    assert np.degrees(np.abs(yaw - want)).max() < 3.0
    # The tangent is far from it: following one is not following the other.
    assert np.degrees(np.abs(path_yaw(plan.points) - yaw)).max() > 20.0
    # A pure yaw: the tool stays level (no roll or pitch), as demonstrated.
    assert np.abs(plan.orientations[:, :2]).max() < 1e-3


@pytest.mark.filterwarnings("error::RuntimeWarning")
def test_to_units_keeps_a_learned_timing() -> None:
    """A skill converted to other units runs as long, with the same speed law, as the original."""
    demos, quats = demonstrations(3, 100.0, seed=6)
    times = [3.0 * np.linspace(0.0, 1.0, len(d)) ** 1.5 for d in demos]
    skill = Skill(units="cm").fit(demos, times=times, orientations=quats)
    assert skill.timing_.source == "demonstrations"
    metres = skill.to_units("m")
    assert metres.timing_ == skill.timing_
    a, b = skill.plan(), metres.plan()
    np.testing.assert_allclose(b.times, a.times, rtol=1e-9, atol=1e-12)
    assert angle_between(a.orientations, b.orientations).max() < 1e-6
    # A timing that starts and ends slowly does not magnify the mean's roughness there.
    assert np.degrees(angle_between(a.orientations, skill.orientations_)).max() < 1.0
