"""Via-points: a path bent through given points the way the demonstrations varied.

Known answers: the result's via samples *are* the via-points and its ends the
path's (to the bit); demonstrations that differ only in one shape give that
shape through the via-point; the band is pinched at the ends and via-points;
the ProMP's state reads back to the bit.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lfdkit.core.rotations import conjugate, exp, log, multiply
from lfdkit.imitate import ProMP
from lfdkit.imitate.via_points import (
    check_via,
    check_via_orientations,
    orientations_through_via,
    through_via_points,
)

S = np.linspace(0.0, 1.0, 81)


def arcs(amplitudes, scale: float = 1.0) -> list[np.ndarray]:
    """Demonstrations that differ only by the height of one arch, ``a·sin(πs)``."""
    return [scale * np.c_[S, a * np.sin(np.pi * S)] for a in amplitudes]


@pytest.fixture(scope="module")
def arch_model() -> ProMP:
    return ProMP(n_basis=15).fit(arcs([0.2, 0.25, 0.3, 0.35, 0.4]))


@settings(max_examples=25, deadline=None)
@given(
    phases=st.lists(st.floats(0.05, 0.95), min_size=1, max_size=3, unique=True),
    offsets=st.lists(st.floats(-0.3, 0.3), min_size=6, max_size=6),
    scale=st.sampled_from([1e-3, 1.0, 1e3]),
)
def test_via_points_are_passed_to_the_bit_and_the_ends_stay(phases, offsets, scale) -> None:
    phases = np.sort(phases)
    if np.any(np.diff(phases) < 0.1):  # closer than the basis resolves: a tested warning
        phases = np.linspace(0.2, 0.8, len(phases))
    path = scale * np.c_[S, 0.3 * np.sin(np.pi * S)]
    points = np.column_stack([np.interp(phases, S, path[:, k]) for k in range(2)])
    points = points + scale * np.reshape(offsets[: 2 * len(phases)], (-1, 2))
    model = ProMP(n_basis=15).fit(arcs([0.2, 0.3, 0.4], scale))
    for promp in (model, None):
        bent = through_via_points(path, S, phases, points, promp)
        assert bent.points.shape == (len(S) + len(phases), 2)
        np.testing.assert_array_equal(bent.points[0], path[0])
        np.testing.assert_array_equal(bent.points[-1], path[-1])
        np.testing.assert_array_equal(bent.miss, 0.0)
        at = [int(np.flatnonzero(bent.phases == p)[-1]) for p in phases]  # the inserted one
        np.testing.assert_array_equal(bent.points[at], points)
        assert np.all(np.diff(bent.phases) >= 0.0)


def test_a_via_point_on_a_demonstrated_shape_gives_that_shape(arch_model) -> None:
    # The demonstrations vary only by the arch's height: asking for a higher top
    # lifts the whole arch, not a spike at the via-point.
    path = np.c_[S, 0.3 * np.sin(np.pi * S)]
    bent = through_via_points(path, S, np.array([0.5]), np.array([[0.5, 0.38]]), arch_model)
    wanted = np.c_[bent.phases, 0.38 * np.sin(np.pi * bent.phases)]
    # Within 6 % of the 8 cm asked for (measured 4.7 %: the isotropic part, ISOTROPIC_SHARE).
    assert np.abs(bent.points - wanted).max() < 0.06 * 0.08
    # With no ProMP the bend is local: a smooth bump, the quarter points barely moved.
    smooth = through_via_points(path, S, np.array([0.5]), np.array([[0.5, 0.38]]))
    quarter = np.flatnonzero(np.isclose(smooth.phases, 0.25))[0]
    assert abs(smooth.points[quarter, 1] - path[20, 1]) < 0.25 * abs(
        bent.points[quarter, 1] - path[20, 1]
    )


def test_the_band_is_pinched_at_the_ends_and_via_points(arch_model) -> None:
    path = np.c_[S, 0.3 * np.sin(np.pi * S)]
    free = through_via_points(path, S, np.zeros(0), np.zeros((0, 2)), arch_model)
    bent = through_via_points(path, S, np.array([0.5]), np.array([[0.5, 0.3]]), arch_model)
    np.testing.assert_array_equal(free.points, path)  # no via-point: the path itself
    free_std, bent_std = free.std(), bent.std()
    top = np.flatnonzero(bent.phases == 0.5)[0]
    # The demonstrations' spread at the top: heights 0.2 to 0.4, sample std 0.079.
    assert free_std[40, 1] == pytest.approx(np.std([0.2, 0.25, 0.3, 0.35, 0.4], ddof=1), rel=0.02)
    assert bent_std[top].max() < 1e-6 and free_std[[0, -1]].max() < 1e-6
    assert bent_std[:, 1].max() < 0.2 * free_std[:, 1].max()  # one height: little left


def test_via_points_closer_than_the_basis_resolves_are_warned_of(arch_model) -> None:
    path = np.c_[S, 0.3 * np.sin(np.pi * S)]
    with pytest.warns(UserWarning, match=r"points\[\d\]: cannot be reached; .* misses it by"):
        bent = through_via_points(
            path, S, np.array([0.5, 0.5]), np.array([[0.5, 0.2], [0.5, 0.4]]), arch_model
        )
    assert bent.miss.max() > 0.05


@pytest.mark.parametrize(
    ("via", "message"),
    [
        ([(1.2, (0.0, 0.0))], r"via\[0\]: phase 1.2 is outside \(0, 1\); give the fraction"),
        ([(0.0, (0.0, 0.0))], r"via\[0\]: phase 0 is outside \(0, 1\)"),
        ([(0.5, (0.0, 0.0)), (0.5, (0, 0, 0))], r"via\[1\]: point has 3 coordinates; .* 2-D"),
        ([0.5], r"via\[0\]: expected a \(phase, point\) pair"),
        ([], r"via: expected a list of \(phase, point\) pairs"),
        ("0.5", r"via: expected a list"),
        ([(True, (0.0, 0.0))], r"via\[0\]: phase: expected a number"),
        ([(0.5, (0.0, np.nan))], r"via\[0\]: point"),
    ],
)
def test_bad_via_points_are_one_line(via, message) -> None:
    with pytest.raises((ValueError, TypeError), match=message) as caught:
        check_via(via, 2)
    assert "\n" not in str(caught.value)


def test_promp_state_reads_back_to_the_bit_and_scales(arch_model) -> None:
    back = ProMP.from_state(arch_model.to_state())
    np.testing.assert_array_equal(back.weights_cov_, arch_model.weights_cov_)
    np.testing.assert_array_equal(back.mean_path(30), arch_model.mean_path(30))
    mm = arch_model.scaled(1000.0)
    np.testing.assert_allclose(mm.mean_path(30), 1000.0 * arch_model.mean_path(30), rtol=1e-12)
    np.testing.assert_allclose(mm.std(30), 1000.0 * arch_model.std(30), rtol=1e-9, atol=1e-12)
    state = arch_model.to_state()
    with pytest.raises(ValueError, match=r"promp: weights of shape \(30,\) and \(29, 29\)"):
        ProMP.from_state({**state, "weights_cov": state["weights_cov"][1:, 1:]})
    with pytest.raises(ValueError, match=r"promp.width: missing field"):
        ProMP.from_state({k: v for k, v in state.items() if k != "width"})


@settings(max_examples=25, deadline=None)
@given(
    phase=st.floats(0.1, 0.9),
    axis=st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3).filter(
        lambda v: np.linalg.norm(v) > 0.1
    ),
    angle=st.floats(0.05, 1.4),
)
def test_a_turn_from_rest_stays_about_its_axis_and_is_met_exactly(phase, axis, angle) -> None:
    # Known answer: from a constant orientation, the only turn asked is about one axis, so
    # every sample is a rotation about that axis (the isotropic field has no other part),
    # 0 at both ends and the asked one at the via-point's phase.
    rest = np.array([0.1, -0.2, 0.3, 0.9])
    rest /= np.linalg.norm(rest)
    u = np.linspace(0.0, 1.0, 201)
    direction = np.asarray(axis) / np.linalg.norm(axis)
    target = multiply(exp(0.5 * angle * direction), rest)
    got = orientations_through_via(
        np.r_[u, phase], np.tile(rest, (202, 1)), np.array([phase]), target[None], rest[None]
    )
    turn = log(multiply(got, conjugate(rest)))  # half-angle vectors
    np.testing.assert_allclose(np.cross(turn, direction), 0.0, atol=1e-12)
    assert np.allclose(got[-1], target, atol=1e-15) or np.allclose(got[-1], -target, atol=1e-15)
    np.testing.assert_array_equal(got[[0, 200]], np.tile(rest, (2, 1)))
    # The largest turn is at (about) the via-point: the one asked, or up to 14 % more where
    # the via-point is within 0.1 of an end (the basis must rise from 0 that quickly).
    assert abs(u[np.argmax(np.linalg.norm(turn[:-1], axis=1))] - phase) <= 0.06
    assert np.linalg.norm(turn[:-1], axis=1).max() <= 0.5 * angle * 1.15


@pytest.mark.parametrize(
    ("turn", "message"),
    [
        ((0, 0, 1), r"via\[0\]: orientation: has 3 values"),
        ((0, 0, 0.5, 0.5), r"via\[0\]: orientation: has norm 0.707107"),
        ((0, 0, 1, np.inf), r"via\[0\]: orientation"),
    ],
)
def test_bad_via_orientations_name_the_entry(turn, message) -> None:
    with pytest.raises(ValueError, match=message):
        check_via_orientations([(0.5, (0, 0), turn)])
    phases, turns = check_via_orientations([(0.5, (0, 0)), (0.6, (0, 0), (0, 0, 0, 1.0005))])
    assert phases.tolist() == [0.6] and np.allclose(turns, [[0, 0, 0, 1]])
