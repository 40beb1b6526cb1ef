"""Via-points with an orientation: ``Skill.plan(via=[(phase, point, [x, y, z, w])])``.

Known answers on the orientation skill of ``tests/skill/test_orientation.py``
(3-D, centimetres, a turning yaw and a rising pitch): the orientation at the
via-point's phase is the one given (to 1e-6 rad; it is set to the bit), the
start and goal orientations are unchanged, the movement stays unit and
continuous, a via-orientation equal to the unbent one changes nothing, and
the plan has the orientation given where it passes the via-point (timed by
its own length, a little off the phase asked).
Bad orientations and an orientation for a skill without one are one line.
"""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.core.rotations import angle_between, exp, multiply, slerp
from lfdkit.skill import Skill
from tests.skill.test_orientation import demonstrations
from tests.skill.test_via import sweeps

U = np.linspace(0.0, 1.0, 801)


@pytest.fixture(scope="module")
def skill() -> Skill:
    demos, quats = demonstrations(3, 100.0, seed=4)
    return Skill(units="cm", mimic="average", n_points=60).fit_path(demos, orientations=quats)


def turned(skill: Skill, phase: float, rotvec) -> np.ndarray:
    """The unbent orientation at ``phase`` turned by ``exp(rotvec)`` (half-angle vector)."""
    return multiply(exp(np.asarray(rotvec, dtype=float)), skill.orientations_at([phase])[0])


@pytest.mark.parametrize(
    ("phase", "rotvec"), [(0.4, (0.3, -0.2, 0.25)), (0.73, (0.0, 0.0, -0.6)), (0.2, (1.0, 0, 0))]
)
def test_the_orientation_at_the_via_phase_is_the_one_given(skill, phase, rotvec) -> None:
    target = turned(skill, phase, rotvec)
    via = [(phase, skill.path_[20], target)]
    got = skill.orientations_at(np.r_[U, phase], via=via)
    assert angle_between(got[-1], target) <= 1e-6
    # Start and goal orientations kept exactly; unit; no jump (the unbent steps 0.4 mrad).
    assert angle_between(got[0], skill.orientations_[0]) <= 1e-12
    assert angle_between(got[-2], skill.orientations_[-1]) <= 1e-12
    np.testing.assert_allclose(np.linalg.norm(got, axis=1), 1.0, atol=1e-12)
    assert angle_between(got[1:-1], got[:-2]).max() < 0.02
    # Away from the via-point (beyond the basis's reach) the movement is as before.
    far = np.abs(U - phase) > 0.35
    assert angle_between(got[:-1][far], skill.orientations_at(U[far])).max() < 0.1 * np.linalg.norm(
        rotvec
    )


def test_several_via_orientations_at_once(skill) -> None:
    via = [
        (0.3, skill.path_[18], turned(skill, 0.3, (0.2, 0.1, 0))),
        (0.7, skill.path_[42], turned(skill, 0.7, (0, -0.3, 0.2))),
        (0.5, skill.path_[30]),  # a via-point without orientation leaves it alone
    ]
    got = skill.orientations_at([0.3, 0.7], via=via)
    assert angle_between(got[0], via[0][2]) <= 1e-6
    assert angle_between(got[1], via[1][2]) <= 1e-6


def test_the_unbent_orientation_as_via_changes_nothing(skill) -> None:
    via = [(0.45, skill.path_[27], skill.orientations_at([0.45])[0])]
    np.testing.assert_allclose(
        skill.orientations_at(U, via=via), skill.orientations_at(U), atol=1e-12
    )


def test_the_plan_has_the_via_orientation_where_it_passes_the_point(skill) -> None:
    target = turned(skill, 0.3, (0.2, 0.3, -0.1))
    nominal = skill.via_path().points  # equal time steps
    point = nominal[round(0.3 * (len(nominal) - 1))] + (0.0, 4.0, 0.0)
    plan = skill.plan(via=[(0.3, point, target)])
    phases = plan.times / plan.times[-1]
    # Timed by its own length, the plan passes the point a little after 0.3 of its time: the
    # orientation is turned to be the one given there (where the tool is at the point).
    t = np.linspace(0.0, plan.times[-1], 40001)
    dense = np.column_stack([np.interp(t, plan.times, plan.points[:, k]) for k in range(3)])
    passing = t[np.argmin(np.linalg.norm(dense - point, axis=1))] / plan.times[-1]
    assert 0.305 < passing < 0.33
    moved = [(passing, point, target)]
    # (The passing phase found to 1/40000 here: the orientations agree to that.)
    np.testing.assert_allclose(
        plan.orientations, skill.orientations_at(phases, via=moved), atol=2e-4
    )
    assert angle_between(skill.orientations_at([passing], via=moved)[0], target) <= 1e-6
    # Read off the plan's own samples (slerp between them) as the tool passes: 1 mrad.
    j = int(np.searchsorted(phases, passing)) - 1
    w = (passing - phases[j]) / (phases[j + 1] - phases[j])
    assert angle_between(slerp(plan.orientations[j], plan.orientations[j + 1], w), target) < 1e-3
    assert angle_between(plan.orientations[0], skill.orientations_[0]) <= 1e-12
    assert angle_between(plan.orientations[-1], skill.orientations_[-1]) <= 1e-12


@pytest.mark.parametrize(
    ("turn", "message"),
    [
        ([0, 0, 1], r"^via\[0\]: orientation: has 3 values; give a unit quaternion"),
        ([0, 0, 1.2, 0], r"^via\[0\]: orientation: has norm 1.2; a unit quaternion's norm is 1"),
        ([0, 0, np.nan, 1], r"^via\[0\]: orientation"),
    ],
)
def test_bad_via_orientations_are_one_line(skill, turn, message) -> None:
    with pytest.raises(ValueError, match=message) as caught:
        skill.plan(via=[(0.5, skill.path_[30], turn)])
    assert "\n" not in str(caught.value)


def test_an_orientation_for_a_skill_without_one_is_refused() -> None:
    plain = Skill(mimic="average").fit_path(sweeps())
    with pytest.raises(ValueError, match=r"^via\[0\]: orientation: this skill has no orientation"):
        plain.plan(via=[(0.5, (0.0, 0.6), (0, 0, 0, 1))])
