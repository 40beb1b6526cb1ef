"""Skill.plan(via=...): plans through via-points, the skill's ProMP in files and units.

Known answers: the bent nominal holds each via-point as a sample (to the bit);
the plan passes it within a small share of the path; without via-points the
plan is unchanged; the skill file reads back to the byte and plans the same;
the same skill in millimetres plans 1000 times the metres' plan.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from lfdkit.core.geometry import polyline_distances
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import VIA_TOLERANCE, Skill

S = np.linspace(0.0, 1.0, 60)
#: Sweeps from (-0.4, 0.45) to (0.4, 0.45) over arches of different heights (metres).
HEIGHTS = (0.05, 0.08, 0.1, 0.12, 0.15)
VIA = [(0.5, [0.0, 0.62])]


def sweeps(heights=HEIGHTS, scale: float = 1.0) -> list[np.ndarray]:
    return [scale * np.c_[0.8 * S - 0.4, 0.45 + h * np.sin(np.pi * S)] for h in heights]


@pytest.fixture(scope="module")
def skill() -> Skill:
    return Skill(mimic="average").fit_path(sweeps())  # the cheapest mean: the ProMP is the point


def test_the_skill_learns_the_demonstrations_promp(skill) -> None:
    assert skill.promp_.n_demos_ == len(HEIGHTS)
    # The spread at the top is that of the heights.
    top = skill.promp_.std(61)[30, 1]
    assert top == pytest.approx(np.std(HEIGHTS, ddof=1), rel=0.02)


def test_the_plan_passes_the_via_points(skill) -> None:
    bent = skill.via_path(VIA)
    assert bent.miss[0] == 0.0 and np.all(bent.points == VIA[0][1], axis=1).sum() == 1
    plan = skill.plan(via=VIA)
    extent = np.ptp(plan.points, axis=0).max()
    miss = polyline_distances(np.array([VIA[0][1]]), plan.points)[0]
    assert miss < 1e-3 * extent  # the planner's resampling cuts it by a hair
    np.testing.assert_allclose(plan.points[[0, -1]], skill.path_[[0, -1]], atol=1e-12)
    # Near its phase in time too: the via-point is passed about half-way through.
    k = int(np.argmin(np.linalg.norm(plan.points - VIA[0][1], axis=1)))
    assert plan.times[k] / plan.duration == pytest.approx(0.5, abs=0.03)
    # The whole arch is lifted, as the demonstrations vary (not a spike at the top).
    plain = skill.plan()
    lift = plan.points[:, 1] - np.interp(plan.points[:, 0], plain.points[:, 0], plain.points[:, 1])
    quarter = int(np.argmin(np.abs(plan.points[:, 0] + 0.2)))
    assert lift[quarter] > 0.5 * lift.max()


def test_several_via_points_and_a_new_goal(skill) -> None:
    via = [(0.3, [-0.1, 0.55]), (0.7, [0.25, 0.5])]
    plan = skill.plan(goal=[0.5, 0.4], via=via)
    miss = polyline_distances(np.array([p for _, p in via]), plan.points)
    assert miss.max() < 1e-3 * np.ptp(plan.points, axis=0).max()
    np.testing.assert_allclose(plan.points[-1], [0.5, 0.4], atol=1e-9)


def test_without_via_points_the_plan_is_unchanged(skill) -> None:
    # The ProMP is only consulted for via-points: the plan is the DMP's as before.
    plain = Skill().use_path(skill.path_, timing=skill.timing_)
    np.testing.assert_array_equal(skill.plan().points, plain.plan().points)


def test_the_skill_file_keeps_the_promp_to_the_byte(skill, tmp_path: Path) -> None:
    first = skill.save(tmp_path / "a.json")
    loaded = Skill.load(first)
    second = loaded.save(tmp_path / "b.json")
    assert first.read_bytes() == second.read_bytes()
    np.testing.assert_array_equal(loaded.promp_.weights_cov_, skill.promp_.weights_cov_)
    np.testing.assert_array_equal(loaded.plan(via=VIA).points, skill.plan(via=VIA).points)


def test_a_file_without_the_promp_still_bends_exactly(skill, tmp_path: Path) -> None:
    document = skill.to_dict()
    del document["promp"]  # as written before issue 33
    path = tmp_path / "old.json"
    path.write_text(json.dumps(document))
    old = Skill.load(path)
    assert old.promp_ is None
    bent = old.via_path(VIA)
    assert bent.miss[0] == 0.0 and np.all(bent.points == VIA[0][1], axis=1).sum() == 1
    np.testing.assert_array_equal(old.plan().points, skill.plan().points)


def test_a_broken_promp_in_a_file_names_the_field(skill, tmp_path: Path) -> None:
    document = skill.to_dict()
    document["promp"]["n_dims"] = 3
    path = tmp_path / "broken.json"
    path.write_text(json.dumps(document))
    with pytest.raises(ValueError, match=r"broken.json: promp: weights of shape"):
        Skill.load(path)
    document["promp"]["n_dims"] = 2
    document["promp"]["weights_mean"] = {}  # not a list: NumPy's own TypeError before
    path.write_text(json.dumps(document))
    with pytest.raises(ValueError, match=r"broken.json: promp: weights_mean and weights_cov must"):
        Skill.load(path)


def test_millimetres_plan_the_same_via_points(skill) -> None:
    mm = skill.to_units("mm")
    via_mm = [(0.5, [0.0, 620.0])]
    np.testing.assert_allclose(
        mm.plan(via=via_mm).points, 1000.0 * skill.plan(via=VIA).points, rtol=0, atol=1e-6
    )
    learned_mm = Skill(mimic="average", units="mm").fit_path(sweeps(scale=1000.0))
    cov = skill.promp_.weights_cov_
    np.testing.assert_allclose(
        learned_mm.promp_.weights_cov_, 1e6 * cov, rtol=0, atol=1e-9 * 1e6 * np.abs(cov).max()
    )


@pytest.mark.parametrize(
    ("via", "message"),
    [
        ([(1.5, [0.0, 0.6])], r"^via\[0\]: phase 1.5 is outside \(0, 1\)"),
        ([(0.5, [0.0, 0.6, 0.1])], r"^via\[0\]: point has 3 coordinates; this skill is 2-D"),
        ([(0.5,)], r"^via\[0\]: expected a \(phase, point\) pair"),
    ],
)
def test_bad_via_points_are_refused_in_one_line(skill, via, message) -> None:
    with pytest.raises(ValueError, match=message) as caught:
        skill.plan(via=via)
    assert "\n" not in str(caught.value)


def test_a_via_point_an_obstacle_keeps_away_is_warned_of(skill) -> None:
    # The via-point lies inside an obstacle: the plan keeps out, and says it missed.
    scene = Scene((Obstacle("box", [0.0, 0.62], 0.05),))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        plan = skill.plan(scene=scene, via=VIA, unknown_class=0.0, planner="full")
    missed = [w for w in caught if "via[0]: the plan passes" in str(w.message)]
    assert len(missed) == 1, [str(w.message) for w in caught]
    miss = polyline_distances(np.array([VIA[0][1]]), plan.points)[0]
    assert miss >= 0.05 - 1e-9 and miss > VIA_TOLERANCE * np.ptp(plan.points, axis=0).max()
